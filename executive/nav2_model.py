"""Facts about Nav2's behaviour-tree nodes per distribution, and BehaviorTree.CPP's built-ins.

``data/nav2_nodes.json`` holds, for Humble, Jazzy, Kilted and main, every node type that
``nav2_behavior_tree`` registers (or lists in its ``nav2_tree_nodes.xml`` palette) with its
category and ports (direction, type, default); no descriptions. It is generated from a
navigation2 checkout at the commits of ``../shared/data/SOURCES.md`` section 6 with
``python -m executive.nav2_model PATH_TO_NAVIGATION2_GIT``.

The loader uses it for hints ("a Nav2 node of jazzy, kilted, main that navbt lacks"), the XML
writer to export Nav2 node types with Nav2's own ports only, and the tests to check that
``mission nodes`` covers every Nav2 node except those in ``NOT_PROVIDED``.
"""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path
from typing import Any

DISTROS = ("humble", "jazzy", "kilted", "main")
DEFAULT_XML_DISTRO = "jazzy"  # XML with BTCPP_format="4" and no nav2_distro: the current LTS
BTCPP3_DISTRO = "humble"      # XML without BTCPP_format is BehaviorTree.CPP 3, i.e. Humble
DEFAULT_YAML_DISTRO = None    # navbt's own YAML: navbt's semantics (docs/trees.md)
COMMITS = {"humble": "3c3db59d6969d8ecee8e68468693d006397f4a0c",
           "jazzy": "f4108e5b1c2bce804a1aa0c7be6673a8eb4a1501",
           "kilted": "71a1d84f49dc48e226c96619188ee12054824ff3",
           "main": "a3a97043ee93d92fe8d70ec56d183933169beb1c"}
_DATA = Path(__file__).resolve().parent / "data" / "nav2_nodes.json"

# Nav2 node types navbt does not provide, and why (docs/trees.md lists them).
NOT_PROVIDED: dict[str, str] = {
    "AssistedTeleop": "needs a teleoperation input (joystick) navbt does not have",
    "CancelAssistedTeleop": "cancels AssistedTeleop, which navbt does not have",
    "DockRobot": "needs opennav_docking's docking server and dock detection",
    "UndockRobot": "needs opennav_docking's docking server",
    "FollowObject": "needs an object tracker (opennav_following)",
    "CancelFollowObject": "cancels FollowObject, which navbt does not have",
    "ComputeAndTrackRoute": "needs Nav2's route tracking server (operations on route edges)",
    "CancelComputeAndTrackRoute": "cancels ComputeAndTrackRoute, which navbt does not have",
    "ToggleCollisionMonitor": "needs Nav2's collision monitor server",
    "PauseResumeController": "needs pause/resume ROS services",
    "CheckStopStatus": "needs the controller server's stop-status service",
}

# Port defaults that differ per distribution where the port is not written: RoundRobin always
# wraps around before main (no wrap_around port there); main added the port, default false.
DISTRO_DEFAULTS: dict[str, dict[str, dict[str, Any]]] = {
    "RoundRobin": {"wrap_around": {"humble": True, "jazzy": True, "kilted": True, "main": False}},
}

# BehaviorTree.CPP 4 built-in node types (src/bt_factory.cpp), incl. the v3 name SequenceStar.
BTCPP_BUILTINS = (
    "Fallback", "AsyncFallback", "Sequence", "AsyncSequence", "SequenceWithMemory",
    "SequenceStar", "Parallel", "ParallelAll", "ReactiveSequence", "ReactiveFallback",
    "IfThenElse", "WhileDoElse", "TryCatch", "Inverter", "RetryUntilSuccessful",
    "KeepRunningUntilFailure", "Repeat", "Timeout", "Delay", "RunOnce", "ForceSuccess",
    "ForceFailure", "AlwaysSuccess", "AlwaysFailure", "Script", "ScriptCondition",
    "SetBlackboard", "Sleep", "UnsetBlackboard", "SubTree", "Precondition", "Switch2",
    "Switch3", "Switch4", "Switch5", "Switch6", "LoopInt", "LoopBool", "LoopDouble",
    "LoopString", "WasEntryUpdated", "SkipUnlessUpdated", "WaitValueUpdate")


@lru_cache(maxsize=1)
def table() -> dict[str, dict[str, Any]]:
    """{distro: {node type: [category, {port: [direction "in"/"ou"/"io", type, default]}]}}."""
    with open(_DATA, encoding="utf-8") as f:
        return json.load(f)


def distros_of(node_type: str) -> list[str]:
    """The Nav2 distributions that have ``node_type`` (empty if none)."""
    return [d for d in DISTROS if node_type in table()[d]]


def all_node_types() -> set[str]:
    """Every Nav2 node type of the four distributions."""
    return {t for d in DISTROS for t in table()[d]}


def ports(node_type: str, distro: str) -> dict[str, list[Any]] | None:
    """Nav2's ports of ``node_type`` in ``distro`` (falling back to the nearest distribution that
    has it), or None if Nav2 has no such node."""
    order = [distro] + [d for d in reversed(DISTROS) if d != distro]
    for d in order:
        entry = table()[d].get(node_type)
        if entry is not None:
            return entry[1]
    return None


def any_ports(node_type: str) -> set[str]:
    """Port names ``node_type`` has in any distribution (empty if Nav2 has no such node)."""
    return {p for d in DISTROS for p in (table()[d].get(node_type) or ["", {}])[1]}


def category(node_type: str) -> str | None:
    for d in reversed(DISTROS):
        entry = table()[d].get(node_type)
        if entry is not None:
            return entry[0]
    return None


NAVBT = "navbt"  # as a nav2_distro value: navbt's own semantics (what YAML trees get by default)


def check_distro(name: str) -> str:
    """``name`` lower-cased if it is a known distribution (or ``navbt``), else ValueError
    naming the choices."""
    d = name.strip().lower()
    if d not in DISTROS and d != NAVBT:
        raise ValueError(f"unknown Nav2 distribution {name!r}; expected one of "
                         f"{', '.join(DISTROS)} (or {NAVBT} for navbt's own semantics)")
    return d


def _generate(repo: str) -> dict[str, dict[str, Any]]:
    """Read the palette and the plugin registrations of each distribution from a git checkout."""
    import re
    import subprocess
    import xml.etree.ElementTree as ET

    def git(*args: str) -> str:
        return subprocess.run(["git", "-C", repo, *args], check=True, capture_output=True,
                              text=True).stdout

    models, registered = {}, {}
    for d, commit in COMMITS.items():
        root = ET.fromstring(git("show", f"{commit}:nav2_behavior_tree/nav2_tree_nodes.xml"))
        models[d] = {e.get("ID"): e for e in root.find("TreeNodesModel")}
        text = git("grep", "-h", "-A3", "factory.register", commit, "--",
                   "nav2_behavior_tree/plugins/*.cpp").replace("\n", " ")
        registered[d] = set(re.findall(r'register\w*<[^>]*>\(\s*"(\w+)"', text))
    out: dict[str, dict[str, Any]] = {}
    for d in DISTROS:
        entries = {}
        for node in sorted(set(models[d]) | registered[d]):
            el = models[d].get(node)
            for other in reversed(DISTROS):  # a registered node missing from its palette
                if el is None:
                    el = models[other].get(node)
            if el is None:
                continue
            kinds = {"input_port": "in", "output_port": "ou", "inout_port": "io"}
            entries[node] = [el.tag, {p.get("name"): [kinds[p.tag], p.get("type"), p.get("default")]
                                      for p in el if p.tag in kinds}]
        out[d] = entries
    return out


if __name__ == "__main__":  # python -m executive.nav2_model PATH_TO_NAVIGATION2_GIT
    import sys
    data = _generate(sys.argv[1])
    _DATA.write_text(json.dumps(data, separators=(",", ":"), sort_keys=True) + "\n",
                     encoding="utf-8")
    print(f"{_DATA}: {sum(len(v) for v in data.values())} entries")
