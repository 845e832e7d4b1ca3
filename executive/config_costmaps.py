"""Costmap namespaces of the robot config as costmap_2d reads them.

What ROS accepts in a costmap namespace but has no effect here is listed (ignored notes), not
dropped silently; then the costmap is built once on a tiny map so that every layer validates its
own namespace, each error reported at its line.
"""
from __future__ import annotations

import importlib.util
import math
import re
from typing import Any, Mapping

from navcore.params import ParameterError
from executive.param_files import Findings
from executive.ros_params import (COSTMAP_IGNORED, COSTMAP_LAYER_IGNORED, COSTMAP_NO_EFFECT,
                                  SOURCE_NO_EFFECT)

# a component's error names the namespace path and the parameter: found here to report the
# error at that key's line
ERROR_PATH = re.compile(r"^(?:.*: )?([\w./-]+): (?:unknown parameter|parameter) '([^']+)'")
_UNLISTED_SOURCE = re.compile(r"^([\w/]+): namespace '([^']+)' is not listed in "
                              r"observation_sources")


def _costmap_body(body: dict[str, Any], ns: str, report: Findings) -> dict[str, Any]:
    """The costmap namespace without what ROS accepts there but navbt has no use for: keys of
    COSTMAP_IGNORED, layer namespaces that 'plugins' does not list, layer keys ROS ignores."""
    out = dict(body)
    plugins = out.get("plugins")
    if isinstance(plugins, (list, tuple)):
        names = {str(p.get("name", "")) if isinstance(p, Mapping) else str(p) for p in plugins}
        for key, value in body.items():
            if key in COSTMAP_IGNORED:
                if key in ("static_map", "map_type"):
                    report.add("ignored", (ns, key), f"{ns}: '{key}' has no effect when "
                               "'plugins' is given (as in costmap_2d)")
                else:
                    report.add("ignored", (ns, key), f"{ns}: '{key}': {COSTMAP_IGNORED[key]}")
                out.pop(key)
            elif isinstance(value, Mapping) and key not in names and key != "footprint":
                report.add("note", (ns, key), f"{ns}: layer namespace '{key}' is not in "
                           f"'plugins' ({', '.join(sorted(names))}), so it is not used (ROS "
                           "ignores it too)")
                out.pop(key)
        for name in names:
            layer = out.get(name)
            if isinstance(layer, Mapping):
                layer = dict(layer)
                for key in [k for k in layer if k in COSTMAP_LAYER_IGNORED]:
                    report.add("ignored", (ns, name, key), f"{ns}/{name}: '{key}': "
                               f"{COSTMAP_LAYER_IGNORED[key]}")
                    layer.pop(key)
                out[name] = layer
    else:  # pre-Hydro layout: the costmap moves the layer keys itself; these it never read
        for key in ("inscribed_radius", "circumscribed_radius"):
            if key in out:
                report.add("ignored", (ns, key), f"{ns}: '{key}': {COSTMAP_IGNORED[key]}")
                out.pop(key)
        # a layer's keys when the costmap has no such layer (static_map false, no voxel type):
        # costmap_2d's conversion does not move them, nothing reads them
        unused = []
        if not out.get("static_map", False):
            unused += [k for k in ("map_topic", "unknown_cost_value", "lethal_cost_threshold")
                       if k in out]
        if out.get("map_type", "costmap") != "voxel":
            unused += [k for k in ("origin_z", "z_resolution", "z_voxels", "mark_threshold",
                                   "unknown_threshold", "publish_voxel_map") if k in out]
        for key in unused:
            out.pop(key)
        if unused:
            report.add("ignored", (ns, unused[0]), f"{ns}: {', '.join(unused)}: keys of a layer "
                       "this costmap does not have (static_map / map_type), unused as in "
                       "costmap_2d")
    _note_no_effect(out, ns, report)
    return out


def _note_no_effect(body: Mapping[str, Any], ns: str, report: Findings) -> None:
    """One "ignored" note listing the frame, topic and publishing keys of a costmap (and of its
    observation sources) that are accepted but change nothing here."""
    paths = [(k,) for k in body if k in COSTMAP_NO_EFFECT]
    for layer, lbody in body.items():
        if isinstance(lbody, Mapping):
            paths += [(layer,) + p for p in _source_keys_no_effect(lbody)]
    paths += _source_keys_no_effect(body)   # pre-Hydro: sources at the top level
    if paths:
        report.add("ignored", (ns,) + paths[0], f"{ns}: frames, topics and publishing have no "
                   "effect here (components are wired directly, in one frame): "
                   + ", ".join("/".join(map(str, p)) for p in paths))


def _source_keys_no_effect(holder: Mapping[str, Any]) -> list[tuple[str, str]]:
    """(source, key) of each frame or topic key of the observation sources ``holder`` lists."""
    sources = holder.get("observation_sources")
    out: list[tuple[str, str]] = []
    for src in sources.split() if isinstance(sources, str) else []:
        sbody = holder.get(src)
        if isinstance(sbody, Mapping):
            out += [(src, k) for k in sbody if k in SOURCE_NO_EFFECT]
    return out


def drop(body: dict[str, Any], path: tuple) -> bool:
    d: Any = body
    for part in path[:-1]:
        if not isinstance(d, dict) or part not in d:
            return False
        d = d[part]
    if isinstance(d, dict) and path[-1] in d:
        d.pop(path[-1])
        return True
    return False


def deep_copy(body: Any) -> Any:
    if isinstance(body, Mapping):
        return {k: deep_copy(v) for k, v in body.items()}
    return body


def check_costmap(body: dict[str, Any], ns: str, footprint: list, radius: float,
                   report: Findings) -> dict[str, Any]:
    """Build the costmap once on a tiny map: every layer validates its own namespace. Each
    error is reported and its key left out for another try, so that all of them are listed.
    Returns the namespace to build the real costmap from."""
    body = _costmap_body(body, ns, report)
    if importlib.util.find_spec("navcore.costmap.layered") is None:
        return body  # the costmap component is not installed: nothing to check against
    if not _costmap_size_ok(body, ns, report):
        return body  # building it to check it would take the memory it is refused for
    from navcore.maps import OccupancyGrid
    import numpy as np
    trial = deep_copy(body)
    if "footprint" not in trial and "robot_radius" not in trial:
        if footprint:
            trial["footprint"] = footprint
        else:
            trial["robot_radius"] = radius
    for _ in range(50):
        try:
            cm = make_costmap(trial, OccupancyGrid(np.zeros((4, 4)), 0.05), ns)
        except (ParameterError, ValueError, KeyError) as e:
            text = str(e)
            unlisted = _UNLISTED_SOURCE.match(text)
            if unlisted:
                parts = tuple(unlisted.group(1).split("/")) + (unlisted.group(2),)
                report.add("note", parts, f"{text} (ROS ignores it too)")
                drop(trial, parts[1:])
                drop(body, parts[1:])
                continue
            m = ERROR_PATH.match(text)
            parts = (tuple(m.group(1).split(".")[0].split("/")) + (m.group(2),)) if m else (ns,)
            report.add("error", parts, text)
            if not m or parts[0] != ns or not drop(trial, parts[1:]):
                break
            continue
        for w in getattr(cm, "warnings", []):
            report.add("ignored", (ns,), w)
        break
    return body


def _costmap_size_ok(body: Mapping[str, Any], ns: str, report: Findings) -> bool:
    """Refuse (by arithmetic, before anything is allocated) a costmap of more cells than a map
    may have; a static layer's map is bounded when it is read."""
    from navcore.maps import MAX_MAP_CELLS
    from navcore.costmap.layered import COSTMAP_PARAMS
    defaults = {p.name: p.default for p in COSTMAP_PARAMS}
    dims = []
    for key in ("width", "height", "resolution"):
        v = body.get(key, defaults[key])
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                or v < 0:
            return True  # a malformed value: the build below names it
        dims.append(float(v))
    width, height, res = dims
    if res <= 0:
        return True
    cells = math.ceil(width / res) * math.ceil(height / res)
    if cells > MAX_MAP_CELLS:
        key = "width" if "width" in body else "height" if "height" in body else "resolution"
        report.add("error", (ns, key), f"{ns}: {width:g} m x {height:g} m at {res:g} m is "
                   f"{cells:.4g} cells, more than the limit of {MAX_MAP_CELLS}")
        return False
    return True


def make_costmap(params: dict[str, Any], grid: Any, name: str, clock: Any = None) -> Any:
    """A LayeredCostmap from a ROS namespace; the map goes to it only if it has a static layer."""
    from navcore.costmap.layered import LayeredCostmap
    try:
        return LayeredCostmap.from_params(params, static_map=None, name=name, clock=clock)
    except ParameterError as e:
        if "needs a map" not in str(e):
            raise
    return LayeredCostmap.from_params(params, static_map=grid, name=name, clock=clock)
