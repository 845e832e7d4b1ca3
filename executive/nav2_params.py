"""Nav2 parameter files (the ``ros__parameters`` layout) as navbt robot config namespaces.

``read_nav2_params("nav2_params.yaml")`` maps every Nav2 name that has a navbt counterpart: amcl
(``alpha1``-``alpha5``, ``z_hit`` ..., ``max_beams``, ``robot_model_type``), both costmaps and
their plugins (``raytrace_max_range`` and friends, ``footprint`` strings), the planner server's
NavFn, the controller server (DWB's kinematics and the critics that mean the same in the DWA;
MPPI and RPP limits to the DWA), the goal checker, ``velocity_smoother`` and
``collision_monitor`` limits to the safety gate. What has no counterpart is reported once,
grouped by server, as "ignored: ..."; a server navbt replaces by another algorithm gets a warning
that says which. Nothing is dropped silently and nothing here is an error unless the file
cannot be read.
"""

from __future__ import annotations

import os
from typing import Any, Mapping

from executive.config_params import BEHAVIOR_SERVER_PARAMS
from executive.param_files import Note, ParamsError, Path_, nearest, read_ros_yaml
from executive.ros_params import Converted

_AMCL = {f"alpha{i}": f"odom_alpha{i}" for i in range(1, 6)}
_AMCL.update({"z_hit": "laser_z_hit", "z_short": "laser_z_short", "z_max": "laser_z_max",
              "z_rand": "laser_z_rand", "sigma_hit": "laser_sigma_hit",
              "lambda_short": "laser_lambda_short", "max_beams": "laser_max_beams",
              "pf_err": "kld_err", "pf_z": "kld_z"})
_AMCL_SAME = ("laser_min_range", "laser_max_range", "laser_likelihood_max_dist",
              "laser_model_type", "min_particles", "max_particles", "update_min_d",
              "update_min_a", "resample_interval", "transform_tolerance", "recovery_alpha_slow",
              "recovery_alpha_fast", "do_beamskip", "beam_skip_distance", "beam_skip_threshold",
              "beam_skip_error_threshold", "save_pose_rate", "tf_broadcast", "base_frame_id",
              "global_frame_id", "odom_frame_id", "first_map_only", "selective_resampling")
# Nav2's DifferentialMotionModel samples with the square root of the variance: ROS 1's
# "diff-corrected" (nav2_amcl/src/motion_model/differential_motion_model.cpp).
_MOTION_MODELS = {"nav2_amcl::DifferentialMotionModel": "diff-corrected",
                  "nav2_amcl::OmniMotionModel": "omni-corrected",
                  "differential": "diff-corrected", "omnidirectional": "omni-corrected"}

# costmap observation sources: Nav2 name -> costmap_2d name
_SOURCE = {"raytrace_max_range": "raytrace_range", "obstacle_max_range": "obstacle_range"}
_SOURCE_MIN = ("raytrace_min_range", "obstacle_min_range")
_LAYER_TYPES = ("StaticLayer", "ObstacleLayer", "VoxelLayer", "InflationLayer")

# DWB (dwb_core::DWBLocalPlanner) -> DWAPlannerROS, kinematics and sampling
_DWB = {"max_vel_x": "max_vel_x", "min_vel_x": "min_vel_x", "max_vel_y": "max_vel_y",
        "min_vel_y": "min_vel_y", "max_vel_theta": "max_vel_theta",
        "min_speed_xy": "min_vel_trans", "max_speed_xy": "max_vel_trans",
        "min_speed_theta": "min_vel_theta", "acc_lim_x": "acc_lim_x", "acc_lim_y": "acc_lim_y",
        "acc_lim_theta": "acc_lim_theta", "vx_samples": "vx_samples", "vy_samples": "vy_samples",
        "vtheta_samples": "vth_samples", "sim_time": "sim_time",
        "linear_granularity": "sim_granularity", "angular_granularity": "angular_sim_granularity",
        "trans_stopped_velocity": "trans_stopped_vel", "xy_goal_tolerance": "xy_goal_tolerance",
        "prune_plan": "prune_plan"}
# DWB critics whose scale is the DWA's weight of the same cost (dwa_planner.cpp): PathDist ->
# path_distance_bias, GoalDist -> goal_distance_bias, BaseObstacle -> occdist_scale,
# Twirling -> twirling_scale; the alignment critics' forward point is the DWA's.
_DWB_CRITICS = {("PathDist", "scale"): "path_distance_bias",
                ("GoalDist", "scale"): "goal_distance_bias",
                ("BaseObstacle", "scale"): "occdist_scale",
                ("ObstacleFootprint", "scale"): "occdist_scale",
                ("Twirling", "scale"): "twirling_scale",
                ("PathAlign", "forward_point_distance"): "forward_point_distance",
                ("GoalAlign", "forward_point_distance"): "forward_point_distance",
                ("Oscillation", "oscillation_reset_dist"): "oscillation_reset_dist",
                ("Oscillation", "oscillation_reset_angle"): "oscillation_reset_angle"}
# MPPI's limits -> DWA's (the sampler is not MPPI's: see the warning)
_MPPI = {"vx_max": "max_vel_x", "vx_min": "min_vel_x", "vy_max": "max_vel_y",
         "wz_max": "max_vel_theta", "ax_max": "acc_lim_x", "ay_max": "acc_lim_y",
         "az_max": "acc_lim_theta"}

_TREES = {"navigate_to_pose_w_replanning_and_recovery.xml": "nav2",
          "navigate_w_replanning_and_recovery.xml": "nav2"}

_NAV2_BT_LIBS = {"nav2_compute_path_to_pose_action_bt_node": "ComputePathToPose",
                 "nav2_follow_path_action_bt_node": "FollowPath",
                 "nav2_spin_action_bt_node": "Spin",
                 "nav2_wait_action_bt_node": "Wait", "nav2_back_up_action_bt_node": "BackUp",
                 "nav2_clear_costmap_service_bt_node": "ClearEntireCostmap",
                 "nav2_goal_reached_condition_bt_node": "GoalReached",
                 "nav2_goal_updated_condition_bt_node": "GoalUpdated",
                 "nav2_rate_controller_bt_node": "RateController",
                 "nav2_recovery_node_bt_node": "RecoveryNode",
                 "nav2_pipeline_sequence_bt_node": "PipelineSequence",
                 "nav2_round_robin_node_bt_node": "RoundRobin",
                 "nav2_is_stuck_condition_bt_node": "IsStuck",
                 "nav2_drive_on_heading_bt_node": "DriveOnHeading",
                 "nav2_distance_controller_bt_node": "DistanceController",
                 "nav2_speed_controller_bt_node": "SpeedController",
                 "nav2_goal_updater_node_bt_node": "GoalUpdater",
                 "nav2_truncate_path_action_bt_node": "TruncatePath",
                 "nav2_single_trigger_bt_node": "SingleTrigger",
                 "nav2_is_path_valid_condition_bt_node": "IsPathValid",
                 "nav2_time_expired_condition_bt_node": "TimeExpired",
                 "nav2_distance_traveled_condition_bt_node": "DistanceTraveled",
                 "nav2_goal_updated_controller_bt_node": "GoalUpdatedController",
                 "nav2_initial_pose_received_condition_bt_node": "InitialPoseReceived",
                 "nav2_reinitialize_global_localization_service_bt_node":
                     "ReinitializeGlobalLocalization"}


class _Mapper:
    def __init__(self, file: str, lines: Mapping[Path_, int]) -> None:
        self.file = file
        self.lines = lines
        self.out = Converted()
        self.ignored: dict[str, list[str]] = {}

    def where(self, path: Path_) -> str:
        line = nearest(self.lines, path)
        return self.file if line is None else f"{self.file}:{line}"

    def put(self, dst: Path_, value: Any, src: Path_) -> None:
        self.out.put(dst, value, self.where(src))
        self.out.origins[dst] = self.where(src)

    def ignore(self, group: str, key: str) -> None:
        self.ignored.setdefault(group, []).append(key)

    def note(self, level: str, src: Path_, text: str) -> None:
        self.out.notes.append(Note(level, self.where(src), text))

    # ------------------------------------------------------------ servers
    def amcl(self, p: Mapping[str, Any], src: Path_) -> None:
        for k, v in p.items():
            s = src + (k,)
            if k in _AMCL:
                self.put(("amcl", _AMCL[k]), v, s)
            elif k in _AMCL_SAME:
                self.put(("amcl", k), v, s)
            elif k == "robot_model_type":
                model = _MOTION_MODELS.get(str(v))
                if model is None:
                    self.note("warning", s, f"amcl: robot_model_type '{v}' has no counterpart; "
                                            "the differential model is used")
                else:
                    self.put(("amcl", "odom_model_type"), model, s)
            elif k == "initial_pose" and isinstance(v, Mapping) and p.get("set_initial_pose"):
                for a, b in (("x", "initial_pose_x"), ("y", "initial_pose_y"),
                             ("yaw", "initial_pose_a")):
                    if a in v:
                        self.put(("amcl", b), v[a], s + (a,))
            else:
                self.ignore("amcl", k)

    def costmap(self, name: str, p: Mapping[str, Any], src: Path_) -> None:
        from navcore.costmap.layered import COSTMAP_PARAMS
        top = {q.name for q in COSTMAP_PARAMS} | {"footprint", "plugins"}
        plugins = p.get("plugins")
        names = [str(x) for x in plugins] if isinstance(plugins, list) else []
        filters = p.get("filters")
        filters = [str(x) for x in filters] if isinstance(filters, list) else []
        kept = []
        for layer in names:
            body = p.get(layer)
            kind = str(body.get("plugin", "")) if isinstance(body, Mapping) else ""
            if kind.rpartition("::")[2] not in _LAYER_TYPES:
                self.note("warning", src + (layer,), f"{name}: layer '{layer}' ({kind}) has no "
                                                     "counterpart in navbt and is left out")
                continue
            kept.append(layer)
        for k, v in p.items():
            s = src + (k,)
            if k == "plugins":
                self.put((name, "plugins"), kept, s)
            elif k == "filters" or k in filters:
                self.ignore(f"{name} costmap filters", k)
            elif k in names and isinstance(v, Mapping):
                if k in kept:
                    self.layer(name, k, v, s)
            elif isinstance(v, Mapping):
                self.put((name, k), dict(v), s)   # an unused layer: the loader notes it
            elif k in top:
                self.put((name, k), v, s)
            else:
                self.ignore(name, k)

    def layer(self, cm: str, layer: str, p: Mapping[str, Any], src: Path_) -> None:
        sources = str(p.get("observation_sources", "")).split()
        for k, v in p.items():
            s = src + (k,)
            if k in sources and isinstance(v, Mapping):
                for sk, sv in v.items():
                    if sk in _SOURCE:
                        self.put((cm, layer, k, _SOURCE[sk]), sv, s + (sk,))
                    elif sk in _SOURCE_MIN:
                        if sv:
                            self.note("warning", s + (sk,), f"{cm}/{layer}/{k}: '{sk}' = {sv}: "
                                      "navbt marks and clears from the sensor (0)")
                        else:
                            self.ignore(f"{cm}/{layer}/{k}", sk)
                    elif sk in ("clearing", "marking", "data_type", "min_obstacle_height",
                                "max_obstacle_height", "inf_is_valid", "expected_update_rate",
                                "observation_persistence", "topic", "sensor_frame"):
                        self.put((cm, layer, k, sk), sv, s + (sk,))
                    else:
                        self.ignore(f"{cm}/{layer}/{k}", sk)
            elif k in ("map_subscribe_transient_local", "inflate_around_unknown"):
                self.ignore(f"{cm}/{layer}", k)
            else:
                self.put((cm, layer, k), v, s)

    def planner(self, p: Mapping[str, Any], src: Path_) -> None:
        ids = _names(p.get("planner_plugins"), "GridBased")
        for k, v in p.items():
            if k == "planner_plugins" or k in ids[:1]:
                continue
            self.ignore("planner_server" + (" (only the first planner id is used)"
                                            if k in ids else ""), k)
        for pid in ids:
            body = p.get(pid) if isinstance(p.get(pid), Mapping) else {}
            s = src + (pid,)
            kind = str(body.get("plugin", ""))
            if "navfn" in kind.lower():
                self.put(("move_base", "base_global_planner"), "navfn/NavfnROS", s)
                for k, v in body.items():
                    if k == "tolerance":
                        self.put(("NavfnROS", "default_tolerance"), v, s + (k,))
                    elif k == "allow_unknown":
                        self.put(("NavfnROS", "allow_unknown"), v, s + (k,))
                    elif k == "use_astar" and v:
                        self.note("warning", s + (k,), "planner_server: NavFn's A* is not "
                                  "available; its Dijkstra wavefront plans (same cost, the path "
                                  "may differ where costs tie)")
                    elif k not in ("plugin", "use_astar"):
                        self.ignore(f"planner_server/{pid}", k)
            else:
                self.note("warning", s, f"planner_server: '{pid}' ({kind or 'no plugin'}) is not "
                                        "available in navbt (Smac, Theta* ...): NavfnROS plans "
                                        "instead")
                if "tolerance" in body:
                    self.put(("NavfnROS", "default_tolerance"), body["tolerance"],
                             s + ("tolerance",))
                if "allow_unknown" in body:
                    self.put(("NavfnROS", "allow_unknown"), body["allow_unknown"],
                             s + ("allow_unknown",))
            break  # the first planner id is the one the default trees use

    def controller(self, p: Mapping[str, Any], src: Path_) -> None:
        ids = _names(p.get("controller_plugins"), "FollowPath")
        goal_checkers = p.get("goal_checker_plugins") or [p.get("goal_checker_plugin")]
        skip = {"controller_plugins", "goal_checker_plugins", "goal_checker_plugin",
                "progress_checker_plugins", "progress_checker_plugin"}
        for k, v in p.items():
            s = src + (k,)
            if k == "controller_frequency":
                self.put(("move_base", "controller_frequency"), v, s)
                self.put(("DWAPlannerROS", "controller_frequency"), v, s)
            elif k in skip or k in ids[:1]:
                continue
            elif k in ids:
                self.ignore("controller_server (only the first controller id is used)", k)
            elif k in goal_checkers and isinstance(v, Mapping):
                for gk, gv in v.items():
                    if gk in ("xy_goal_tolerance", "yaw_goal_tolerance"):
                        self.put(("DWAPlannerROS", gk), gv, s + (gk,))
                    elif gk == "stateful":
                        self.put(("DWAPlannerROS", "latch_xy_goal_tolerance"), gv, s + (gk,))
                    elif gk != "plugin":
                        self.ignore(f"controller_server/{k}", gk)
            else:
                self.ignore("controller_server", k)
        self.put(("move_base", "base_local_planner"), "dwa_local_planner/DWAPlannerROS", src)
        pid = ids[0]
        body = p.get(pid) if isinstance(p.get(pid), Mapping) else {}
        kind = str(body.get("plugin", ""))
        s = src + (pid,)
        if "dwb" in kind.lower():
            self.dwb(body, s)
        elif "mppi" in kind.lower():
            self.note("warning", s, f"controller_server: {kind} is not available in navbt: the "
                                    "DWA (DWAPlannerROS) follows the path with MPPI's velocity "
                                    "and acceleration limits; MPPI's critics are not used")
            self.limits(body, s, _MPPI, "MPPI", body.get("motion_model", "DiffDrive"))
        elif "regulated_pure_pursuit" in kind.lower() or "rotation_shim" in kind.lower():
            self.note("warning", s, f"controller_server: {kind} is not available in navbt: the "
                                    "DWA follows the path with its speed limits")
            lim = {"desired_linear_vel": "max_vel_x", "rotate_to_heading_angular_vel":
                   "max_vel_theta", "max_angular_accel": "acc_lim_theta"}
            self.limits(body, s, lim, "RPP", "DiffDrive")
        else:
            self.note("warning", s, f"controller_server: '{pid}' ({kind or 'no plugin'}) is not "
                                    "available in navbt: the DWA follows the path with its "
                                    "defaults")

    def dwb(self, body: Mapping[str, Any], src: Path_) -> None:
        critics = [str(c) for c in body.get("critics", [])]
        for k, v in body.items():
            s = src + (k,)
            head, dot, tail = k.partition(".")
            if k in _DWB:
                self.put(("DWAPlannerROS", _DWB[k]), v, s)
            elif dot and (head, tail) in _DWB_CRITICS:
                self.put(("DWAPlannerROS", _DWB_CRITICS[(head, tail)]), v, s)
            elif k in critics and isinstance(v, Mapping):
                for ck, cv in v.items():
                    if (k, ck) in _DWB_CRITICS:
                        self.put(("DWAPlannerROS", _DWB_CRITICS[(k, ck)]), cv, s + (ck,))
                    else:
                        self.ignore("controller_server/DWB critics", f"{k}.{ck}")
            elif dot:
                self.ignore("controller_server/DWB critics", k)
            elif k not in ("plugin", "critics"):
                self.ignore("controller_server/DWB", k)
        mapped = {c for c, _ in _DWB_CRITICS}
        unmapped = [c for c in critics if c not in mapped]
        if unmapped:
            self.note("note", src + ("critics",), "controller_server: the DWA scores path "
                      "distance, goal distance, obstacle cost and twirling; DWB critics "
                      f"{', '.join(unmapped)} have no DWA counterpart")

    def limits(self, body: Mapping[str, Any], src: Path_, table: Mapping[str, str],
               what: str, motion: Any) -> None:
        for k, v in body.items():
            if k in table:
                if k == "vy_max" and str(motion) != "Omni":
                    continue
                self.put(("DWAPlannerROS", table[k]), v, src + (k,))
            elif k != "plugin":
                self.ignore(f"controller_server/{what}", k)
        if str(motion) != "Omni":
            for k, v in (("max_vel_y", 0.0), ("min_vel_y", 0.0), ("vy_samples", 1)):
                self.put(("DWAPlannerROS", k), v, src)
        if "max_vel_x" in table.values() and "vx_max" in body:
            self.put(("DWAPlannerROS", "max_vel_trans"), body["vx_max"], src + ("vx_max",))
        if what == "RPP" and "desired_linear_vel" in body:
            self.put(("DWAPlannerROS", "max_vel_trans"), body["desired_linear_vel"],
                     src + ("desired_linear_vel",))

    def bt_navigator(self, p: Mapping[str, Any], src: Path_) -> None:
        for k, v in p.items():
            s = src + (k,)
            if k in ("default_nav_to_pose_bt_xml", "default_bt_xml_filename"):
                base = os.path.basename(str(v))
                tree = _TREES.get(base)
                self.note("note", s, f"bt_navigator: {k} = {v}: " + (
                    f"navbt ships it as trees/{tree}.yaml (mission run trees/{tree}.yaml)"
                    if tree else "give this tree file to mission run (Nav2 XML loads as is)"))
            elif k == "plugin_lib_names" and isinstance(v, list):
                from behaviors.registry import node_classes
                known = set(node_classes())
                missing = [lib for lib in v if _NAV2_BT_LIBS.get(str(lib)) not in known]
                if missing:
                    self.note("note", s, "bt_navigator: plugin libraries without a navbt node "
                                         f"(trees using their nodes will not load): "
                                         f"{', '.join(map(str, missing))}")
            else:
                self.ignore("bt_navigator", k)

    def behavior_server(self, p: Mapping[str, Any], src: Path_) -> None:
        """Its motion limits are the recovery nodes' ports of the same names here
        (``behavior_server`` namespace: used where the tree leaves those ports unset)."""
        names = {q.name for q in BEHAVIOR_SERVER_PARAMS}
        for k, v in p.items():
            if k in names:
                self.put(("behavior_server", k), v, src + (k,))
            else:
                self.ignore("behavior_server", k)

    def velocity_smoother(self, p: Mapping[str, Any], src: Path_) -> None:
        for k, v in p.items():
            s = src + (k,)
            if k == "max_velocity" and isinstance(v, list) and len(v) == 3:
                self.put(("safety", "max_vel_x"), abs(float(v[0])), s)
                self.put(("safety", "max_vel_y"), abs(float(v[1])), s)
                self.put(("safety", "max_vel_theta"), abs(float(v[2])), s)
            elif k == "min_velocity" and isinstance(v, list) and len(v) == 3:
                self.put(("safety", "min_vel_x"), min(0.0, float(v[0])), s)
            else:
                self.ignore("velocity_smoother", k)

    def collision_monitor(self, p: Mapping[str, Any], src: Path_) -> None:
        for k, v in p.items():
            if k == "source_timeout":
                # no fresh sensor data for this long: the robot stops (as the gate's watchdog)
                self.put(("safety", "sensor_timeout"), v, src + (k,))
            else:
                self.ignore("collision_monitor", k)


def _names(value: Any, default: str) -> list[str]:
    """A Nav2 plugin id list (a list, or one name), the default id when absent or empty."""
    if isinstance(value, str):
        return [value]
    if isinstance(value, list) and value:
        return [str(v) for v in value]
    return [default]


def _nodes(doc: Any, path: Path_ = ()) -> list[tuple[str, Path_, Mapping[str, Any]]]:
    """(node name, path of its ros__parameters, parameters) for every node in the file."""
    out = []
    if isinstance(doc, Mapping):
        for k, v in doc.items():
            if k == "ros__parameters" and isinstance(v, Mapping):
                out.append((path[-1] if path else "", path + (k,), v))
            elif isinstance(v, Mapping):
                out += _nodes(v, path + (str(k),))
    return out


def read_nav2_params(path: str | os.PathLike) -> Converted:
    """A Nav2 ``nav2_params.yaml`` as navbt config namespaces, with notes and ignored keys."""
    file = str(path)
    read_notes: list[Note] = []
    doc, lines = read_ros_yaml(file, read_notes)
    nodes = _nodes(doc)
    if not nodes:
        raise ParamsError(f"{file}: no 'ros__parameters' found: not a Nav2 parameter file "
                          "(a ROS 1 file loads with --params)")
    m = _Mapper(file, lines)
    m.out.notes += read_notes
    handlers = {"amcl": m.amcl, "planner_server": m.planner, "controller_server": m.controller,
                "bt_navigator": m.bt_navigator, "velocity_smoother": m.velocity_smoother,
                "behavior_server": m.behavior_server,
                "collision_monitor": m.collision_monitor}
    whole: list[str] = []
    for name, src, params in nodes:
        params = dict(params)
        if "use_sim_time" in params:
            params.pop("use_sim_time")
            m.ignore(name, "use_sim_time")
        if name in ("global_costmap", "local_costmap"):
            m.costmap(name, params, src)
        elif name in handlers:
            handlers[name](params, src)
        else:
            whole.append(name or "/**")
    if whole:
        m.ignored.setdefault("servers navbt does not run", []).extend(whole)
    if m.ignored:
        groups = [f"{g}: {', '.join(keys)}" for g, keys in m.ignored.items()]
        m.out.notes.append(Note("ignored", file, "no counterpart in navbt: "
                                + "; ".join(groups)))
    return m.out
