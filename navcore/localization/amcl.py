"""AMCL: adaptive (KLD-sampling) Monte Carlo localisation with amcl's semantics.

One ``update`` is amcl's ``laserReceived``: it is gated by ``update_min_d``/``update_min_a`` on the
odometry delta; when it fires, the odometry motion model moves the particles, the laser model
weights them, and every ``resample_interval``-th update resamples (systematic, O(N), KLD-limited,
with augmented-MCL random poses when ``recovery_alpha_slow/fast`` say the fit got worse). The
output is the mean of the heaviest cluster, the set covariance and the map -> odom correction.

Deviations from amcl, all deliberate: systematic resampling instead of the O(N^2) CDF scan; cluster
statistics refreshed after every update (amcl only after resampling); map cells follow the
map_server convention (amcl's own grid is shifted by half a cell); random poses are uniform inside
free cells rather than at their centres.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from navcore.localization.amcl_params import AMCL_PARAMS
from navcore.localization.clusters import cluster_stats
from navcore.localization.distance_field import distance_field
from navcore.localization.laser_models import (cube_table, hit_table, likelihood_field,
                                                likelihood_field_prob)
from navcore.localization.motion_models import MODEL_CODES, sample_motion
from navcore.localization.resampling import kld_resample
from navcore.maps import FREE, OccupancyGrid
from navcore.params import Parameters
from navcore.types import LaserScan, Pose2D, angle_diff

_EMPTY_BOOL = np.zeros(0, np.bool_)
_EMPTY_POSES = np.zeros((0, 3), np.float64)


class Amcl:
    """Particle-filter localisation on an OccupancyGrid (implements behaviors' Localizer).

    ``params`` are amcl's ROS parameters (``AMCL_PARAMS``; unknown names raise ParameterError);
    ``rng`` is the only source of randomness. The filter starts as amcl does: a Gaussian of
    ``max_particles`` around ``initial_pose_*`` with ``initial_cov_*``.
    """

    def __init__(self, grid: OccupancyGrid, params: Mapping[str, Any] | None,
                 rng: np.random.Generator) -> None:
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"Amcl: rng must be a numpy.random.Generator, got {type(rng).__name__}")
        self.params = Parameters(AMCL_PARAMS, params, where="amcl")
        if self.params.min_particles > self.params.max_particles:
            raise ValueError(f"amcl: min_particles {self.params.min_particles} > max_particles "
                             f"{self.params.max_particles}")
        self._rng = rng
        self._w_slow = 0.0
        self._w_fast = 0.0
        self._resample_count = 0
        self._odom: Pose2D | None = None  # odometry pose the particles were last moved to
        self._odom_sensor: Pose2D | None = None  # odometry pose at the last scan update
        self._force_update = False
        self.converged = False
        self.n_effective = 0.0
        self.updates = 0  # sensor updates done
        self.last_error = ""  # why the last update() was refused, if it was
        self.set_map(grid)
        p = self.params
        cov = np.diag([p.initial_cov_xx, p.initial_cov_yy, p.initial_cov_aa])
        self.set_initial_pose(Pose2D(p.initial_pose_x, p.initial_pose_y, p.initial_pose_a), cov)

    # ----------------------------------------------------------------- map and initialisation
    def set_map(self, grid: OccupancyGrid) -> None:
        """Use a new map (amcl's set_map service keeps the particles; call set_initial_pose or
        global_localization to move them)."""
        if not isinstance(grid, OccupancyGrid):
            raise TypeError(f"amcl: set_map needs an OccupancyGrid, got {type(grid).__name__}")
        free = np.flatnonzero(grid.data.ravel() == FREE)
        if free.size == 0:
            raise ValueError("amcl: the map has no free cell to localise in")
        self.grid = grid
        o = grid.origin
        self._geom = np.array([o.x, o.y, math.cos(o.theta), math.sin(o.theta), grid.resolution])
        self._free = free
        self._dist_for = -1.0
        self._dist = np.zeros((1, 1), np.float32)
        self._clear: np.ndarray | None = None  # beam model ray-casting grid, built on demand
        self._table_for: tuple = ()
        self._ensure_distance_field()

    def _ensure_distance_field(self) -> None:
        d = float(self.params.laser_likelihood_max_dist)
        if d != self._dist_for:
            self._dist = distance_field(self.grid.data, self.grid.resolution, d)
            self._dist_for = d

    def set_initial_pose(self, pose: Pose2D, cov: np.ndarray) -> None:
        """Re-seed ``max_particles`` from a Gaussian around ``pose`` (3x3 x, y, yaw covariance)."""
        cov = np.asarray(cov, dtype=np.float64)
        if cov.shape != (3, 3) or not np.all(np.isfinite(cov)):
            raise ValueError(f"amcl: initial covariance must be a finite 3x3 array, got {cov!r}")
        cov = 0.5 * (cov + cov.T)
        vals, vecs = np.linalg.eigh(cov)
        if vals.min() < -1e-9:
            raise ValueError(f"amcl: initial covariance is not positive semi-definite "
                             f"(eigenvalues {vals})")
        n = self.params.max_particles
        z = self._rng.standard_normal((n, 3)) * np.sqrt(np.clip(vals, 0.0, None))
        parts = z @ vecs.T + np.array([pose.x, pose.y, pose.theta])
        parts[:, 2] = (parts[:, 2] + math.pi) % (2 * math.pi) - math.pi
        self._reset(parts)

    def global_localization(self) -> None:
        """Spread ``max_particles`` uniformly over the free space of the map."""
        self._reset(self._random_poses(self.params.max_particles))

    def request_nomotion_update(self) -> None:
        """Make the next ``update`` integrate its scan even if the robot has not moved."""
        self._force_update = True

    def _reset(self, parts: np.ndarray) -> None:
        self.particles = np.ascontiguousarray(parts, dtype=np.float64)
        self.weights = np.full(len(parts), 1.0 / len(parts))
        self._w_slow = self._w_fast = 0.0
        # like amcl's pf_init_ = false: the next scan is integrated without motion
        self._odom = None
        self._odom_sensor = None
        self._resample_count = 0
        self._refresh_clusters()

    def _random_poses(self, n: int) -> np.ndarray:
        g = self.grid
        cells = self._free[self._rng.integers(0, len(self._free), n)]
        lx = (cells % g.width + self._rng.random(n)) * g.resolution
        ly = (cells // g.width + self._rng.random(n)) * g.resolution
        c, s = self._geom[2], self._geom[3]
        out = np.empty((n, 3))
        out[:, 0] = self._geom[0] + c * lx - s * ly
        out[:, 1] = self._geom[1] + s * lx + c * ly
        out[:, 2] = self._rng.uniform(-math.pi, math.pi, n)
        return out

    # ----------------------------------------------------------------- the filter step
    def update(self, odom_pose: Pose2D, scan: LaserScan | None, laser_mount: Pose2D) -> bool:
        """One amcl laser callback. True when the filter was updated: the particles were moved
        to ``odom_pose`` and weighed with ``scan``. That happens when the odometry moved at least
        update_min_d (in x or y) or update_min_a since the last scan update, on the first scan
        after (re)initialisation, and after request_nomotion_update.

        With ``scan`` None this is ``predict(odom_pose)`` and returns False. A non-finite odometry
        pose or an unusable scan is refused (False, reason in ``last_error``), never raised:
        this runs in the control loop.
        """
        if not all(math.isfinite(v) for v in (odom_pose.x, odom_pose.y, odom_pose.theta)):
            self.last_error = f"odometry pose is not finite: {odom_pose}"
            return False
        if scan is None:
            self.predict(odom_pose)
            return False
        if not scan.range_max > 0.0 or len(scan.ranges) < 2:
            # a broken scan must not stop the control loop: skip it and say why
            self.last_error = (f"scan unusable: range_max {scan.range_max}, "
                               f"{len(scan.ranges)} ranges")
            return False
        p = self.params
        ref = self._odom_sensor
        if ref is not None and not self._force_update:
            if not (abs(odom_pose.x - ref.x) > p.update_min_d
                    or abs(odom_pose.y - ref.y) > p.update_min_d
                    or abs(angle_diff(odom_pose.theta, ref.theta)) > p.update_min_a):
                return False
        self.predict(odom_pose)
        self._odom_sensor = odom_pose
        self._force_update = False
        self._sensor_update(scan, laser_mount)
        self._resample_count += 1
        if self._resample_count % p.resample_interval == 0:
            self._resample()
        self._refresh_clusters()
        return True

    def predict(self, odom_pose: Pose2D) -> None:
        """Move the particles by the odometry since the last applied odometry pose (motion model
        only). amcl does this only when a scan is integrated; calling it for odometry that
        arrives between scans splits the motion into the short steps the noise model assumes."""
        last = self._odom
        self._odom = odom_pose
        if last is None:
            return  # first odometry after (re)initialisation: nothing to move by
        dx, dy = odom_pose.x - last.x, odom_pose.y - last.y
        dth = angle_diff(odom_pose.theta, last.theta)
        if dx == 0.0 and dy == 0.0 and dth == 0.0:
            return
        p = self.params
        alphas = np.array([p.odom_alpha1, p.odom_alpha2, p.odom_alpha3, p.odom_alpha4,
                           p.odom_alpha5])
        noise = self._rng.standard_normal((len(self.particles), 3))
        sample_motion(self.particles, last.theta, dx, dy, dth, alphas,
                      MODEL_CODES[p.odom_model_type], noise)

    def _beams(self, scan: LaserScan) -> tuple[np.ndarray, np.ndarray, float]:
        """Subsampled (ranges, bearings in the laser frame, range_max) as amcl prepares them."""
        p = self.params
        rmax = float(scan.range_max)
        if p.laser_max_range > 0.0:
            rmax = min(rmax, p.laser_max_range)
        rmin = float(scan.range_min)
        if p.laser_min_range > 0.0:
            rmin = max(rmin, p.laser_min_range)
        r = np.asarray(scan.ranges, dtype=np.float64).copy()
        r[r <= rmin] = rmax  # too-short readings count as "no return", like amcl
        n = len(r)
        if p.laser_model_type == "likelihood_field_prob":
            step = max(int(math.ceil(n / p.laser_max_beams)), 1)
        else:
            step = max((n - 1) // (p.laser_max_beams - 1), 1)
        idx = np.arange(0, n, step)
        bearings = scan.angle_min + scan.angle_increment * idx.astype(np.float64)
        return np.ascontiguousarray(r[idx]), bearings, rmax

    def _sensor_update(self, scan: LaserScan, mount: Pose2D) -> None:
        p = self.params
        ranges, bearings, rmax = self._beams(scan)
        m = np.array([mount.x, mount.y, mount.theta])
        model = p.laser_model_type
        if model == "beam":
            from navcore.localization.beam_model import beam_model  # only compiled when used
            if self._clear is None:
                from navcore.raycast import clearance_field
                self._clear = clearance_field(
                    np.ascontiguousarray(self.grid.data != FREE).view(np.uint8))
            total = beam_model(self.particles, self.weights, ranges, bearings, m, self._clear,
                               self._geom, p.laser_z_hit, p.laser_z_short, p.laser_z_max,
                               p.laser_z_rand, p.laser_sigma_hit, p.laser_lambda_short, rmax)
        else:
            self._ensure_distance_field()
            key = (p.laser_z_hit, p.laser_z_rand, p.laser_sigma_hit, rmax, self._dist_for)
            if key != self._table_for:
                self._table = hit_table(self._dist, p.laser_z_hit, p.laser_z_rand,
                                        p.laser_sigma_hit, rmax)
                self._cubes, self._cube_scale = cube_table(self._table)
                self._table_for = key
            d = self._dist_for
            # an end point off the map counts as max_occ_dist away from any obstacle
            off_map = p.laser_z_hit * math.exp(-d * d / (2 * p.laser_sigma_hit ** 2)) + \
                p.laser_z_rand / rmax
            if model == "likelihood_field":
                total = likelihood_field(self.particles, self.weights, ranges, bearings, m,
                                         self._cubes, self._cube_scale, self._geom, off_map,
                                         rmax)
            else:
                total = likelihood_field_prob(
                    self.particles, self.weights, ranges, bearings, m, self._table, self._dist,
                    self._geom, off_map, rmax, bool(p.do_beamskip and self.converged),
                    p.beam_skip_distance, p.beam_skip_threshold, p.beam_skip_error_threshold)
        n = len(self.weights)
        if total > 0.0 and math.isfinite(total):
            w_avg = total / n
            self.weights /= total
            self.n_effective = 1.0 / float(np.dot(self.weights, self.weights))
            self._w_slow = w_avg if self._w_slow == 0.0 else \
                self._w_slow + p.recovery_alpha_slow * (w_avg - self._w_slow)
            self._w_fast = w_avg if self._w_fast == 0.0 else \
                self._w_fast + p.recovery_alpha_fast * (w_avg - self._w_fast)
        else:
            self.weights[:] = 1.0 / n
            self.n_effective = float(n)
        self.updates += 1

    def _resample(self) -> None:
        p = self.params
        n = len(self.particles)
        if p.selective_resampling and self.n_effective > 0.5 * n:
            return
        m = p.max_particles
        w_diff = 0.0
        if self._w_slow > 0.0:
            w_diff = max(0.0, 1.0 - self._w_fast / self._w_slow)
        if w_diff > 0.0:
            is_random = self._rng.random(m) < w_diff
            poses = self._random_poses(int(is_random.sum()))
        else:
            is_random, poses = _EMPTY_BOOL, _EMPTY_POSES
        order = self._rng.permutation(m)
        self.particles = kld_resample(self.particles, self.weights, p.min_particles, m,
                                      p.kld_err, p.kld_z, float(self._rng.random()), order,
                                      is_random, poses)
        if w_diff > 0.0:
            self._w_slow = self._w_fast = 0.0
        self.weights = np.full(len(self.particles), 1.0 / len(self.particles))
        mean = self.particles[:, :2].mean(axis=0)
        self.converged = bool(np.all(np.abs(self.particles[:, :2] - mean) <= 0.5))

    def _refresh_clusters(self) -> None:
        cw, cm, mean, cov = cluster_stats(self.particles, self.weights)
        self.cluster_weights, self.cluster_means = cw, cm
        self._mean, self._cov = mean, cov
        best = cm[int(np.argmax(cw))]
        self._pose = Pose2D(float(best[0]), float(best[1]), float(best[2]))
        self._pose_odom = self._odom  # the odometry pose this estimate belongs to

    # ----------------------------------------------------------------- outputs
    def pose(self) -> Pose2D:
        """Estimated base pose in the map frame: the mean of the heaviest cluster."""
        return self._pose

    def covariance(self) -> np.ndarray:
        """3x3 (x, y, yaw) covariance of the whole particle set, as amcl publishes it."""
        return self._cov.copy()

    def map_to_odom(self) -> Pose2D:
        """The map -> odom correction: map pose of the odom frame's origin."""
        odom = self._pose_odom if self._pose_odom is not None else Pose2D()
        return self._pose.compose(odom.inverse())

    @property
    def particle_count(self) -> int:
        return len(self.particles)
