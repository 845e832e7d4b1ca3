"""rosparam files in ROS namespaces: a parameter tree that remembers where each value came from.

ROS users compose a robot from several YAML files, each loaded into a namespace (``<rosparam
file=... ns="global_costmap"/>`` or ``--params FILE:global_costmap``), merged leaf by leaf in load
order as rosparam does. ``ParamTree`` holds that tree with the ``file:line`` of every value;
``move_base_to_config`` turns the move_base node's namespace (and amcl's) into navbt's robot
config namespaces, with ROS's own leniency (deprecated names, clamps, keys ROS ignores) and a note
for everything that has no counterpart here. Nothing is dropped silently.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any, Iterator, Mapping

from navcore.params import Leniency, suggest
from executive.config_params import MOVE_BASE_PARAMS
from executive.param_files import Note, ParamsError, Path_, nearest, read_ros_yaml


# --------------------------------------------------------------------------- the tree
def split_name(name: str) -> Path_:
    """``/move_base/global_costmap`` or ``global_costmap/`` -> path parts (empty parts dropped)."""
    return tuple(p for p in str(name).split("/") if p)


class ParamTree:
    """Nested parameter values with the origin (``file:line``) of each key, merged like rosparam:
    a mapping loaded into a namespace updates it key by key; anything else replaces."""

    def __init__(self) -> None:
        self.values: dict[str, Any] = {}
        self.origins: dict[Path_, str] = {}

    def set(self, path: Path_, value: Any, origin: str) -> None:
        """Set one parameter (a mapping is merged key by key, as rosparam and roslaunch do)."""
        if not path:
            if isinstance(value, Mapping):
                for k, v in value.items():
                    self.set((str(k),), v, origin)
            return
        d = self.values
        for i, part in enumerate(path[:-1]):
            if not isinstance(d.get(part), dict):
                d[part] = {}
                self.origins.setdefault(path[:i + 1], origin)
            d = d[part]
        key = path[-1]
        if isinstance(value, Mapping):
            if not isinstance(d.get(key), dict):
                d[key] = {}
            self.origins[path] = origin
            for k, v in value.items():
                self.set(path + (str(k),), v, origin)
        else:
            self._forget(path)
            d[key] = value
            self.origins[path] = origin

    def _forget(self, path: Path_) -> None:
        n = len(path)
        for p in [p for p in self.origins if len(p) > n and p[:n] == path]:
            del self.origins[p]

    def load(self, doc: Any, ns: Path_, file: str, lines: Mapping[Path_, int],
             line: int | None = None) -> None:
        """Merge a parsed YAML document into namespace ``ns``; each key keeps its file line."""
        if isinstance(doc, Mapping):
            for k, v in doc.items():
                self._load_key(v, ns, (str(k),), file, lines)
        elif doc is not None:
            raise ParamsError(f"{file}{':' + str(line) if line else ''}: a rosparam file without "
                              f"'param' must hold a mapping, got {type(doc).__name__}")

    def _load_key(self, value: Any, ns: Path_, rel: Path_, file: str,
                  lines: Mapping[Path_, int]) -> None:
        origin = f"{file}:{lines[rel]}" if rel in lines else file
        if isinstance(value, Mapping):
            self.set(ns + rel, {}, origin)
            for k, v in value.items():
                self._load_key(v, ns, rel + (str(k),), file, lines)
        else:
            self.set(ns + rel, value, origin)

    def get(self, path: Path_) -> Any:
        d: Any = self.values
        for part in path:
            if not isinstance(d, dict) or part not in d:
                return None
            d = d[part]
        return d

    def origin(self, path: Path_) -> str:
        """Where the value at ``path`` (or its nearest recorded parent) came from."""
        found = nearest(self.origins, path)
        return "" if found is None else found

    def delete(self, path: Path_) -> None:
        parent = self.get(path[:-1]) if path else None
        if isinstance(parent, dict):
            parent.pop(path[-1], None)
        self._forget(path)
        self.origins.pop(path, None)

    def leaves(self, path: Path_ = ()) -> Iterator[tuple[Path_, Any]]:
        """Every (path, value) below ``path`` that is not a mapping."""
        value = self.get(path) if path else self.values
        if isinstance(value, dict):
            for k, v in value.items():
                yield from self.leaves(path + (k,))
        elif path:
            yield path, value


# --------------------------------------------------------------------------- --params FILE[:NS]
def split_params_arg(text: str) -> tuple[str, str]:
    """``FILE[:NAMESPACE]`` -> (file, namespace); a file that exists with a colon in its name
    stays whole."""
    if os.path.exists(text):
        return text, ""
    head, sep, tail = text.rpartition(":")
    if sep and head:
        return head, tail
    return text, ""


def load_params_file(tree: ParamTree, spec: str, node_ns: Path_ = ("move_base",)) -> list[Note]:
    """``--params FILE[:NAMESPACE]``: load FILE into NAMESPACE relative to the move_base node
    (``/abs`` is a global name); without a namespace, into the move_base node itself. Returns
    the notes of reading it (keys written twice)."""
    file, ns = split_params_arg(spec)
    notes: list[Note] = []
    doc, lines = read_ros_yaml(file, notes)
    if ns.startswith("/"):
        target = split_name(ns)
    elif split_name(ns)[:1] == ("amcl",):
        target = split_name(ns)  # amcl is its own node, beside move_base
    else:
        target = node_ns + split_name(ns)
    tree.load(doc, target, file, lines)
    return notes


# --------------------------------------------------------------------------- what ROS tolerates
_PUBLISH_ONLY = "only changes what ROS publishes for visualisation; no effect here"
_FRAME = "a frame name: navbt runs in map/odom/base_link; no effect here"
_TOPIC = "a topic name: navbt wires components directly; no effect here"
_RECONF = "a dynamic_reconfigure switch; no effect at load"

LOCAL_PLANNER_LIMITS_IGNORED = {
    "publish_traj_pc": _PUBLISH_ONLY, "publish_cost_grid_pc": _PUBLISH_ONLY,
    "publish_cost_grid": _PUBLISH_ONLY, "global_frame_id": _FRAME, "odom_topic": _TOPIC,
    "restore_defaults": _RECONF,
}

# Per navbt namespace: the names, clamps and ignored keys of the ROS (noetic) component.
# Clamps are the dynamic_reconfigure ranges (.cfg files), which ROS applies at start-up.
LENIENCY: dict[str, Leniency] = {
    "DWAPlannerROS": Leniency(
        # dwa_planner_ros.cpp warnRenamedParameter (new <- old)
        renamed={"max_trans_vel": "max_vel_trans", "min_trans_vel": "min_vel_trans",
                 "max_rot_vel": "max_vel_theta", "min_rot_vel": "min_vel_theta",
                 "acc_limit_trans": "acc_lim_trans", "rot_stopped_vel": "theta_stopped_vel",
                 # base_local_planner's old names, still met in DWA files copied from TR ones
                 "pdist_scale": "path_distance_bias", "gdist_scale": "goal_distance_bias",
                 "acc_lim_th": "acc_lim_theta", "max_vel_rot": "max_vel_theta",
                 "min_vel_rot": "min_vel_theta"},
        # base_local_planner's name, which the DWA does not read (PR2's DWA file has it)
        misspelled={"vtheta_samples": "vth_samples"},
        clamps={"sim_time": (0.0, None), "sim_granularity": (0.0, None),
                "angular_sim_granularity": (0.0, None), "path_distance_bias": (0.0, None),
                "goal_distance_bias": (0.0, None), "occdist_scale": (0.0, None),
                "twirling_scale": (0.0, None), "stop_time_buffer": (0.0, None),
                "oscillation_reset_dist": (0.0, None), "oscillation_reset_angle": (0.0, None),
                "scaling_speed": (0.0, None), "max_scaling_factor": (0.0, None),
                "vx_samples": (1, None), "vy_samples": (1, None), "vth_samples": (1, None),
                "max_vel_trans": (0.0, None), "min_vel_trans": (0.0, None),
                "max_vel_theta": (0.0, None), "min_vel_theta": (0.0, None),
                "acc_lim_x": (0.0, 20.0), "acc_lim_y": (0.0, 20.0), "acc_lim_theta": (0.0, 20.0),
                "acc_lim_trans": (0.0, None)},
        ignored=dict(LOCAL_PLANNER_LIMITS_IGNORED)),
    "TrajectoryPlannerROS": Leniency(
        # trajectory_planner_ros.cpp loadParameterWithDeprecation / backup_vel
        renamed={"pdist_scale": "path_distance_bias", "gdist_scale": "goal_distance_bias",
                 "min_in_place_rotational_vel": "min_in_place_vel_theta",
                 "backup_vel": "escape_vel", "acc_lim_th": "acc_lim_theta"},
        # BaseLocalPlanner.cfg ranges
        clamps={"acc_lim_x": (0.0, 20.0), "acc_lim_y": (0.0, 20.0), "acc_lim_theta": (0.0, 20.0),
                "max_vel_x": (0.0, 20.0), "min_vel_x": (0.0, 20.0), "max_vel_theta": (0.0, 20.0),
                "min_vel_theta": (-20.0, 0.0), "min_in_place_vel_theta": (0.0, 20.0),
                "sim_time": (0.0, 10.0), "sim_granularity": (0.0, 5.0),
                "path_distance_bias": (0.0, 5.0), "goal_distance_bias": (0.0, 5.0),
                "occdist_scale": (0.0, 5.0), "oscillation_reset_dist": (0.0, 5.0),
                "escape_reset_dist": (0.0, 5.0), "escape_reset_theta": (0.0, 5.0),
                "vx_samples": (1, 300), "vtheta_samples": (1, 300),
                "heading_lookahead": (0.0, 5.0), "escape_vel": (-2.0, 2.0),
                "heading_scoring_timestep": (0.0, 1.0)},
        ignored=dict(LOCAL_PLANNER_LIMITS_IGNORED,
                     world_model="only 'costmap' exists in noetic; the costmap is used",
                     point_grid="the freespace controller's grid (world_model: costmap only)",
                     max_rotational_vel="read by noetic but overridden by max_vel_theta "
                                        "(dynamic_reconfigure)")),
    "GlobalPlanner": Leniency(
        clamps={"lethal_cost": (1, 255), "neutral_cost": (1, 255), "cost_factor": (0.01, 5.0),
                "orientation_mode": (0, 6)}),
    "move_base": Leniency(
        clamps={"planner_frequency": (0.0, 100.0), "controller_frequency": (0.0, 100.0),
                "planner_patience": (0.0, 100.0), "controller_patience": (0.0, 100.0),
                "max_planning_retries": (-1, 1000), "conservative_reset_dist": (0.0, 50.0),
                "oscillation_timeout": (0.0, 60.0), "oscillation_distance": (0.0, 10.0)},
        ignored={"restore_defaults": _RECONF},
        misspelled={"recovery_behaviour_enabled": "recovery_behavior_enabled"}),
    "amcl": Leniency(
        renamed={"beam_skip_error_threshold_": "beam_skip_error_threshold"},
        ignored={"force_update_after_initialpose": "a new initial pose is always used here",
                 "force_update_after_set_map": "the map does not change while running",
                 "std_warn_level_x": "diagnostics only", "std_warn_level_y": "diagnostics only",
                 "std_warn_level_yaw": "diagnostics only", "bag_scan_period": "bag playback "
                 "only", "restore_defaults": _RECONF, "use_sim_time": "time is the Clock's",
                 "scan_topic": _TOPIC, "map_topic": _TOPIC}),
}

# Keys of a costmap namespace ROS accepts that have no effect here (besides COSTMAP_PARAMS').
COSTMAP_IGNORED = {"map_type": "pre-Hydro costmap switch, only read without 'plugins'",
                   "publish_voxel_map": _PUBLISH_ONLY, "map_topic": _TOPIC,
                   "static_map": "pre-Hydro switch, only read without 'plugins'",
                   "inscribed_radius": "computed from the footprint here (as in costmap_2d)",
                   "circumscribed_radius": "computed from the footprint here (as in costmap_2d)",
                   "origin_z": "only the voxel layer's (in its namespace)",
                   "map_subscribe_transient_local": _TOPIC}
COSTMAP_LAYER_IGNORED = {"map_subscribe_transient_local": _TOPIC, "footprint_topic": _TOPIC,
                         "transform_tolerance": "transforms are exact here",
                         "use_sim_time": "time is the Clock's"}

# Keys the costmap tables accept (so ROS files load) that change nothing here: listed per costmap
# in one "ignored" note. Top level, then an obstacle source's.
COSTMAP_NO_EFFECT = ("global_frame", "robot_base_frame", "transform_tolerance",
                     "publish_frequency", "footprint_topic", "always_send_full_costmap",
                     "use_sim_time")
SOURCE_NO_EFFECT = ("sensor_frame", "topic")

# move_base-level keys the costmaps find by searching up the namespace (costmap_2d searchParam):
# footprint and robot_radius (makeFootprintFromParams), obstacle_range and raytrace_range (the
# obstacle layer's sources).
SEARCHED_BY_COSTMAPS = ("footprint", "robot_radius", "obstacle_range", "raytrace_range")

# Parameters that only a costmap reads: at the move_base level ROS ignores them.
COSTMAP_ONLY = ("inflation_radius", "cost_scaling_factor", "observation_sources", "map_type",
                "static_map", "rolling_window", "width", "height", "resolution",
                "update_frequency", "publish_frequency", "global_frame", "robot_base_frame",
                "transform_tolerance", "footprint_padding", "track_unknown_space", "plugins",
                "max_obstacle_height", "origin_x", "origin_y", "always_send_full_costmap",
                "lethal_cost_threshold", "unknown_cost_value", "inflate_unknown")

# Default move_base recovery namespaces (move_base.cpp loadDefaultRecoveryBehaviors).
DEFAULT_RECOVERIES = ("conservative_reset", "rotate_recovery", "aggressive_reset")

PLANNER_NAMESPACES = ("NavfnROS", "GlobalPlanner", "CarrotPlanner", "DWAPlannerROS",
                      "TrajectoryPlannerROS")
# Other ROS planners people configure: accepted (unused) when not selected.
OTHER_PLANNERS = ("TebLocalPlannerROS", "EBandPlannerROS", "MPCPlannerROS", "SBPLLatticePlanner",
                  "PoseFollower", "GlobalPlannerROS", "base_local_planner", "dwa_local_planner")

# Recovery plugin types and the tree nodes that do the same (trees/move_base.yaml).
RECOVERY_TREE_NODES = {"clear_costmap_recovery/ClearCostmapRecovery": "ClearCostmapExceptRegion",
                       "rotate_recovery/RotateRecovery": "Spin",
                       "move_slow_and_clear/MoveSlowAndClear": "(none)"}


@dataclass
class Converted:
    """A navbt-shaped config document, the origin of each of its keys and the findings."""

    doc: dict[str, Any] = field(default_factory=dict)
    origins: dict[Path_, str] = field(default_factory=dict)
    notes: list[Note] = field(default_factory=list)

    def put(self, path: Path_, value: Any, origin: str) -> None:
        d = self.doc
        for part in path[:-1]:
            d = d.setdefault(part, {})
        d[path[-1]] = value
        self.origins.setdefault(path, origin)

    def note(self, level: str, where: str, text: str) -> None:
        self.notes.append(Note(level, where, text))


def _copy_origins(tree: ParamTree, src: Path_, out: Converted, dst: Path_) -> None:
    n = len(src)
    for p, o in tree.origins.items():
        if p[:n] == src:
            out.origins[dst + p[n:]] = o


NAVBT_ONLY = ("robot", "sim", "safety")


def move_base_to_config(tree: ParamTree, node_ns: Path_ = ("move_base",),
                        amcl_ns: Path_ | None = ("amcl",), out: Converted | None = None,
                        outside_files: frozenset[str] = frozenset()) -> Converted:
    """The move_base node's parameters (and amcl's) as navbt config namespaces.

    Keys move_base reads go to ``move_base``; costmap and planner namespaces keep their names;
    ``footprint``/``robot_radius``/``obstacle_range``/``raytrace_range`` at the node level reach
    both costmaps (ROS finds them by searchParam); recovery lists get a note; a costmap parameter
    at the node level is an error saying where it belongs (ROS would silently not use it).
    Parameters outside both nodes that came from ``outside_files`` are listed as ignored."""
    out = out if out is not None else Converted()
    node = tree.get(node_ns)
    node = node if isinstance(node, dict) else {}
    move_base_names = {p.name for p in MOVE_BASE_PARAMS}
    lenient = LENIENCY["move_base"]
    recovery_names = set(DEFAULT_RECOVERIES)
    listed = node.get("recovery_behaviors")
    if isinstance(listed, list):
        recovery_names |= {str(r.get("name")) for r in listed if isinstance(r, Mapping)}
    searched: dict[str, tuple[Any, str]] = {}
    sources = node.get("observation_sources")
    stray_sources = set(sources.split()) if isinstance(sources, str) else set()
    for key, value in node.items():
        path = node_ns + (key,)
        where = tree.origin(path)
        if key in ("global_costmap", "local_costmap") + PLANNER_NAMESPACES + NAVBT_ONLY:
            if not isinstance(value, dict):
                out.note("error", where, f"'{key}' must be a namespace (a mapping), got "
                                         f"{value!r}")
                continue
            out.put((key,), dict(value), where)
            _copy_origins(tree, path, out, (key,))
        elif key in move_base_names or key in lenient.known():
            out.put(("move_base", key), value, where)
        elif key in SEARCHED_BY_COSTMAPS:
            searched[key] = (value, where)
        elif key == "recovery_behaviors":
            out.note("note", where, _recovery_note(value, node))
        elif key in recovery_names:
            out.note("ignored", where, f"'{key}': parameters of a move_base recovery behaviour; "
                                       "recoveries are tree nodes here (see docs/ros-users.md)")
        elif key in OTHER_PLANNERS:
            out.note("ignored", where, f"'{key}': parameters of a planner navbt does not have")
        elif key in COSTMAP_ONLY:
            # ROS silently does not read it here; a whole costmap file in the wrong place
            # shows as one such warning per key
            out.note("warning", where, f"'{key}' is a costmap parameter, which neither "
                                       "move_base nor the costmaps read at this level (ROS "
                                       "ignores it too; its value is not used): load it into a "
                                       "costmap namespace (<rosparam ns=\"global_costmap\"> "
                                       "/ --params FILE:local_costmap)")
        elif key in stray_sources:
            out.note("warning", where, f"'{key}' is an observation source of a costmap, not "
                                       "read at this level (ROS ignores it too): load it with "
                                       "its observation_sources into a costmap namespace")
        elif key == "amcl":
            out.note("error", where, "'amcl' is its own node, not a namespace of move_base: "
                                     "put its parameters in a file of their own and load it "
                                     "with --params FILE:amcl (<rosparam ns=\"/amcl\">)")
        elif isinstance(value, dict):
            spaces = ("global_costmap", "local_costmap") + PLANNER_NAMESPACES
            out.note("error", where, f"unknown namespace '{key}' in move_base"
                                     f"{suggest(key, spaces)}")
        else:
            out.note("error", where, f"move_base: unknown parameter '{key}'"
                                     f"{suggest(key, move_base_names | set(lenient.known()))}")
    for key, (value, where) in searched.items():
        for cm in ("global_costmap", "local_costmap"):
            body = out.doc.setdefault(cm, {})
            if key not in body:
                body[key] = value
                out.origins[(cm, key)] = where
        out.note("note", where, f"'{key}' at the move_base level: both costmaps use it unless "
                                "they set their own (costmap_2d searches up the namespace)")
    if outside_files:
        used = [node_ns] + ([amcl_ns] if amcl_ns is not None else [])
        stray = [(p, tree.origin(p)) for p, _ in tree.leaves()
                 if not any(p[:len(u)] == u for u in used)
                 and tree.origin(p).rpartition(":")[0] in outside_files]
        if stray:
            out.note("ignored", stray[0][1], "parameters outside the move_base and amcl nodes "
                     "(no node here reads them): " + ", ".join(
                         f"/{'/'.join(p)} ({os.path.basename(o)})" for p, o in stray))
    if amcl_ns is not None:
        amcl = tree.get(amcl_ns)
        if isinstance(amcl, dict):
            out.put(("amcl",), dict(amcl), tree.origin(amcl_ns))
            _copy_origins(tree, amcl_ns, out, ("amcl",))
    return out


def _recovery_note(value: Any, node: Mapping[str, Any]) -> str:
    """What the recovery list is here; when every entry has a node, the list as the recovery
    subtree to put in a tree (their namespaces' reset_distance carried over)."""
    if not isinstance(value, list):
        return "'recovery_behaviors' is move_base's recovery list; recoveries are tree nodes here"
    names, nodes = [], []
    for r in value:
        if not isinstance(r, Mapping):
            nodes = None
            continue
        name, kind = str(r.get("name")), str(r.get("type", ""))
        node_type = RECOVERY_TREE_NODES.get(kind, "no node")
        names.append(f"{name} ({kind} -> {node_type})")
        params = node.get(name) if isinstance(node.get(name), Mapping) else {}
        if nodes is None or node_type in ("no node", "(none)"):
            nodes = None
        elif node_type == "Spin":
            nodes.append(f"Spin: {{name: {name}, spin_dist: 6.28}}")
        else:
            dist = params.get("reset_distance", 3.0)
            nodes.append(f"ClearCostmapExceptRegion: {{name: {name}, costmap: both, "
                         f"reset_distance: {dist}}}")
    text = ("'recovery_behaviors' is move_base's recovery list: in navbt recoveries are tree "
            "nodes, so this list is not used; trees/move_base.yaml runs move_base's default "
            "order as a tree. Listed: " + ", ".join(names))
    if nodes:
        text += ("; as the recovery subtree of trees/move_base.yaml (MoveBaseRecoveries): "
                 "RoundRobin: {name: RecoveryBehaviors, wrap_around: false, children: ["
                 + ", ".join(f"{{{n}}}" for n in nodes) + "]}")
    return text
