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


def test_attribute_reads_follow_every_set_and_assignment() -> None:
    p = Parameters(SPECS, {"vx_samples": 7})
    p.max_vel_x = 0.25
    p.set({"orientation_mode": "Forward", "use_dijkstra": False})
    with pytest.raises(ParameterError):
        p.set({"vx_samples": 9, "max_vel_x": -2.0})  # refused whole: nothing changes
    with pytest.raises(ParameterError):
        p.vx_samples = 0
    assert {n: getattr(p, n) for n in p.as_dict()} == p.as_dict() == {
        "max_vel_x": 0.25, "vx_samples": 7, "use_dijkstra": False, "orientation_mode": "Forward"}
    with pytest.raises(AttributeError, match="no parameter 'max_vel'"):
        _ = p.max_vel


def test_a_parameter_named_like_a_method_leaves_the_method_alone() -> None:
    p = Parameters((Param("specs", 1, int),), {"specs": 2})
    assert callable(p.specs) and p.as_dict() == {"specs": 2}


def test_nan_is_refused_by_name() -> None:
    p = Parameters(SPECS)
    with pytest.raises(ParameterError, match="'max_vel_x' must be a number, got NaN"):
        p.set({"max_vel_x": float("nan")})
    assert p.max_vel_x == 0.55


def test_before_change_sees_accepted_changes_before_they_apply() -> None:
    p = Parameters(SPECS)
    seen = []
    p.before_change(lambda values: seen.append((dict(values), p.max_vel_x)))
    p.max_vel_x = 0.3
    with pytest.raises(ParameterError):
        p.set({"vx_samples": 0})
    assert seen == [({"max_vel_x": 0.3}, 0.55)]


def test_a_weak_method_hook_does_not_keep_its_object_alive() -> None:
    # The owner of the parameters registers its own method: held strongly that is a cycle, and
    # the owner (a costmap with its grids) outlived every use until the next garbage collection.
    import gc
    import weakref

    class Owner:
        def __init__(self) -> None:
            self.params = Parameters(SPECS)
            self.params.before_change(self.seen, weak=True)
            self.calls = 0

        def seen(self, values) -> None:
            self.calls += 1

    owner = Owner()
    owner.params.max_vel_x = 0.3
    assert owner.calls == 1
    params, ref = owner.params, weakref.ref(owner)
    gc.disable()
    try:
        del owner
        assert ref() is None  # freed by reference counting alone
    finally:
        gc.enable()
    params.max_vel_x = 0.2  # a dead owner's hook is skipped
    assert params.max_vel_x == 0.2
