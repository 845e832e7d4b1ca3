"""``run.png``: the map, the global paths, the driven trajectory, the footprint at contacts, and a
labelled marker wherever a recovery fired. Pillow only (fast to import, about 25 ms per picture).

The picture is cropped to the part of the map the run touched (plus a margin), so a 4000-cell
map does not turn into a 4000-pixel image of mostly nothing.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np
from PIL import Image, ImageDraw

from navcore.maps import OccupancyGrid

MAX_SIDE_PX = 900
MARGIN_M = 1.5

_PATH_COLOURS = [(120, 170, 255), (80, 130, 235), (40, 90, 215)]
_RECOVERY_COLOUR = (230, 120, 0)
_TRAJ_COLOUR = (20, 150, 40)
_CONTACT_COLOUR = (220, 0, 0)
_GOAL_COLOUR = (160, 0, 200)
_PHANTOM_COLOUR = (230, 60, 160)


def _map_rgb(grid: OccupancyGrid) -> np.ndarray:
    """RGB of the grid with the top row = max y (image convention)."""
    d = grid.data[::-1]
    rgb = np.empty(d.shape + (3,), np.uint8)
    rgb[...] = 205  # unknown
    rgb[d == 0] = 255
    occ = d >= 65
    rgb[occ] = 30
    mid = (d > 0) & (d < 65)
    if mid.any():
        v = (255 - d[mid].astype(np.int32) * 2).clip(60, 255).astype(np.uint8)
        rgb[mid] = v[:, None]
    return rgb


def draw_run(grid: OccupancyGrid, trajectory: Sequence[Sequence[float]],
             paths: Sequence[Sequence[Sequence[float]]], recoveries: Sequence[dict[str, Any]],
             contacts: Sequence[Sequence[float]], goals: Sequence[Sequence[float]],
             footprint: Sequence[Sequence[float]], out_path: str,
             obstacles: Sequence[Sequence[Sequence[float]]] = (),
             phantoms: Sequence[Sequence[Sequence[float]]] = (), title: str = "") -> Image.Image:
    """Draw a run and save it as PNG at ``out_path``; returns the image (for tests)."""
    res = grid.resolution
    ox, oy = grid.origin.x, grid.origin.y
    pts = [p[:2] for p in trajectory] + [g[:2] for g in goals]
    for path in paths:
        pts += [p[:2] for p in path]
    if pts:
        arr = np.asarray(pts, float)
        x0, y0 = arr.min(axis=0) - MARGIN_M
        x1, y1 = arr.max(axis=0) + MARGIN_M
    else:
        x0, y0, x1, y1 = ox, oy, ox + grid.width * res, oy + grid.height * res
    c0 = max(0, int((x0 - ox) / res))
    c1 = min(grid.width, int(math.ceil((x1 - ox) / res)))
    r0 = max(0, int((y0 - oy) / res))
    r1 = min(grid.height, int(math.ceil((y1 - oy) / res)))
    if c1 <= c0 or r1 <= r0:
        c0, c1, r0, r1 = 0, grid.width, 0, grid.height
    sub = OccupancyGrid(grid.data[r0:r1, c0:c1], res)
    scale = max(1.0, min(40.0, MAX_SIDE_PX / max(sub.width, sub.height)))
    img = Image.fromarray(_map_rgb(sub), "RGB")
    img = img.resize((int(sub.width * scale), int(sub.height * scale)), Image.NEAREST)
    h = img.height
    draw = ImageDraw.Draw(img)

    def px(x: float, y: float) -> tuple[float, float]:
        return ((x - ox) / res - c0) * scale, h - ((y - oy) / res - r0) * scale

    for poly in obstacles:
        if len(poly) >= 3:
            draw.polygon([px(*p[:2]) for p in poly], fill=(110, 110, 110), outline=(60, 60, 60))
    for poly in phantoms:  # costmap-only obstacles: an outline, since nothing is really there
        if len(poly) >= 3:
            pts = [px(*p[:2]) for p in poly]
            draw.line(pts + [pts[0]], fill=_PHANTOM_COLOUR, width=2)
            draw.text((pts[0][0] + 2, pts[0][1] + 2), "phantom", fill=_PHANTOM_COLOUR)
    for i, path in enumerate(paths):
        if len(path) >= 2:
            draw.line([px(*p[:2]) for p in path], fill=_PATH_COLOURS[i % 3], width=1)
    if len(trajectory) >= 2:
        draw.line([px(*p[:2]) for p in trajectory], fill=_TRAJ_COLOUR, width=2)
    for c in contacts:
        x, y, th = c[0], c[1], c[2] if len(c) > 2 else 0.0
        cs, sn = math.cos(th), math.sin(th)
        outline = [px(x + cs * fx - sn * fy, y + sn * fx + cs * fy) for fx, fy in footprint]
        draw.polygon(outline, outline=_CONTACT_COLOUR)
    for g in goals:
        gx, gy = px(g[0], g[1])
        draw.line([(gx - 6, gy - 6), (gx + 6, gy + 6)], fill=_GOAL_COLOUR, width=2)
        draw.line([(gx - 6, gy + 6), (gx + 6, gy - 6)], fill=_GOAL_COLOUR, width=2)
    placed: list[tuple[float, float]] = []
    for n, rec in enumerate(recoveries, 1):
        rx, ry = px(*rec["pose"][:2])
        draw.ellipse([rx - 5, ry - 5, rx + 5, ry + 5], fill=_RECOVERY_COLOUR, outline=(0, 0, 0))
        # stack labels of recoveries fired at the same spot instead of overprinting them
        k = sum(1 for q in placed if abs(q[0] - rx) < 40 and abs(q[1] - ry) < 8)
        placed.append((rx, ry))
        draw.text((rx + 7, ry - 6 + 11 * k), f"{n}. {rec.get('recovery', '?')}",
                  fill=(140, 60, 0))
    if trajectory:
        sx, sy = px(*trajectory[0][:2])
        draw.ellipse([sx - 4, sy - 4, sx + 4, sy + 4], outline=(0, 0, 0), fill=_TRAJ_COLOUR)
    if title:
        draw.rectangle([0, 0, 8 + 6 * len(title), 14], fill=(255, 255, 255))
        draw.text((4, 2), title, fill=(0, 0, 0))
    img.save(out_path)
    return img
