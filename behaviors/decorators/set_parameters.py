"""Dynamic reconfigure from the tree: SetParameters (the tuning guide's section 7 idea, e.g. a
lower ``path_distance_bias`` near the goal)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, DecoratorNode, PortInformation, Status, Ticking
from navcore.params import ParameterError
from navcore.safe_read import parse_yaml


def parse_values(text: str) -> dict[str, Any]:
    """``"a: 1.0; b: true"`` (the XML form) -> ``{"a": 1.0, "b": True}``; values are YAML scalars."""
    out: dict[str, Any] = {}
    for item in filter(None, (part.strip() for part in text.split(";"))):
        name, sep, value = item.partition(":") if ":" in item else item.partition("=")
        if not sep or not name.strip():
            raise ValueError(f"'{item}' is not 'name: value'")
        out[name.strip()] = parse_yaml(value.strip(), f"value of '{name.strip()}'")
    return out


class SetParameters(DecoratorNode):
    """Set ``values`` on the component parameters of ``namespace`` while the child runs.

    On the first tick of a run the values are applied (all or nothing) and the previous values
    kept; the child is then ticked and its status returned. When the node ends (finished or
    halted) the previous values are restored. When the namespace is unknown or a value is
    rejected, ``error_msg`` says which and the node FAILs without ticking the child, unless
    ``required`` is false: then the child runs with the parameters unchanged.
    """

    INPUT_PORTS = {
        "namespace": PortInformation(str, True, "ROS namespace, e.g. DWAPlannerROS"),
        "values": PortInformation(dict, True, "parameter name -> value"),
        "required": PortInformation(bool, False, "fail when the change is rejected", True),
    }
    OUTPUT_PORTS = {"error_msg": PortInformation(str, False, "why the change was rejected")}
    DEFAULT_KEYS = {"error_msg": "set_parameters_error_msg"}

    def setup(self, **kwargs: Any) -> None:
        self.parameters = self.component(kwargs, "parameters")
        self._restore: tuple[Any, dict[str, Any]] | None = None

    def _apply(self) -> str:
        ns = self.get_input("namespace")
        target = self.parameters.get(ns)
        if target is None:
            known = ", ".join(sorted(self.parameters)) or "none"
            return f"no parameter namespace '{ns}' (known: {known})"
        try:
            previous = target.set(self.get_input("values"))
        except ParameterError as e:
            return str(e)
        self._restore = (target, previous)
        self.say(f"{ns}: set {self.get_input('values')}")
        return ""

    def tick(self) -> Ticking:
        if self.begin_tick():
            self._put_back()
            problem = self._apply()
            if problem:
                self.write("error_msg", problem)
                self.say(problem)
                if self.get_input("required"):
                    yield self.finish(FAILURE)
                    return
        yield from self.decorated.tick()
        yield self.finish(self.decorated.status)

    def _put_back(self) -> None:
        if self._restore is not None:
            target, previous = self._restore
            target.set(previous)
            self._restore = None

    def terminate(self, new_status: Status) -> None:
        self._put_back()
