"""Robot profiles: one file describing a robot that many scenarios name, and the merged config.

A profile (``robot_profile: NAME`` marks the file) gives the footprint, the drive, the speed and
acceleration limits, the laser and any other namespaces. Its limits go to every place that has
one: the simulated body (``sim``), the safety gate (``safety``) and the local planners
(``DWAPlannerROS``, ``TrajectoryPlannerROS``), so a limit is written once. The config of a run is
the base robot config, the profile over it, then the scenario's ``robot``/``params`` over that;
every layer merges deeply (a mapping changes only the keys it names).
"""

from __future__ import annotations

import copy
import os
from pathlib import Path as FsPath
from typing import Any, Mapping

from navcore.params import suggest

from executive.scenarios.source import ScenarioError, Source, read_source

SHIPPED = FsPath(__file__).resolve().parent.parent / "data" / "robots"
PROFILE_KEYS = ("robot_profile", "description", "footprint", "robot_radius", "drive", "limits",
                "laser", "params")
LIMIT_KEYS = ("max_vel_x", "min_vel_x", "max_vel_y", "max_vel_theta", "acc_lim_x", "acc_lim_y",
              "acc_lim_theta")
# where each limit goes besides the simulated body (which takes the fastest of either way)
_PLANNER_LIMITS = {
    "DWAPlannerROS": ("max_vel_x", "max_vel_y", "max_vel_theta", "acc_lim_x", "acc_lim_y",
                      "acc_lim_theta"),
    "TrajectoryPlannerROS": ("max_vel_x", "max_vel_theta", "acc_lim_x", "acc_lim_y",
                             "acc_lim_theta"),
}
_SAFETY_LIMITS = ("max_vel_x", "min_vel_x", "max_vel_y", "max_vel_theta")


def deep_merge(base: Any, over: Any) -> Any:
    """``over`` on top of ``base``: mappings merge key by key, anything else replaces."""
    if isinstance(base, Mapping) and isinstance(over, Mapping):
        out = {k: copy.deepcopy(v) for k, v in base.items()}
        for k, v in over.items():
            out[k] = deep_merge(out[k], v) if k in out else copy.deepcopy(v)
        return out
    return copy.deepcopy(over)


def find_profile(name: Any, scenario_path: str) -> str:
    """The file of profile ``name``: a path (relative to the scenario), else ``robots/NAME.yaml``
    beside the scenario, else the shipped ``executive/data/robots/NAME.yaml``."""
    if not isinstance(name, str) or not name:
        raise ScenarioError(f"expected a profile name or file, got {name!r}")
    here = os.path.dirname(os.path.abspath(scenario_path))
    if name.endswith((".yaml", ".yml")):
        path = name if os.path.isabs(name) else os.path.join(here, name)
        if not os.path.isfile(path):
            raise ScenarioError(f"no profile file {path}")
        return path
    for folder in (os.path.join(here, "robots"), str(SHIPPED)):
        path = os.path.join(folder, name + ".yaml")
        if os.path.isfile(path):
            return path
    known = sorted({p.stem for folder in (FsPath(here) / "robots", SHIPPED)
                    if folder.is_dir() for p in folder.glob("*.yaml")})
    raise ScenarioError(f"no robot profile {name!r}{suggest(name, known)} (looked in "
                        f"{os.path.join(here, 'robots')} and {SHIPPED})")


def profile_doc(src: Source) -> tuple[dict[str, Any], list[str]]:
    """A profile file -> (config namespaces it sets, problems as file:line: what)."""
    d = src.doc
    errs: list[str] = []
    if not isinstance(d, Mapping) or "robot_profile" not in d:
        return {}, [f"{src.where(())}: a robot profile is a mapping with robot_profile: NAME"]
    for k in d:
        if k not in PROFILE_KEYS:
            errs.append(f"{src.where((k,))}: unknown key '{k}'{suggest(str(k), PROFILE_KEYS)}")
    out: dict[str, Any] = {"robot": {}, "sim": {}, "safety": {}}
    if "footprint" in d:
        out["robot"]["footprint"] = d["footprint"]
    if "robot_radius" in d:
        out["robot"]["robot_radius"] = d["robot_radius"]
        out["robot"].setdefault("footprint", [])
    if "drive" in d:
        if d["drive"] not in ("diff", "omni"):
            errs.append(f"{src.where(('drive',))}: must be diff or omni, got {d['drive']!r}")
        else:
            out["sim"]["kinematics"] = d["drive"]
    limits = d.get("limits") or {}
    if not isinstance(limits, Mapping):
        errs.append(f"{src.where(('limits',))}: expected a mapping of {', '.join(LIMIT_KEYS)}")
        limits = {}
    for k, v in limits.items():
        if k not in LIMIT_KEYS:
            errs.append(f"{src.where(('limits', k))}: unknown limit '{k}'"
                        f"{suggest(str(k), LIMIT_KEYS)}")
            continue
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            errs.append(f"{src.where(('limits', k))}: expected a number, got {v!r}")
            continue
        if k in _SAFETY_LIMITS:
            out["safety"][k] = v
        if k == "min_vel_x":
            continue           # the body's limit is the fastest either way (below)
        out["sim"][k] = v
        for ns, keys in _PLANNER_LIMITS.items():
            if k in keys:
                out.setdefault(ns, {})[k] = v
        if k == "max_vel_x":
            out.setdefault("DWAPlannerROS", {})["max_vel_trans"] = v
        if k == "max_vel_y" and v > 0:
            out.setdefault("DWAPlannerROS", {})["min_vel_y"] = -v
    if "min_vel_x" in limits and isinstance(limits.get("min_vel_x"), (int, float)):
        fastest = max(abs(float(limits["min_vel_x"])), float(limits.get("max_vel_x", 0) or 0))
        if fastest > 0:
            out["sim"]["max_vel_x"] = fastest
    if "laser" in d:
        if not isinstance(d["laser"], Mapping):
            errs.append(f"{src.where(('laser',))}: expected a mapping of sim laser parameters")
        else:
            out["sim"]["laser"] = dict(d["laser"])
    params = d.get("params") or {}
    if not isinstance(params, Mapping):
        errs.append(f"{src.where(('params',))}: expected namespace -> parameters")
        params = {}
    return deep_merge(out, params), errs


def scenario_doc(scenario: Any, base: Any = None
                 ) -> tuple[dict[str, Any], str, dict[tuple, str], list[Any]]:
    """The merged config document of a scenario, its label and the base's key origins and
    notes. ``base``: a robot YAML path or the ``ConfigSources`` of ROS files (None: the bundled
    robot); the profile goes over it, then the scenario's ``robot`` and ``params``."""
    from executive.config import ConfigSources, merged_doc
    sources = base if isinstance(base, ConfigSources) else ConfigSources(config=base)
    doc, origins, notes = merged_doc(sources)
    label = os.path.basename(sources.config) if sources.config else (
        sources.describe() if sources.has_ros() else "robot.yaml")
    if scenario.profile:
        pdoc, errs = profile_doc(read_source(scenario.profile))
        if errs:
            raise ScenarioError("\n".join(errs), errs)
        doc = deep_merge(doc, pdoc)
        label += f" + {os.path.basename(scenario.profile)}"
        for path in _leaves(pdoc):
            origins[path] = scenario.profile
    doc = deep_merge(doc, {"robot": scenario.robot} if scenario.robot else {})
    doc = deep_merge(doc, scenario.params)
    # a value the scenario sets is reported at its own line, not at the base file's namespace
    for top, body in (("robot", {"robot": scenario.robot}), ("params", scenario.params)):
        for path in _leaves(body):
            line = scenario.lines.get((top,) + path[1:] if top == "robot" else ("params",) + path)
            origins[path] = f"{scenario.source}:{line}" if line else scenario.source
    return doc, label, origins, notes


def _leaves(d: Any, path: tuple = ()) -> list[tuple]:
    """Key paths of the non-mapping values of nested mappings."""
    if not isinstance(d, Mapping) or not d:
        return [path] if path else []
    out: list[tuple] = []
    for k, v in d.items():
        out += _leaves(v, path + (k,))
    return out


def scenario_config(scenario: Any, base: Any = None) -> Any:
    """The robot config for a scenario: base config (a path or ``ConfigSources``), its profile,
    then its robot/params."""
    from executive.config import config_from_mapping
    doc, label, origins, notes = scenario_doc(scenario, base)
    return config_from_mapping(doc, f"{scenario.source} (over {label})", origins, notes)


def config_problems(scenario: Any, src: Source | None = None, base: Any = None
                    ) -> list[str]:
    """Problems of the merged config (profile and parameter errors), as file:line: what."""
    from executive.config import ConfigError
    from navcore.params import ParameterError, Parameters
    try:
        config = scenario_config(scenario, base)
    except ScenarioError as e:
        return e.errors
    except ConfigError as e:
        # each line already names file:line (the scenario's, its profile's or the base's)
        return [f"{line}" if line.startswith(scenario.source) or ":" in line.split(" ")[0]
                else f"{scenario.source}: merged robot config: {line}"
                for line in str(e).splitlines() if line.strip()]
    # a parameter change an event makes, checked against the namespace's declared table (the
    # costmaps' layer namespaces exist only once built: those are checked when the event fires)
    live = config.all_parameters()
    errs = []
    for i, ev in enumerate(scenario.events):
        if ev.action != "set":
            continue
        for ns, values in ev.arg.items():
            where = (src.where(("events", i, "set", ns)) if src is not None
                     else f"{scenario.source}: events[{i}].set.{ns}")
            if ns in live:
                try:
                    Parameters(live[ns].specs(), live[ns].as_dict(), where=where).set(values)
                except ParameterError as e:
                    errs.append(str(e))
    return errs
