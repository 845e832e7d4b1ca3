"""The kernels as plain Python: the reference tests of the planner, costmap, controller, AMCL,
simulator and driver kernels run again in a subprocess with ``NUMBA_DISABLE_JIT=1``.

With the JIT off every ``@njit`` function is the Python function it decorates, so these runs
check that the kernels are valid Python with the compiled semantics (no LLVM intrinsics, no
integer wraparound or float32 promotion that only numba gives) and that the plain references
the tests compare against are met either way. The selection keeps to small maps: plain Python
is about a hundred times slower than the compiled kernels.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# node ids (or prefixes of them), one area per block
SELECTED = [
    # planners: the wavefront and path extraction against their plain references
    "tests/test_planners.py::test_wavefront_kernel_matches_the_plain_reference",
    "tests/test_planners.py::test_wavefront_leaves_the_gate_idle_and_reused_buffers_give_fresh_"
    "results",
    "tests/test_planners.py::test_gradient_path_matches_the_plain_reference",
    "tests/test_planners.py::test_dijkstra_and_astar_costs_are_optimal_on_random_grids",
    "tests/test_planners.py::test_cell_coordinates_from_the_reciprocal_match_integer_division",
    "tests/test_planners.py::test_replan_repairs_to_the_from_scratch_field_on_random_changes",
    "tests/test_planners.py::test_goal_rooted_quadratic_field_is_the_order_free_fixed_point[plain]",
    "tests/test_planners.py::test_reuse_search_replans_by_repair_with_the_fresh_path",
    # costmap: footprint rasterisation, grid kernels, inflation
    "tests/test_costmap_footprint.py",
    "tests/test_costmap_grid.py",
    "tests/test_costmap_layered.py::test_rolling_static_sampling_equals_the_per_cell_centre_"
    "lookup_on_random_windows",
    "tests/test_costmap_layered.py::test_scan_points_are_the_valid_beam_ends_in_beam_order",
    "tests/test_costmap_layered.py::test_observations_keep_the_finite_points_within_the_source_"
    "heights",
    "tests/test_costmap_layered.py::test_scan_and_observation_filters_give_empty_arrays_when_"
    "nothing_is_valid",
    "tests/test_costmap_inflation.py::test_inflation_agrees_with_brute_force_on_random_small_maps",
    "tests/test_costmap_inflation.py::test_exact_distance_transform_matches_brute_force",
    "tests/test_costmap_inflation.py::test_inflated_costs_equal_the_formula_around_one_obstacle",
    # observed-space memory
    "tests/test_observed_space.py::test_stamp_scan_matches_the_plain_reference",
    "tests/test_observed_space.py::test_stamp_scan_stamps_the_cells_the_per_beam_raytrace_stamped",
    "tests/test_observed_space.py::test_fan_angles_are_the_scans_angles_turned_bit_for_bit",
    "tests/test_observed_space.py::test_update_stamps_what_the_window_move_the_raytrace_scan_and_"
    "the_body_stamp_stamp",
    "tests/test_observed_space.py::test_free_body_matches_the_numpy_reference",
    "tests/test_observed_space.py::test_the_window_moves_as_shift_grid_moves_a_copy",
    # controllers
    "tests/test_controllers_rollout.py::test_start_footprint_cells_agree_with_the_numpy_even_odd_"
    "test_on_random_poses",
    "tests/test_controllers_rollout.py::test_boxed_in_it_backs_off_at_escape_vel",
    "tests/test_controllers_rollout.py::test_holonomic_robot_samples_strafes",
    "tests/test_controllers_rollout.py::test_start_footprint_cells_are_its_inside",
    # DWA (the default local planner): its kernels one by one, then whole cycles
    "tests/test_controllers_dwa.py::test_velocity_iterator_matches_ros_sampling",
    "tests/test_controllers_dwa.py::test_filter_refuses_slow_fast_and_still_samples",
    "tests/test_controllers_dwa.py::test_simulate_constant_arc_and_ramped_velocity",
    "tests/test_controllers_dwa.py::test_distance_grid_is_4_connected_bfs_with_obstacle_and_"
    "unreachable_values",
    "tests/test_controllers_dwa.py::test_distance_grid_agrees_with_a_plain_wavefront_on_random_"
    "maps",
    "tests/test_controllers_dwa.py::test_plan_densified_cut_and_seeded_as_ros_does",
    "tests/test_controllers_dwa.py::test_local_plan_is_the_first_run_of_poses_inside_on_random_"
    "plans",
    "tests/test_controllers_dwa.py::test_fused_grid_critics_equal_the_critic_chain",
    "tests/test_controllers_dwa.py::test_branch_and_bound_picks_what_exhaustive_scoring_picks",
    "tests/test_controllers_dwa.py::test_footprint_bound_skips_rasterising_without_changing_any_"
    "score[0]",
    "tests/test_controllers_dwa.py::test_wall_across_the_path_stops_the_robot_with_a_reason",
    "tests/test_controllers_dwa.py::test_holonomic_sampling_uses_vy_and_differential_does_not",
    "tests/test_controllers_dwa.py::test_at_the_goal_position_it_brakes_then_rotates_to_the_goal_"
    "yaw",
    "tests/test_controllers_dwa.py::test_rolling_costmap_origin_is_read_every_cycle",
    # the observed-space memory, goal substitution, path progress, exact clearance
    "tests/test_observed_space.py::test_first_unobserved_matches_the_sampled_reference",
    "tests/test_observed_space.py::test_backup_goes_into_space_seen_free_a_second_ago_and_stops_"
    "at_a_seen_box",
    "tests/test_observed_space.py::test_follow_path_turns_instead_of_reversing_blind_and_reverses_"
    "where_it_has_looked",
    "tests/test_free_goal.py::test_label_free_kernel_matches_the_reference",
    "tests/test_free_goal.py::test_a_free_goal_is_kept_and_an_occupied_one_moves_to_the_reachable_"
    "side",
    "tests/test_motion.py",
    "tests/test_progress.py",
    "tests/test_costmap_clearance.py",
    "tests/test_costmap_layered.py::test_voxel_layer_marks_in_3d_and_clears_along_3d_rays",
    "tests/test_costmap_layered.py::test_a_scan_marks_and_a_later_scan_that_sees_through_clears",
    # AMCL (all but the closed-loop tracking run) and its map-agreement check
    "tests/test_amcl.py",
    "tests/test_localization_map_agreement.py::test_endpoint_distances_match_a_brute_force_search_"
    "on_random_points",
    # the drivers' byte-stream kernels (SCIP decoding, the LMS CRC)
    "tests/test_hw_scip.py",
    "tests/test_hw_lms2xx.py::test_crc_matches_reference",
    "tests/test_hw_lms2xx.py::test_scan_round_trip",
    "tests/test_hw_lms2xx.py::test_every_single_byte_corruption_is_rejected",
    # simulator and its ray casting
    "tests/test_sim_motion.py",
    "tests/test_sim_sensors.py::test_ranges_in_a_box_world_match_the_analytic_distances",
    "tests/test_sim_sensors.py::test_odometry_twist_covariance_is_the_alpha_model_over_one_period",
    "tests/test_raycast.py::test_box_world_ranges_are_exact_to_the_cell_faces",
    "tests/test_raycast.py::test_matches_a_fine_brute_force_march_in_clutter",
    "tests/test_raycast.py::test_fan_casting_from_cell_faces_and_corners_along_the_axes",
    "tests/test_raycast.py::test_distance_field_matches_brute_force",
]
DESELECTED = [
    "tests/test_amcl.py::test_tracks_a_robot_driving_through_rooms_from_an_offset_start",
]


def test_kernel_tests_pass_with_the_jit_disabled() -> None:
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:warnings",
           "-o", "addopts=", *SELECTED]
    for d in DESELECTED:
        cmd += ["--deselect", d]
    out = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=900)
    tail = (out.stdout + out.stderr)[-4000:]
    assert out.returncode == 0, tail
    passed = re.search(r"(\d+) passed", out.stdout)
    assert passed and int(passed.group(1)) >= 170, tail
