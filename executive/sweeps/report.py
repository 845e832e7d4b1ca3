"""Sweep reports: a table of success rates with confidence intervals, and the pictures a person
looks at (heat maps over two parameters, success-vs-parameter curves with error bars, the best
and worst runs' run.png).

The interval is Wilson's score interval at 95 %: with a handful of seeds per point the normal
approximation gives intervals outside [0, 1] and zero width at 0 % and 100 %.
"""

from __future__ import annotations

import json
import math
import os
from collections import defaultdict
from dataclasses import dataclass
from typing import Any, Sequence, TextIO

from PIL import Image, ImageDraw, ImageFont

Z95 = 1.959963984540054


def wilson(successes: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval of a proportion (lower, upper); (0, 1) when n is 0."""
    if n == 0:
        return 0.0, 1.0
    p = successes / n
    denom = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    return max(0.0, centre - half), min(1.0, centre + half)


@dataclass
class PointStats:
    tree: str
    point: dict[str, Any]
    runs: int
    solved: int
    passed: int
    errors: int
    contacts: int
    mean_time_s: float | None
    mean_path_m: float | None
    mean_clearance_m: float | None = None
    mean_turning: float | None = None

    @property
    def rate(self) -> float:
        return self.solved / self.runs if self.runs else 0.0

    @property
    def interval(self) -> tuple[float, float]:
        return wilson(self.solved, self.runs)

    def as_dict(self) -> dict[str, Any]:
        lo, hi = self.interval
        return {"tree": self.tree, "point": self.point, "runs": self.runs,
                "solved": self.solved, "success_rate": round(self.rate, 4),
                "ci95": [round(lo, 4), round(hi, 4)], "met_expectation": self.passed,
                "errors": self.errors, "contacts": self.contacts,
                "mean_time_s": None if self.mean_time_s is None else round(self.mean_time_s, 3),
                "mean_path_m": None if self.mean_path_m is None else round(self.mean_path_m, 3),
                "mean_min_clearance_m": _round(self.mean_clearance_m),
                "mean_turning_rad_per_m": _round(self.mean_turning)}


def _round(v: float | None, n: int = 3) -> float | None:
    return None if v is None else round(v, n)


def _mean(values: list[Any]) -> float | None:
    vals = [v for v in values if v is not None]
    return sum(vals) / len(vals) if vals else None


def point_stats(records: Sequence[dict[str, Any]]) -> list[PointStats]:
    """Aggregate runs per (tree, point) over scenarios and seeds, in a stable order."""
    groups: dict[tuple[str, str], list[dict[str, Any]]] = defaultdict(list)
    for r in records:
        groups[(r["tree"], json.dumps(r["point"], sort_keys=True))].append(r)
    def order(item: tuple[tuple[str, str], Any]) -> tuple:
        (tree, pkey), _ = item
        point = json.loads(pkey)
        return (tree,) + tuple((0, v, "") if isinstance(v, (int, float)) else (1, 0, str(v))
                               for _, v in sorted(point.items()))

    out = []
    for (tree, pkey), rs in sorted(groups.items(), key=order):
        ok = [r for r in rs if r["outcome"] != "error"]
        times = [r["sim_time_s"] for r in rs if r["solved"]]
        paths = [r["path_length_m"] for r in rs if r["solved"] and r["path_length_m"] is not None]
        out.append(PointStats(tree, json.loads(pkey), len(rs), sum(r["solved"] for r in rs),
                              sum(r["passed"] for r in rs), len(rs) - len(ok),
                              sum(r["contacts"] or 0 for r in ok),
                              sum(times) / len(times) if times else None,
                              sum(paths) / len(paths) if paths else None,
                              _mean([r.get("min_clearance_m") for r in ok]),
                              _mean([r.get("turning_rad_per_m") for r in ok])))
    return out


def _fmt(v: Any) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


def print_table(stats: Sequence[PointStats], out: TextIO) -> None:
    """One row per (tree, point): runs, success rate with its 95 % interval, time, contacts."""
    keys = sorted({k for s in stats for k in s.point})
    head = ["tree"] + keys + ["runs", "success", "95% CI", "met", "mean t (s)", "path (m)", "clear (m)",
                              "turn (rad/m)", "contacts", "errors"]
    rows = []
    for s in stats:
        lo, hi = s.interval
        rows.append([s.tree] + [_fmt(s.point.get(k, "-")) for k in keys] +
                    [str(s.runs), f"{100 * s.rate:.0f}%", f"[{100 * lo:.0f}, {100 * hi:.0f}]",
                     f"{s.passed}/{s.runs}",
                     "-" if s.mean_time_s is None else f"{s.mean_time_s:.1f}",
                     "-" if s.mean_path_m is None else f"{s.mean_path_m:.2f}",
                     "-" if s.mean_clearance_m is None else f"{s.mean_clearance_m:.2f}",
                     "-" if s.mean_turning is None else f"{s.mean_turning:.2f}",
                     str(s.contacts), str(s.errors)])
    widths = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h)
              for i, h in enumerate(head)]
    out.write("  ".join(h.ljust(w) for h, w in zip(head, widths)) + "\n")
    for r in rows:
        out.write("  ".join(c.ljust(w) for c, w in zip(r, widths)) + "\n")


# --------------------------------------------------------------------------- pictures
_W, _H, _M = 720, 480, 70


def _font(size: int = 13) -> ImageFont.ImageFont:
    try:
        return ImageFont.load_default(size=size)
    except TypeError:   # Pillow < 10.1 has one size only
        return ImageFont.load_default()


def _colour(rate: float) -> tuple[int, int, int]:
    """Red (0 %) through yellow to green (100 %)."""
    rate = min(1.0, max(0.0, rate))
    if rate < 0.5:
        return 215, int(60 + 330 * rate), 60
    return int(215 - 330 * (rate - 0.5)), 200, 70


def numeric_keys(stats: Sequence[PointStats]) -> list[str]:
    """Parameters that vary across points and are all numbers."""
    keys = sorted({k for s in stats for k in s.point})
    out = []
    for k in keys:
        vals = {s.point.get(k) for s in stats}
        if len(vals) > 1 and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                 for v in vals):
            out.append(k)
    return out


def heat_map(stats: Sequence[PointStats], kx: str, ky: str, path: str, title: str) -> None:
    """Success rate over two parameters: one cell per (x, y) value pair, the rate written in."""
    xs = sorted({s.point[kx] for s in stats})
    ys = sorted({s.point[ky] for s in stats})
    cell: dict[tuple[Any, Any], list[PointStats]] = defaultdict(list)
    for s in stats:
        cell[(s.point[kx], s.point[ky])].append(s)
    img = Image.new("RGB", (_W, _H), "white")
    d = ImageDraw.Draw(img)
    f = _font()
    d.text((_M, 15), title, fill="black", font=_font(15))
    gw, gh = (_W - 2 * _M) / len(xs), (_H - 2 * _M) / len(ys)
    for i, x in enumerate(xs):
        for j, y in enumerate(ys):
            group = cell.get((x, y))
            x0, y1 = _M + i * gw, _H - _M - j * gh
            box = [x0 + 1, y1 - gh + 1, x0 + gw - 1, y1 - 1]
            if not group:
                d.rectangle(box, fill=(235, 235, 235))
                continue
            runs = sum(g.runs for g in group)
            solved = sum(g.solved for g in group)
            rate = solved / runs if runs else 0.0
            d.rectangle(box, fill=_colour(rate))
            d.text((x0 + gw / 2, y1 - gh / 2), f"{100 * rate:.0f}%\n{solved}/{runs}",
                   fill="black", font=f, anchor="mm", align="center")
        d.text((_M + (i + 0.5) * gw, _H - _M + 8), _fmt(x), fill="black", font=f, anchor="mt")
    for j, y in enumerate(ys):
        d.text((_M - 8, _H - _M - (j + 0.5) * gh), _fmt(y), fill="black", font=f, anchor="rm")
    d.text((_W / 2, _H - 25), kx, fill="black", font=f, anchor="mm")
    d.text((8, 45), ky, fill="black", font=f)
    img.save(path)


def curve(stats: Sequence[PointStats], kx: str, path: str, title: str,
          by: str | None = None) -> None:
    """Success rate against one parameter with 95 % error bars; one line per value of ``by``
    (another parameter) or per tree."""
    series: dict[str, dict[Any, list[PointStats]]] = defaultdict(lambda: defaultdict(list))
    for s in stats:
        label = f"{by.split('.')[-1]}={_fmt(s.point[by])}" if by else s.tree
        series[label][s.point[kx]].append(s)
    xs = sorted({s.point[kx] for s in stats})
    lo_x, hi_x = float(xs[0]), float(xs[-1])
    span = hi_x - lo_x or 1.0
    img = Image.new("RGB", (_W, _H), "white")
    d = ImageDraw.Draw(img)
    f = _font()
    d.text((_M, 15), title, fill="black", font=_font(15))
    x0, x1, y0, y1 = _M, _W - _M - 120, _H - _M, _M

    pad = 30   # keep the end points and their error bars off the axes

    def px(x: float) -> float:
        return x0 + pad + (float(x) - lo_x) / span * (x1 - x0 - 2 * pad)

    def py(r: float) -> float:
        return y0 - r * (y0 - y1)

    d.line([x0, y0, x1, y0], fill="black")
    d.line([x0, y0, x0, y1], fill="black")
    for r in (0, 0.25, 0.5, 0.75, 1.0):
        d.line([x0 - 4, py(r), x1, py(r)], fill=(225, 225, 225))
        d.text((x0 - 8, py(r)), f"{100 * r:.0f}%", fill="black", font=f, anchor="rm")
    for x in xs:
        d.text((px(x), y0 + 8), _fmt(x), fill="black", font=f, anchor="mt")
    d.text(((x0 + x1) / 2, _H - 25), kx, fill="black", font=f, anchor="mm")
    d.text((8, y1 - 30), "solved (95% CI)", fill="black", font=f)
    palette = [(31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189),
               (140, 86, 75), (227, 119, 194), (127, 127, 127)]
    for n, (label, pts) in enumerate(sorted(series.items(), key=lambda kv: _natural(kv[0]))):
        c = palette[n % len(palette)]
        shift = 5 * (n - (len(series) - 1) / 2)   # side by side, so error bars do not hide
        line = []
        for x in sorted(pts):
            runs = sum(g.runs for g in pts[x])
            solved = sum(g.solved for g in pts[x])
            rate = solved / runs if runs else 0.0
            lo, hi = wilson(solved, runs)
            cx = px(x) + shift
            line.append((cx, py(rate)))
            d.line([cx, py(lo), cx, py(hi)], fill=c, width=2)
            d.line([cx - 4, py(lo), cx + 4, py(lo)], fill=c, width=2)
            d.line([cx - 4, py(hi), cx + 4, py(hi)], fill=c, width=2)
            d.ellipse([cx - 4, py(rate) - 4, cx + 4, py(rate) + 4], fill=c)
        if len(line) > 1:
            d.line(line, fill=c, width=2)
        d.rectangle([x1 + 15, y1 + 20 * n, x1 + 27, y1 + 20 * n + 12], fill=c)
        d.text((x1 + 32, y1 + 20 * n + 6), label[-24:], fill="black", font=f, anchor="lm")
    img.save(path)


def _natural(label: str) -> tuple:
    """Sort ``k=2.5`` before ``k=10``."""
    head, _, value = label.rpartition("=")
    try:
        return head, float(value), ""
    except ValueError:
        return label, 0.0, value


def write_report(records: Sequence[dict[str, Any]], out_dir: str, out: TextIO,
                 name: str = "sweep") -> dict[str, Any]:
    """Print the table and write ``report.json`` and the pictures into ``out_dir``; returns
    what was written."""
    os.makedirs(out_dir, exist_ok=True)
    stats = point_stats(records)
    print_table(stats, out)
    written: dict[str, Any] = {"points": [s.as_dict() for s in stats], "pictures": []}
    keys = numeric_keys(stats)
    for tree in sorted({s.tree for s in stats}):
        ts = [s for s in stats if s.tree == tree]
        if len(keys) >= 2:
            for a in range(len(keys)):
                for b in range(a + 1, len(keys)):
                    p = os.path.join(out_dir, f"heat_{tree}_{keys[a]}__{keys[b]}.png")
                    heat_map(ts, keys[a], keys[b], p, f"{name} / {tree}: success rate")
                    written["pictures"].append(p)
        for k in keys:
            others = [o for o in keys if o != k]
            p = os.path.join(out_dir, f"curve_{tree}_{k}.png")
            curve(ts, k, p, f"{name} / {tree}: success vs {k}",
                  by=others[0] if len(others) == 1 else None)
            written["pictures"].append(p)
    with open(os.path.join(out_dir, "report.json"), "w", encoding="utf-8") as fh:
        json.dump(written, fh, indent=1)
    for p in written["pictures"]:
        out.write(f"wrote {p}\n")
    return written


def best_and_worst(stats: Sequence[PointStats]) -> tuple[PointStats, PointStats] | None:
    """The best point (highest success, then fastest) and the worst (lowest success, then
    slowest)."""
    if not stats:
        return None
    def key(s: PointStats) -> tuple[float, float]:
        return (s.rate, -(s.mean_time_s if s.mean_time_s is not None else 1e9))
    ordered = sorted(stats, key=key)
    return ordered[-1], ordered[0]
