"""``run.png``: the map with the global costmap shaded under it, the planned paths, the driven
trajectory, the footprint at the start, the goals and every contact, laser points and a numbered
marker wherever a recovery fired; beside it a title, a legend and the list of recoveries; below
it plots over time (speed, distance to the goal, the active recovery, the localisation error
when an estimator ran). Pillow only (fast to import, tens of milliseconds per picture).

The map is cropped to the part the run touched (plus a margin), so a 4000-cell map does not turn
into a 4000-pixel image of mostly nothing. Markers carry numbers, not names: names are listed
beside the map, so labels never overlap each other or leave the image.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any, Sequence

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from navcore.maps import OccupancyGrid

MAX_SIDE_PX = 900
MARGIN_M = 1.5
SCAN_CROP_M = 3.0     # laser hits this close to the robot at a recovery widen the crop
SIDE_W = 330          # px, the legend and recovery list
AXIS_PAD = 38         # px left of and below the map for coordinates
PLOT_H = 92           # px per plot row

_PATH_COLOURS = [(120, 170, 255), (80, 130, 235), (40, 90, 215)]
_RECOVERY_COLOUR = (230, 120, 0)
_TRAJ_COLOUR = (20, 150, 40)
_CONTACT_COLOUR = (220, 0, 0)
_GOAL_COLOUR = (160, 0, 200)
_START_COLOUR = (0, 110, 160)
_PHANTOM_COLOUR = (230, 60, 160)
_INFLATION_COLOUR = np.array([90, 120, 255], np.float32)
_LETHAL_COLOUR = np.array([200, 40, 120], np.float32)
_INSCRIBED_COLOUR = np.array([235, 150, 60], np.float32)
# one colour per recovery for its laser points and its band in the plots
_PALETTE = [(230, 120, 0), (0, 150, 200), (200, 0, 120), (120, 90, 0), (0, 160, 110),
            (130, 60, 200), (200, 60, 40), (60, 60, 60)]


@lru_cache(maxsize=4)
def _font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    return ImageFont.load_default(size=size)


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


def _shade_costmap(rgb: np.ndarray, free: np.ndarray, xs: np.ndarray, ys: np.ndarray,
                   costmap: Any) -> None:
    """Tint free cells by the costmap's cost at their centres (``xs``/``ys``: world coordinates
    of the crop's columns / rows, rows top = max y): inflation blue, lethal and inscribed red."""
    c = costmap.costs
    res, ox, oy = costmap.resolution, costmap.origin_x, costmap.origin_y
    ci = np.floor((xs - ox) / res).astype(np.int64)
    ri = np.floor((ys - oy) / res).astype(np.int64)
    okc = (ci >= 0) & (ci < c.shape[1])
    okr = (ri >= 0) & (ri < c.shape[0])
    cost = np.zeros((len(ys), len(xs)), np.int32)
    sub = c[np.clip(ri, 0, c.shape[0] - 1)][:, np.clip(ci, 0, c.shape[1] - 1)]
    cost[:] = sub
    cost[~okr, :] = 0
    cost[:, ~okc] = 0
    cost[cost == 255] = 0  # unknown: leave the map as it is
    mask = free & (cost > 0)
    if not mask.any():
        return
    v = cost[mask].astype(np.float32)
    lethal = v >= 254
    inscribed = v == 253
    alpha = np.where(lethal, 0.6, np.where(inscribed, 0.35, 0.06 + 0.36 * v / 252.0))[:, None]
    colour = np.where(lethal[:, None], _LETHAL_COLOUR,
                      np.where(inscribed[:, None], _INSCRIBED_COLOUR, _INFLATION_COLOUR))
    px = rgb[mask].astype(np.float32)
    rgb[mask] = (px * (1 - alpha) + colour * alpha).astype(np.uint8)


def _nice_step(span: float, target: int) -> float:
    raw = span / max(1, target)
    mag = 10 ** math.floor(math.log10(raw)) if raw > 0 else 1.0
    for m in (1, 2, 5, 10):
        if m * mag >= raw:
            return m * mag
    return 10 * mag


def _footprint(draw: ImageDraw.ImageDraw, px: Any, pose: Sequence[float],
               footprint: Sequence[Sequence[float]], colour: tuple[int, int, int],
               width: int = 2) -> None:
    x, y, th = pose[0], pose[1], pose[2] if len(pose) > 2 else 0.0
    cs, sn = math.cos(th), math.sin(th)
    pts = [px(x + cs * fx - sn * fy, y + sn * fx + cs * fy) for fx, fy in footprint]
    if len(pts) >= 3:
        draw.line(pts + [pts[0]], fill=colour, width=width)
    nose = px(x + cs * 0.35, y + sn * 0.35)
    draw.line([px(x, y), nose], fill=colour, width=width)


def _place_badges(points: list[tuple[float, float]], w: int, h: int,
                  r: float) -> list[tuple[float, float]]:
    """Badge centres near each point, none overlapping another or any point, all inside the
    image: a badge moves out on a spiral around its point until it is free."""
    placed: list[tuple[float, float]] = []
    for x, y in points:
        best = None
        for k in range(1, 400):
            ang = -0.8 + k * 2.39996  # golden angle: an even spiral, first try up-right
            dist = 1.6 * r + 1.1 * r * math.sqrt(k - 1)
            cx = min(max(x + dist * math.cos(ang), r + 1), w - r - 2)
            cy = min(max(y + dist * math.sin(ang), r + 1), h - r - 2)
            if all((cx - qx) ** 2 + (cy - qy) ** 2 >= (2 * r + 1) ** 2 for qx, qy in placed) \
                    and all((cx - qx) ** 2 + (cy - qy) ** 2 >= (r + 5) ** 2 for qx, qy in points):
                best = (cx, cy)
                break
        placed.append(best if best is not None else (x, y))
    return placed


def draw_run(grid: OccupancyGrid, trajectory: Sequence[Sequence[float]],
             paths: Sequence[Sequence[Sequence[float]]], recoveries: Sequence[dict[str, Any]],
             contacts: Sequence[Sequence[float]], goals: Sequence[Sequence[float]],
             footprint: Sequence[Sequence[float]], out_path: str,
             obstacles: Sequence[Sequence[Sequence[float]]] = (),
             phantoms: Sequence[Sequence[Sequence[float]]] = (), title: str = "",
             capture: Any = None) -> Image.Image:
    """Draw a run and save it as PNG at ``out_path``; returns the image (for tests).

    ``capture`` (an ``executive.capture.RunCapture``) adds the costmap shading, laser points at
    recoveries and the plots over time."""
    res = grid.resolution
    ox, oy = grid.origin.x, grid.origin.y
    pts = [p[:2] for p in trajectory] + [g[:2] for g in goals]
    for path in paths:
        pts += [p[:2] for p in path]
    if capture is not None:  # what the robot saw nearby when a recovery fired
        for sample in capture.recovery_scans:
            hits = sample.points(90)
            lp = sample.laser_pose
            near = np.hypot(hits[:, 0] - lp.x, hits[:, 1] - lp.y) < SCAN_CROP_M
            pts += hits[near].tolist()
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
    rgb = _map_rgb(sub)
    shaded_at = None
    if capture is not None and capture.global_costmaps:
        # the costmap before the first recovery changed it (the reason the robot was stuck),
        # else as the run left it (sinks see a tick's end: a recovery in the first tick has
        # already cleared what made it fire)
        t_stuck = recoveries[0]["t"] if recoveries else math.inf
        before = [g for g in capture.global_costmaps if g.t < t_stuck - 1e-6]
        g = before[-1] if before else capture.global_costmaps[-1]
        if g is not None:
            xs = ox + (np.arange(c0, c1) + 0.5) * res
            ys = oy + (np.arange(r1 - 1, r0 - 1, -1) + 0.5) * res
            _shade_costmap(rgb, sub.data[::-1] == 0, xs, ys, g)
            shaded_at = g.t
    scale = max(1.0, min(40.0, MAX_SIDE_PX / max(sub.width, sub.height)))
    mw, mh = int(sub.width * scale), int(sub.height * scale)
    map_img = Image.fromarray(rgb, "RGB").resize((mw, mh), Image.NEAREST)

    have_plots = capture is not None and len(capture.times) >= 2
    n_plots = (3 + int(capture.has_localisation)) if have_plots else 0
    plots_h = n_plots * PLOT_H + (30 if n_plots else 0)
    width = AXIS_PAD + mw + 12 + SIDE_W
    height = max(mh + AXIS_PAD + 8, 420) + plots_h
    img = Image.new("RGB", (width, height), (255, 255, 255))
    img.paste(map_img, (AXIS_PAD, 4))
    draw = ImageDraw.Draw(img)
    f10, f12, f14 = _font(10), _font(12), _font(15)

    def px(x: float, y: float) -> tuple[float, float]:
        return (AXIS_PAD + ((x - ox) / res - c0) * scale,
                4 + mh - ((y - oy) / res - r0) * scale)

    # --- map layers -----------------------------------------------------------------------
    for poly in obstacles:
        if len(poly) >= 3:
            draw.polygon([px(*p[:2]) for p in poly], fill=(110, 110, 110), outline=(60, 60, 60))
    for poly in phantoms:  # costmap-only obstacles: an outline, since nothing is really there
        if len(poly) >= 3:
            pp = [px(*p[:2]) for p in poly]
            draw.line(pp + [pp[0]], fill=_PHANTOM_COLOUR, width=2)
    for i, path in enumerate(paths):
        if len(path) >= 2:
            draw.line([px(*p[:2]) for p in path], fill=_PATH_COLOURS[i % 3], width=1)
    if len(trajectory) >= 2:
        draw.line([px(*p[:2]) for p in trajectory], fill=_TRAJ_COLOUR, width=2)
    scans = list(capture.recovery_scans) if capture is not None else []
    for n, rec in enumerate(recoveries):
        match = [s for s in scans if abs(s.t - rec["t"]) < 2e-3]
        if match:
            colour = _PALETTE[n % len(_PALETTE)]
            for x, y in match[0].points(360):
                qx, qy = px(x, y)
                if AXIS_PAD + 1 <= qx <= AXIS_PAD + mw - 2 and 5 <= qy <= 2 + mh:
                    draw.rectangle([qx - 1, qy - 1, qx + 1, qy + 1], fill=colour)
    for c in contacts:
        _footprint(draw, px, c, footprint, _CONTACT_COLOUR)
    if trajectory:
        _footprint(draw, px, trajectory[0], footprint, _START_COLOUR)
    for g in goals:
        _footprint(draw, px, g, footprint, _GOAL_COLOUR)
        gx, gy = px(g[0], g[1])
        draw.line([(gx - 5, gy - 5), (gx + 5, gy + 5)], fill=_GOAL_COLOUR, width=2)
        draw.line([(gx - 5, gy + 5), (gx + 5, gy - 5)], fill=_GOAL_COLOUR, width=2)
    # recovery markers: a dot where it fired, a numbered badge nearby (never overlapping)
    spots = [px(*rec["pose"][:2]) for rec in recoveries]
    rad = 8.0
    badges = _place_badges([(x - AXIS_PAD, y - 4) for x, y in spots], mw, mh, rad)
    for sx, sy in spots:
        draw.ellipse([sx - 4, sy - 4, sx + 4, sy + 4], fill=_RECOVERY_COLOUR, outline=(0, 0, 0))
    for (sx, sy), (bx, by) in zip(spots, badges):
        draw.line([(sx, sy), (bx + AXIS_PAD, by + 4)], fill=(90, 90, 90), width=1)
    for n, (bx, by) in enumerate(badges, 1):
        bx, by = bx + AXIS_PAD, by + 4
        draw.ellipse([bx - rad, by - rad, bx + rad, by + rad], fill=(255, 255, 255),
                     outline=_RECOVERY_COLOUR, width=2)
        draw.text((bx, by), str(n), fill=(0, 0, 0), font=f10, anchor="mm")

    # --- coordinates and scale bar --------------------------------------------------------
    wx0, wy0 = ox + c0 * res, oy + r0 * res
    wx1, wy1 = ox + c1 * res, oy + r1 * res
    step = _nice_step(max(wx1 - wx0, wy1 - wy0), 8)
    draw.rectangle([AXIS_PAD - 1, 3, AXIS_PAD + mw, 4 + mh], outline=(0, 0, 0))
    v = math.ceil(wx0 / step) * step
    while v <= wx1 + 1e-9:
        qx, _ = px(v, wy0)
        draw.line([(qx, 4 + mh), (qx, 8 + mh)], fill=(0, 0, 0))
        draw.text((qx, 10 + mh), f"{v:g}", fill=(0, 0, 0), font=f10, anchor="ma")
        v += step
    v = math.ceil(wy0 / step) * step
    while v <= wy1 + 1e-9:
        _, qy = px(wx0, v)
        draw.line([(AXIS_PAD - 5, qy), (AXIS_PAD - 1, qy)], fill=(0, 0, 0))
        draw.text((AXIS_PAD - 7, qy), f"{v:g}", fill=(0, 0, 0), font=f10, anchor="rm")
        v += step
    draw.text((AXIS_PAD + mw / 2, 24 + mh), "x (m, map frame)", fill=(0, 0, 0), font=f10,
              anchor="ma")
    bar_m = _nice_step(wx1 - wx0, 5)
    bar_px = bar_m / res * scale
    bx0, by0 = AXIS_PAD + 10, 4 + mh - 14
    draw.rectangle([bx0 - 4, by0 - 14, bx0 + bar_px + 4, by0 + 6], fill=(255, 255, 255))
    draw.rectangle([bx0, by0, bx0 + bar_px, by0 + 4], fill=(0, 0, 0))
    draw.text((bx0 + bar_px / 2, by0 - 2), f"{bar_m:g} m", fill=(0, 0, 0), font=f10,
              anchor="mb")

    # --- side panel: title, legend, recoveries ---------------------------------------------
    sx0 = AXIS_PAD + mw + 14
    y = 6
    if title:
        for chunk in _wrap(title, 30):
            draw.text((sx0, y), chunk, fill=(0, 0, 0), font=f14)
            y += 19
    y += 4
    legend: list[tuple[str, Any]] = [
        ("trajectory", ("line", _TRAJ_COLOUR)), ("global plans", ("line", _PATH_COLOURS[1])),
        ("footprint at start", ("box", _START_COLOUR)), ("goal (footprint, heading)",
                                                         ("box", _GOAL_COLOUR))]
    if recoveries:
        legend.append(("recovery fired (n: list below)", ("dot", _RECOVERY_COLOUR)))
    if contacts:
        legend.append(("contact", ("box", _CONTACT_COLOUR)))
    if obstacles:
        legend.append(("obstacle unknown to the map", ("fill", (110, 110, 110))))
    if phantoms:
        legend.append(("phantom (costmap only)", ("box", _PHANTOM_COLOUR)))
    if shaded_at is not None:
        legend.append((f"inflation (global costmap, t={shaded_at:.0f} s)",
                       ("fill", (175, 190, 255))))
        legend.append(("inscribed cost (centre here = contact)", ("fill", (246, 208, 170))))
        legend.append(("lethal cost", ("fill", (225, 140, 180))))
    if scans:
        legend.append(("laser hits at each recovery", ("dot", _PALETTE[1])))
    for text, (kind, colour) in legend:
        if kind == "line":
            draw.line([(sx0, y + 7), (sx0 + 22, y + 7)], fill=colour, width=3)
        elif kind == "box":
            draw.rectangle([sx0 + 3, y + 1, sx0 + 19, y + 13], outline=colour, width=2)
        elif kind == "fill":
            draw.rectangle([sx0 + 3, y + 1, sx0 + 19, y + 13], fill=colour)
        else:
            draw.ellipse([sx0 + 7, y + 3, sx0 + 15, y + 11], fill=colour, outline=(0, 0, 0))
        draw.text((sx0 + 28, y), text, fill=(0, 0, 0), font=f12)
        y += 17
    y += 8
    if recoveries:
        draw.text((sx0, y), f"Recoveries ({len(recoveries)})", fill=(0, 0, 0), font=f14)
        y += 20
        limit = max(y, mh + AXIS_PAD - 16)
        for n, rec in enumerate(recoveries, 1):
            if y > limit - 14:
                draw.text((sx0, y), f"... and {len(recoveries) - n + 1} more (summary.json)",
                          fill=(90, 90, 90), font=f12)
                break
            kind = rec.get("type", "")
            name = rec.get("recovery", "?")
            what = name if not kind or kind == name else f"{kind} ({name})"
            line = f"{n:>2}. t={rec['t']:.1f}s {what}"
            draw.text((sx0, y), _clip(line, 48), fill=_PALETTE[(n - 1) % len(_PALETTE)]
                      if scans else (0, 0, 0), font=f12)
            y += 15
    if have_plots:
        _plots(draw, capture, recoveries, 8, max(mh + AXIS_PAD + 8, 420) + 10, width - 16,
               n_plots)
    img.save(out_path)
    return img


def _wrap(text: str, n: int) -> list[str]:
    words, lines, cur = text.split(), [], ""
    for w in words:
        if cur and len(cur) + 1 + len(w) > n:
            lines.append(cur)
            cur = w
        else:
            cur = f"{cur} {w}".strip()
    return lines + ([cur] if cur else [])


def _clip(text: str, n: int) -> str:
    return text if len(text) <= n else text[: n - 3] + "..."


def _plots(draw: ImageDraw.ImageDraw, cap: Any, recoveries: Sequence[dict[str, Any]],
           x0: int, y0: int, w: int, n_plots: int) -> None:
    """Rows of plots over time sharing one time axis; recovery periods shaded in each."""
    t = np.asarray(cap.times, float)
    t0, t1 = float(t[0]), float(max(t[-1], t[0] + 1e-6))
    left, right = x0 + 58, x0 + w - 8
    f10, f12 = _font(10), _font(12)
    active = np.asarray(cap.active_recovery, int)
    rows: list[tuple[str, np.ndarray | None, tuple[int, int, int]]] = [
        ("speed (m/s)", np.asarray(cap.speed, float), (20, 110, 200)),
        ("distance to goal (m)", np.asarray(cap.goal_distance, float), (160, 0, 200)),
        ("active recovery", None, (0, 0, 0))]
    if n_plots == 4:
        rows.append(("localisation error (m)", cap.localisation_error(), (200, 60, 40)))

    def tx(v: float) -> float:
        return left + (v - t0) / (t1 - t0) * (right - left)

    # spans where a recovery ran, as index ranges
    spans = []
    i = 0
    while i < len(active):
        if active[i] >= 0:
            j = i
            while j + 1 < len(active) and active[j + 1] == active[i]:
                j += 1
            spans.append((i, j, int(active[i])))
            i = j + 1
        else:
            i += 1
    for r, (label, values, colour) in enumerate(rows):
        top = y0 + r * PLOT_H + 16
        bottom = y0 + (r + 1) * PLOT_H - 8
        draw.rectangle([left, top, right, bottom], outline=(120, 120, 120))
        draw.text((left, top - 15), label, fill=(0, 0, 0), font=f12)
        for a, b, k in spans:
            c = _PALETTE[k % len(_PALETTE)]
            light = tuple(int(255 - (255 - ch) * 0.25) for ch in c)
            draw.rectangle([tx(t[a]), top + 1, max(tx(t[b]), tx(t[a]) + 1), bottom - 1],
                           fill=light)
        if values is None:
            names = cap.recovery_names
            for a, b, k in spans:
                xa, xb = tx(t[a]) - 1, max(tx(t[b]), tx(t[a]) + 2)
                mid = top + 6 + (k % 3) * ((bottom - top - 12) / 3)
                draw.rectangle([xa, mid, xb, mid + 10], fill=_PALETTE[k % len(_PALETTE)])
            # one label per recovery, at the right (the bands show when each ran)
            ly = top + 3
            for k, name in enumerate(names[:5]):
                draw.text((right - 4, ly), name, fill=_PALETTE[k % len(_PALETTE)], font=f10,
                          anchor="ra")
                ly += 11
            if not names:
                draw.text((left + 4, top + 18), "none", fill=(90, 90, 90), font=f10)
            continue
        finite = values[np.isfinite(values)]
        vmax = float(finite.max()) if len(finite) else 1.0
        vmax = vmax if vmax > 1e-9 else 1.0
        draw.text((left - 4, top + 2), f"{vmax:.2g}", fill=(0, 0, 0), font=f10, anchor="ra")
        draw.text((left - 4, bottom - 2), "0", fill=(0, 0, 0), font=f10, anchor="rd")
        n = len(values)
        stride = max(1, n // (right - left))
        xs = [tx(v) for v in t[::stride]]
        ys = [bottom - 2 - (v / vmax) * (bottom - top - 6) if math.isfinite(v) else None
              for v in values[::stride]]
        seg: list[tuple[float, float]] = []
        for qx, qy in zip(xs, ys):
            if qy is None:
                if len(seg) >= 2:
                    draw.line(seg, fill=colour, width=2)
                seg = []
            else:
                seg.append((qx, qy))
        if len(seg) >= 2:
            draw.line(seg, fill=colour, width=2)
    # time axis under the last row
    base = y0 + len(rows) * PLOT_H - 8
    step = _nice_step(t1 - t0, 10)
    v = math.ceil(t0 / step) * step
    while v <= t1 + 1e-9:
        draw.line([(tx(v), base), (tx(v), base + 4)], fill=(0, 0, 0))
        draw.text((tx(v), base + 5), f"{v:g}", fill=(0, 0, 0), font=f10, anchor="ma")
        v += step
    draw.text(((left + right) / 2, base + 17), "time (s, simulated)", fill=(0, 0, 0), font=f10,
              anchor="ma")
