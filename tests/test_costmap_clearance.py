"""navcore.costmap.clearance: the numba clearance kernel against the plain numpy formulation."""

from __future__ import annotations

import numpy as np

from navcore.costmap.clearance import footprint_clearances


def _segment_distances(p, a, b):
    ab = b - a
    ap = p[..., :, None, :] - a[..., None, :, :]
    den = np.maximum(np.sum(ab * ab, axis=-1), 1e-18)[..., None, :]
    t = np.clip(np.sum(ap * ab[..., None, :, :], axis=-1) / den, 0.0, 1.0)
    d = ap - t[..., None] * ab[..., None, :, :]
    return np.sqrt(np.sum(d * d, axis=-1))


def _inside(p, poly):
    a = poly[..., None, :, :]
    b = np.roll(poly, -1, axis=-2)[..., None, :, :]
    px, py = p[..., :, None, 0], p[..., :, None, 1]
    crosses = (a[..., 1] > py) != (b[..., 1] > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        xi = a[..., 0] + (py - a[..., 1]) * (b[..., 0] - a[..., 0]) / (b[..., 1] - a[..., 1])
    return (np.sum(crosses & (px < xi), axis=-1) % 2) == 1


def reference_clearances(footprint, poses, squares, half):
    """The broadcast formulation (every pose x corner x edge at once) the kernel replaced."""
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    if squares.shape[0] == 0:
        return np.full(poses.shape[0], np.inf)
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    fx, fy = footprint[:, 0], footprint[:, 1]
    poly = np.stack([poses[:, None, 0] + c[:, None] * fx - s[:, None] * fy,
                     poses[:, None, 1] + s[:, None] * fx + c[:, None] * fy], axis=-1)
    nxt = np.roll(poly, -1, axis=1)
    offs = np.array([[-half, -half], [half, -half], [half, half], [-half, half]])
    corners = (squares[:, None, :] + offs[None, :, :]).reshape(-1, 2)
    cp = np.broadcast_to(corners, (poses.shape[0],) + corners.shape)
    d_corner = _segment_distances(cp, poly, nxt).min(axis=-1)
    inside = _inside(cp, poly)
    dx = np.abs(poly[:, :, None, 0] - squares[None, None, :, 0]) - half
    dy = np.abs(poly[:, :, None, 1] - squares[None, None, :, 1]) - half
    d_vertex = np.hypot(np.maximum(dx, 0.0), np.maximum(dy, 0.0))
    gap = np.minimum(d_corner.min(axis=-1), d_vertex.reshape(poses.shape[0], -1).min(axis=-1))
    vertex_in = np.any((dx < 0.0) & (dy < 0.0), axis=(1, 2))
    depth = np.where(inside, d_corner, 0.0).max(axis=-1)
    return np.where(inside.any(axis=-1), -depth, np.where(vertex_in, 0.0, gap))


def test_kernel_agrees_with_the_broadcast_formulation_on_random_scenes():
    rng = np.random.default_rng(3)
    rect = np.array([[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]])
    for k in range(150):
        if k % 3 == 0:
            fp = rect
        else:  # a random star-shaped polygon, 3 to 9 vertices
            n = int(rng.integers(3, 10))
            ang = np.sort(rng.uniform(-np.pi, np.pi, n))
            rad = rng.uniform(0.1, 0.5, n)
            fp = np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])
        res = 0.05
        m = int(rng.integers(1, 80))
        # cell centres on the grid, some right beside or under the robot
        squares = (np.floor(rng.uniform(-1.0, 1.0, (m, 2)) / res) + 0.5) * res
        poses = np.column_stack([rng.uniform(-0.5, 0.5, (12, 2)), rng.uniform(-4, 4, 12)])
        got = footprint_clearances(fp, poses, squares, 0.5 * res)
        want = reference_clearances(fp, poses, squares, 0.5 * res)
        np.testing.assert_array_equal(got, want)
        assert (got < 0).any() or (got > 0).any()


def test_clearance_signs_and_values():
    rect = np.array([[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]])
    half = 0.025
    pose = np.array([[0.0, 0.0, 0.0]])
    # a cell 10 cm in front of the front edge: gap = 0.10 - half
    far = footprint_clearances(rect, pose, np.array([[0.25 + 0.10, 0.0]]), half)
    assert abs(far[0] - (0.10 - half)) < 1e-12
    # a cell at the centre of the body: its corners are inside, depth = distance to the side
    deep = footprint_clearances(rect, pose, np.array([[0.0, 0.0]]), half)
    assert abs(deep[0] + (0.22 - half)) < 1e-12
    assert np.isinf(footprint_clearances(rect, pose, np.empty((0, 2)), half)).all()
