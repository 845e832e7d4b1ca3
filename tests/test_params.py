"""Typed, ranged parameters: errors name the parameter; set returns what it replaced."""

import pytest

from navcore.params import Param, ParameterError, Parameters

SPECS = (Param("max_vel_x", 0.55, float, "m/s", min=0.0),
         Param("vx_samples", 3, int, "", min=1),
         Param("use_dijkstra", True, bool),
         Param("orientation_mode", "None", str, choices=("None", "Forward")))


def test_defaults_and_conversion() -> None:
    p = Parameters(SPECS, {"max_vel_x": 1, "vx_samples": 20.0})
    assert p.max_vel_x == 1.0 and isinstance(p.max_vel_x, float)
    assert p.vx_samples == 20 and p.use_dijkstra is True


def test_set_returns_previous_and_is_all_or_nothing() -> None:
    p = Parameters(SPECS)
    assert p.set({"max_vel_x": 0.3}) == {"max_vel_x": 0.55}
    with pytest.raises(ParameterError):
        p.set({"max_vel_x": 0.9, "vx_samples": 0})
    assert p.max_vel_x == 0.3


@pytest.mark.parametrize("values,needle", [
    ({"max_vel_xx": 1.0}, "unknown parameter 'max_vel_xx' (did you mean 'max_vel_x'?)"),
    ({"max_vel_x": -1.0}, "'max_vel_x' = -1.0 is below its minimum 0.0"),
    ({"use_dijkstra": 1}, "'use_dijkstra' must be true or false"),
    ({"vx_samples": 2.5}, "'vx_samples' must be an integer"),
    ({"orientation_mode": "Sideways"}, "is not one of"),
])
def test_errors_name_the_parameter(values: dict, needle: str) -> None:
    with pytest.raises(ParameterError) as e:
        Parameters(SPECS, values, where="DWAPlannerROS")
    assert needle in str(e.value) and str(e.value).startswith("DWAPlannerROS: ")
