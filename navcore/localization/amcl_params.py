"""Every amcl parameter with its *effective* ROS 1 default (the node code's, see the parity warning:
amcl ignores the first dynamic_reconfigure call, so e.g. recovery_alpha_slow/fast are 0.001/0.1).

Frame ids, tf and publishing-rate parameters are declared too so that a user's amcl YAML loads
unchanged; they have no effect on the filter itself.
"""

from __future__ import annotations

import math

from navcore.params import Param

LASER_MODELS = ("beam", "likelihood_field", "likelihood_field_prob")
ODOM_MODELS = ("diff", "omni", "diff-corrected", "omni-corrected")

# Limit (docs/limits.md): the filter allocates arrays of max_particles poses and weights.
MAX_PARTICLES = 100_000

AMCL_PARAMS: tuple[Param, ...] = (
    # overall filter
    Param("min_particles", 100, int, "minimum number of particles", min=1, max=MAX_PARTICLES),
    Param("max_particles", 5000, int, "maximum number of particles", min=1, max=MAX_PARTICLES),
    Param("kld_err", 0.01, float, "max error between true and estimated distribution (KLD)",
          min=1e-9, max=1.0),
    Param("kld_z", 0.99, float, "KLD quantile; used literally as z like amcl's pf.c", min=0.0),
    Param("update_min_d", 0.2, float, "translation (m) needed before a filter update", min=0.0),
    Param("update_min_a", math.pi / 6.0, float, "rotation (rad) needed before a filter update",
          min=0.0),
    Param("resample_interval", 2, int, "filter updates between resamplings", min=1),
    Param("transform_tolerance", 0.1, float, "post-dating of the published transform (s)", min=0.0),
    Param("recovery_alpha_slow", 0.001, float, "decay of the slow average weight (0 disables)",
          min=0.0, max=1.0),
    Param("recovery_alpha_fast", 0.1, float, "decay of the fast average weight (0 disables)",
          min=0.0, max=1.0),
    Param("selective_resampling", False, bool, "resample only when N_eff < N/2"),
    Param("initial_pose_x", 0.0, float, "initial pose mean x (m)"),
    Param("initial_pose_y", 0.0, float, "initial pose mean y (m)"),
    Param("initial_pose_a", 0.0, float, "initial pose mean yaw (rad)"),
    Param("initial_cov_xx", 0.5 * 0.5, float, "initial covariance x*x (m^2)", min=0.0),
    Param("initial_cov_yy", 0.5 * 0.5, float, "initial covariance y*y (m^2)", min=0.0),
    Param("initial_cov_aa", (math.pi / 12.0) ** 2, float, "initial covariance yaw*yaw (rad^2)",
          min=0.0),
    Param("gui_publish_rate", -1.0, float, "visualisation publish rate (Hz), -1 off"),
    Param("save_pose_rate", 0.5, float, "rate of storing the pose to parameters (Hz), -1 off"),
    Param("use_map_topic", False, bool, "take the map from a topic (no effect here)"),
    Param("first_map_only", False, bool, "ignore later maps (no effect here)"),
    # laser model
    Param("laser_min_range", -1.0, float, "minimum range used; -1 takes the scan's range_min"),
    Param("laser_max_range", -1.0, float, "maximum range used; -1 takes the scan's range_max"),
    Param("laser_max_beams", 30, int, "evenly spaced beams used per scan", min=2),
    Param("laser_z_hit", 0.95, float, "mixture weight of the hit part", min=0.0),
    Param("laser_z_short", 0.1, float, "mixture weight of the short part (beam model)", min=0.0),
    Param("laser_z_max", 0.05, float, "mixture weight of the max-range part (beam model)", min=0.0),
    Param("laser_z_rand", 0.05, float, "mixture weight of the random part", min=0.0),
    Param("laser_sigma_hit", 0.2, float, "std dev of the hit Gaussian (m)", min=1e-6),
    Param("laser_lambda_short", 0.1, float, "decay of the short part (beam model)", min=0.0),
    Param("laser_likelihood_max_dist", 2.0, float, "distance field cap (m), likelihood field",
          min=0.0),
    Param("laser_model_type", "likelihood_field", str, "beam, likelihood_field or "
          "likelihood_field_prob", choices=LASER_MODELS),
    Param("do_beamskip", False, bool, "skip beams that disagree with the map (LF-prob only)"),
    Param("beam_skip_distance", 0.5, float, "hit within this of an obstacle counts (m)", min=0.0),
    Param("beam_skip_threshold", 0.3, float, "fraction of particles that must agree", min=0.0,
          max=1.0),
    Param("beam_skip_error_threshold", 0.9, float, "skipped fraction above which all are used",
          min=0.0, max=1.0),
    # odometry model
    Param("odom_model_type", "diff", str, "diff, omni, diff-corrected or omni-corrected",
          choices=ODOM_MODELS),
    Param("odom_alpha1", 0.2, float, "rotation noise from rotation", min=0.0),
    Param("odom_alpha2", 0.2, float, "rotation noise from translation", min=0.0),
    Param("odom_alpha3", 0.2, float, "translation noise from translation", min=0.0),
    Param("odom_alpha4", 0.2, float, "translation noise from rotation", min=0.0),
    Param("odom_alpha5", 0.2, float, "strafe noise from translation (omni)", min=0.0),
    Param("odom_frame_id", "odom", str, "odometry frame"),
    Param("base_frame_id", "base_link", str, "robot base frame"),
    Param("global_frame_id", "map", str, "map frame"),
    Param("tf_broadcast", True, bool, "publish map -> odom"),
)
