"""Scenes and a closed loop shared by the local planner tests."""

from __future__ import annotations

import numpy as np

from navcore.costmap.costmap2d import Costmap2D
from navcore.types import Path, Pose2D, Twist

RECT = np.array([[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]])
INSCRIBED = 0.22
DT = 0.05  # one control period at 20 Hz


def inflate(costmap: Costmap2D, lethal: np.ndarray, inscribed: float = INSCRIBED,
            inflation_radius: float = 0.55, cost_scaling_factor: float = 10.0) -> None:
    """Write lethal cells and costmap_2d's inflation around them (brute force, small grids)."""
    res = costmap.resolution
    costs = np.zeros(lethal.shape, dtype=np.float64)
    ys, xs = np.nonzero(lethal)
    if len(xs):
        gy, gx = np.mgrid[0:lethal.shape[0], 0:lethal.shape[1]]
        d = np.full(lethal.shape, np.inf)
        for x, y in zip(xs, ys):
            d = np.minimum(d, np.hypot(gx - x, gy - y) * res)
        inner = d <= inscribed
        ring = (d > inscribed) & (d <= inflation_radius)
        costs[ring] = np.exp(-cost_scaling_factor * (d[ring] - inscribed)) * 252
        costs[inner] = 253
        costs[d == 0] = 254
    costmap.costs[:] = costs.astype(np.uint8)


def straight_path(x0: float, y0: float, x1: float, y1: float, step: float = 0.05) -> Path:
    n = max(2, int(np.hypot(x1 - x0, y1 - y0) / step) + 1)
    th = np.arctan2(y1 - y0, x1 - x0)
    return Path(np.column_stack([np.linspace(x0, x1, n), np.linspace(y0, y1, n), np.full(n, th)]))


def drive(planner, pose: Pose2D, vel: Twist, path: Path, cycles: int,
          costmap: Costmap2D | None = None, rolling: bool = False) -> tuple[Pose2D, Twist, list]:
    """Closed loop with perfect tracking: the commanded velocity is held for one period."""
    results = []
    for _ in range(cycles):
        if rolling and costmap is not None:
            w, h = costmap.size_in_meters()
            costmap.origin_x, costmap.origin_y = pose.x - w / 2, pose.y - h / 2
        r = planner.compute_velocity(pose, vel, path)
        results.append((pose, r))
        vel = r.cmd
        pose = pose.compose(Pose2D(vel.vx * DT, vel.vy * DT, vel.wz * DT))
        if r.status == "goal_reached":
            break
    return pose, vel, results


def test_inflate_writes_costmap_2d_cost_bands():
    cm = Costmap2D(40, 40, 0.05)
    lethal = np.zeros((40, 40), dtype=bool)
    lethal[20, 20] = True
    inflate(cm, lethal)
    assert cm.costs[20, 20] == 254
    assert cm.costs[20, 24] == 253          # 0.20 m away: inside the inscribed radius
    assert 0 < cm.costs[20, 30] < 253       # 0.50 m away: decaying ring
    assert cm.costs[20, 39] == 0            # 0.95 m away: beyond the inflation radius
