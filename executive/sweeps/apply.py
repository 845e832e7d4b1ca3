"""Applying a sweep point: robot-config parameters onto a scenario, tree ports onto a tree file.

A parameter key ``ns.a.b`` sets ``b`` inside ``a`` of namespace ``ns`` (deep: the rest of the
namespace stays); a tree-port key ``Subtree/Node.port`` sets ``port`` on every node of that
subtree whose type or name is ``Node``. Both are checked the way a run would use them: the merged
robot config is validated and the changed tree is loaded.
"""

from __future__ import annotations

import copy
import os
import tempfile
from typing import Any, Mapping

import yaml

from navcore.safe_read import load_yaml
from executive.errors import ExecutiveError


class ApplyError(ExecutiveError, ValueError):
    """A point names a parameter or port that does not exist, or a value it cannot take."""


def split_point(point: Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """(robot-config parameters, tree ports) of a point."""
    params = {k: v for k, v in point.items() if "/" not in k}
    ports = {k: v for k, v in point.items() if "/" in k}
    return params, ports


def merged_params(base: Mapping[str, Any], params: Mapping[str, Any]) -> dict[str, Any]:
    """``base`` (namespace -> mapping) with every dotted key of ``params`` set, deeply."""
    out = copy.deepcopy(dict(base))
    for key, value in params.items():
        parts = key.split(".")
        node = out
        for part in parts[:-1]:
            child = node.get(part)
            if not isinstance(child, dict):
                child = dict(child) if isinstance(child, Mapping) else {}
                node[part] = child
            node = child
        node[parts[-1]] = copy.deepcopy(value)
    return out


def apply_point(scenario: Any, point: Mapping[str, Any], config: Any,
                seed: int | None = None, time_limit: float | None = None) -> Any:
    """A copy of ``scenario`` with the point's parameters merged deeply into its ``params`` (over
    the base robot config ``config``: a path or ``ConfigSources``), and the seed / time limit
    replaced; raises ApplyError when the merged robot config is invalid."""
    from executive.config import ConfigError, ConfigSources, merged_doc
    from executive.scenario import ScenarioError, scenario_config
    params, _ = split_point(point)
    s = copy.copy(scenario)
    try:
        if params:
            sources = config if isinstance(config, ConfigSources) else ConfigSources(config=config)
            base, _, _ = merged_doc(sources)
            touched = {k.split(".")[0] for k in params}
            # the base namespace, then the scenario's own values, then the point: all deep, so a
            # point that sets one value of a layer keeps the layer's other values
            layered = {ns: merged_params(base.get(ns) or {}, _dotted(scenario.params.get(ns)))
                       for ns in touched}
            s.params = merged_params(dict(scenario.params, **layered), params)
        if seed is not None:
            s.seed = int(seed)
        if time_limit is not None:
            s.time_limit = float(time_limit)
        merged = scenario_config(s, config)
    except (ConfigError, ScenarioError) as e:
        raise ApplyError(_strip_source(str(e))) from None
    _refuse_adjusted(merged, params)
    return s


def _refuse_adjusted(config: Any, params: Mapping[str, Any]) -> None:
    """A point's value that the loader would clamp or rename (ROS leniency, with a warning) is an
    error in a sweep: the run would not test the value the sweep file names."""
    for note in getattr(config, "report", []):
        if getattr(note, "level", "") != "warning" or not getattr(note, "path", ()):
            continue
        for key in params:
            ns, _, name = key.partition(".")
            if note.path[0] == ns and note.path[-1] == name.split(".")[-1]:
                text = str(note)
                raise ApplyError(f"'{key}': {text.partition('warning: ')[2] or text}")


def _dotted(values: Any, prefix: str = "") -> dict[str, Any]:
    """``{a: {b: 1}}`` -> ``{"a.b": 1}`` (lists and scalars are leaves)."""
    out: dict[str, Any] = {}
    for k, v in (values or {}).items():
        key = f"{prefix}{k}"
        if isinstance(v, Mapping) and v:
            out.update(_dotted(v, key + "."))
        else:
            out[key] = v
    return out


def _strip_source(message: str) -> str:
    """A config error names the scenario it was merged over; the sweep names its own line."""
    head, sep, rest = message.partition("): ")
    return rest if sep and "(over " in head else message


def _set_ports(node: Any, target: str, port: str, value: Any) -> int:
    """Set ``port`` on every node of type or name ``target`` under ``node``; returns the count."""
    if not isinstance(node, Mapping) or len(node) != 1:
        return 0
    (node_type, body), = node.items()
    hits = 0
    if not isinstance(body, dict):
        return 0
    if node_type == target or body.get("name") == target:
        body[port] = copy.deepcopy(value)
        hits += 1
    for child in body.get("children") or []:
        hits += _set_ports(child, target, port, value)
    if "child" in body:
        hits += _set_ports(body["child"], target, port, value)
    return hits


def tree_doc_with_ports(doc: Mapping[str, Any], ports: Mapping[str, Any], source: str
                        ) -> dict[str, Any]:
    """A copy of a YAML tree document with the ports set; ApplyError names what did not match."""
    out = copy.deepcopy(dict(doc))
    trees = out.get("trees")
    if not isinstance(trees, dict):
        raise ApplyError(f"{source}: tree ports need a YAML tree with 'trees:'")
    for key, value in ports.items():
        path, _, port = key.rpartition(".")
        subtree, _, target = path.partition("/")
        if subtree not in trees:
            raise ApplyError(f"'{key}': tree {source} has no subtree '{subtree}' "
                             f"(it has {', '.join(map(str, trees))})")
        if "/" in target:
            raise ApplyError(f"'{key}': give one node after the subtree: 'Subtree/Node.port'")
        if _set_ports(trees[subtree], target, port, value) == 0:
            raise ApplyError(f"'{key}': no node of type or name '{target}' in subtree "
                             f"'{subtree}' of {source}")
    return out


def tree_with_ports(tree_path: str, point: Mapping[str, Any], out_dir: str | None = None) -> str:
    """The tree file to run for a point: ``tree_path`` itself when the point sets no port, else a
    file of the same name in ``out_dir`` (a temporary folder when None) with the ports set. The
    written tree is loaded once, so a bad port or value raises ApplyError."""
    from executive.tree_loader import TreeLoadError, load_tree_file
    _, ports = split_point(point)
    if not ports:
        return tree_path
    if not tree_path.endswith((".yaml", ".yml")):
        raise ApplyError(f"tree ports need a YAML tree; {tree_path} is not one")
    doc = load_yaml(tree_path, what="tree file", error=ApplyError)
    changed = tree_doc_with_ports(doc, ports, tree_path)
    out_dir = out_dir or tempfile.mkdtemp(prefix="navbt-sweep-tree-")
    out = os.path.join(out_dir, os.path.basename(tree_path))
    with open(out, "w", encoding="utf-8") as f:
        yaml.safe_dump(changed, f, sort_keys=False)
    try:
        load_tree_file(out, namespace="/sweep_ports")
    except TreeLoadError as e:
        raise ApplyError(f"{', '.join(ports)}: {str(e).replace(out, tree_path)}") from None
    return out
