"""One base exception per layer: every error class defined in navcore, hw, behaviors and executive
derives from its layer's base (NavcoreError, HwError, BehaviorError, ExecutiveError), and keeps
its other base, so ``except ValueError`` and ``except <layer base>`` both catch it."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import numpy as np
import pytest

import executive
from behaviors.errors import BehaviorError
from executive.errors import ExecutiveError
from hw.errors import HwError
from navcore.errors import NavcoreError

LAYERS = {"navcore": NavcoreError, "hw": HwError, "behaviors": BehaviorError,
          "executive": ExecutiveError}


def errors_defined_in(layer: str) -> dict[str, type]:
    """Every Exception subclass defined (not imported) in a module of ``layer``, by its
    qualified name; importing a module that fails is a failure, not a skip."""
    found = {}
    package = importlib.import_module(layer)
    for info in pkgutil.walk_packages(package.__path__, layer + "."):
        module = importlib.import_module(info.name)
        for name, obj in vars(module).items():
            if (inspect.isclass(obj) and issubclass(obj, Exception)
                    and obj.__module__ == module.__name__):
                found[f"{module.__name__}.{name}"] = obj
    return found


@pytest.mark.parametrize("layer", list(LAYERS))
def test_every_error_class_of_a_layer_derives_from_its_base(layer):
    base = LAYERS[layer]
    found = errors_defined_in(layer)
    found.pop(f"{base.__module__}.{base.__name__}")      # the base itself
    stray = sorted(name for name, cls in found.items() if not issubclass(cls, base))
    assert stray == [], f"not derived from {base.__name__}: {stray}"
    # the walk does reach the layer's errors (a walk that found nothing would pass vacuously)
    known = {"navcore": {"navcore.maps.MapError", "navcore.params.ParameterError",
                         "navcore.route.graph.RouteError", "navcore.safe_read.ReadError"},
             "hw": {"hw.devices.DeviceConfigError", "hw.drivers.kobuki_codec.KobukiError",
                    "hw.emulators.link.Unplugged", "hw.sim.world.WorldError",
                    "hw.drivers.serial_link.HandshakeError"},
             "behaviors": {"behaviors.base.ComponentError",
                           "behaviors.btcpp.scripting.ScriptError"},
             "executive": {"executive.tree_spec.TreeLoadError", "executive.config.ConfigError",
                           "executive.errors.WiringError", "executive.param_files.ParamsError",
                           "executive.scenarios.source.ScenarioError",
                           "executive.sweeps.spec.SweepError"}}[layer]
    assert known <= set(found)


def test_no_layer_base_derives_from_another_layer_s():
    # one type per layer: catching hw's errors does not also catch navcore's
    for a in LAYERS.values():
        for b in LAYERS.values():
            assert issubclass(a, b) == (a is b)


def test_the_error_classes_keep_their_other_base():
    from executive.tree_spec import TreeLoadError
    from hw.emulators.link import Unplugged
    from hw.drivers.serial_link import HandshakeError
    from navcore.maps import MapError
    assert issubclass(TreeLoadError, ValueError) and issubclass(MapError, ValueError)
    assert issubclass(Unplugged, OSError) and issubclass(HandshakeError, RuntimeError)


def test_one_except_per_layer_catches_real_errors():
    from behaviors.btcpp.scripting import compile_script
    from hw.drivers.kobuki_codec import frame
    from hw.sim.faults import fault_from_mapping
    from navcore.maps import OccupancyGrid
    from navcore.params import Param

    with pytest.raises(NavcoreError, match="resolution must be > 0"):
        OccupancyGrid(np.zeros((2, 2), dtype=np.int8), resolution=0.0)
    with pytest.raises(NavcoreError, match="parameter 'hz' must be a number"):
        Param("hz", 1.0, float, "rate", min=0.0).check("fast")
    with pytest.raises(HwError, match="payload of 0 bytes"):
        frame(b"")
    with pytest.raises(HwError, match="unknown key 'kindd'"):
        fault_from_mapping({"kindd": "laser_dropout", "start": 1.0})
    with pytest.raises(BehaviorError, match="column 1: empty script"):
        compile_script(";", lambda key: key)
    with pytest.raises(ExecutiveError, match=r"<mine>:4: .*NoSuchNode"):
        executive.parse_tree("main_tree: T\ntrees:\n  T:\n    NoSuchNode: {}\n", name="<mine>")
    # and the same errors still are ValueErrors
    with pytest.raises(ValueError):
        executive.parse_tree("main_tree: T\ntrees:\n  T:\n    NoSuchNode: {}\n")


def test_executive_exports_its_base():
    assert executive.ExecutiveError is ExecutiveError
    assert issubclass(executive.TreeLoadError, executive.ExecutiveError)
    assert issubclass(executive.ConfigError, executive.ExecutiveError)
    assert issubclass(executive.WiringError, executive.ExecutiveError)
