"""Judging a finished run against its ``Expectation``: every way it missed, in words.

A ``RunRecord`` is what the runner saw each control tick (true pose and velocity of the body),
plus the recoveries with their start and end times, the event times and the end reason.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from navcore.types import Pose2D, normalize_angle

from executive.scenarios.model import Expectation, Shape, TimeRef


@dataclass
class RunRecord:
    """What one run did (the runner fills it; ``check`` reads it)."""

    outcome: str
    reason: str
    sim_time: float
    goals_reached: int
    goals_total: int
    final_pose: Pose2D
    goal: Pose2D | None                      # the goal being driven to at the end
    collisions: int
    recoveries: list[dict[str, Any]] = field(default_factory=list)  # name, type, t, end
    times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    xs: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ys: np.ndarray = field(default_factory=lambda: np.zeros(0))
    vs: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ws: np.ndarray = field(default_factory=lambda: np.zeros(0))
    events: dict[str, float] = field(default_factory=dict)        # event name -> time fired
    preempts: list[tuple[str, float, float]] = field(default_factory=list)  # (recovery, goal t, end)


def _matches(r: dict[str, Any], key: str) -> bool:
    return key in ("", "any") or r["type"] == key or r["name"] == key


def _time(ref: TimeRef, rec: RunRecord) -> float | None:
    if ref.event == "":
        return ref.at
    if ref.event == "end":
        return rec.sim_time + ref.delay
    t = rec.events.get(ref.event)
    return None if t is None else t + ref.delay


def _label(s: Shape) -> str:
    return s.name or f"{s.kind} {list(round(v, 3) for v in s.values)}"


def check(e: Expectation, rec: RunRecord) -> list[str]:
    """Every way the run missed its expectation (empty when it met it)."""
    f: list[str] = []
    if e.outcome is not None and rec.outcome not in e.outcome:
        f.append(f"outcome: expected {' or '.join(e.outcome)}, got {rec.outcome}")
    if e.reason is not None and rec.reason not in e.reason:
        f.append(f"reason: expected {' or '.join(e.reason)}, got {rec.reason or 'none'}")
    recs = rec.recoveries
    for r in e.recoveries_fired:
        if not any(_matches(x, r) for x in recs):
            f.append(f"recovery {r} must fire but did not")
    for r in e.recoveries_not_fired:
        if any(_matches(x, r) for x in recs):
            f.append(f"recovery {r} fired but must not")
    if e.recoveries_any_of and not any(_matches(x, r) for r in e.recoveries_any_of
                                       for x in recs):
        f.append(f"none of {', '.join(e.recoveries_any_of)} fired")
    for key, n in e.recoveries_at_least.items():
        got = sum(1 for x in recs if _matches(x, key))
        if got < n:
            f.append(f"{got} {key or 'recoveries'} fired, expected at least {n}")
    for key, n in e.recoveries_at_most.items():
        got = sum(1 for x in recs if _matches(x, key))
        if got > n:
            f.append(f"{got} {key or 'recoveries'} fired, expected at most {n}")
    if e.recoveries_order:
        i = 0
        for x in recs:
            if i < len(e.recoveries_order) and _matches(x, e.recoveries_order[i]):
                i += 1
        if i < len(e.recoveries_order):
            f.append(f"recoveries not in the order {' -> '.join(e.recoveries_order)} "
                     f"(fired: {', '.join(x['name'] for x in recs) or 'none'})")
    if e.no_collision and rec.collisions:
        f.append(f"{rec.collisions} collision(s)")
    if e.max_time is not None and rec.sim_time > e.max_time:
        f.append(f"took {rec.sim_time:.1f} s, more than max_time {e.max_time:g} s")
    if e.final_pose is not None:
        target, within, yaw = e.final_pose
        target = target if target is not None else rec.goal
        if target is None:
            f.append("final_pose: no goal to compare with")
        else:
            d = math.hypot(rec.final_pose.x - target.x, rec.final_pose.y - target.y)
            if d > within:
                f.append(f"ended {d:.2f} m from ({target.x:g}, {target.y:g}), more than "
                         f"{within:g} m")
            if yaw is not None:
                dy = abs(normalize_angle(rec.final_pose.theta - target.theta))
                if dy > yaw:
                    f.append(f"ended {dy:.2f} rad off the yaw {target.theta:g}, more than "
                             f"{yaw:g} rad")
    if e.goals_reached is not None:
        lo, hi = e.goals_reached
        if rec.goals_reached < lo or (hi is not None and rec.goals_reached > hi):
            want = f"{lo}" if hi == lo else f"at least {lo}" + (f", at most {hi}" if hi else "")
            f.append(f"reached {rec.goals_reached} goal(s), expected {want}")
    t, v, w = rec.times, rec.vs, rec.ws
    for win in e.stopped:
        a, b = _time(win.start, rec), _time(win.end, rec)
        if a is None:
            f.append(f"stopped: event {win.start.event!r} never happened")
            continue
        b = rec.sim_time if b is None else b
        m = (t >= a) & (t <= b)
        bad = m & ((np.abs(v) > win.v) | (np.abs(w) > win.w))
        if bad.any():
            i = int(np.argmax(bad))
            f.append(f"not stopped at t={t[i]:.1f} s (v={v[i]:.3f} m/s, w={w[i]:.3f} rad/s; "
                     f"window {a:.1f}..{b:.1f} s)")
    for shape, vmax in e.slow_in:
        inside = np.array([shape.contains(x, y) for x, y in zip(rec.xs, rec.ys)], bool)
        fast = inside & (np.abs(v) > vmax)
        if fast.any():
            i = int(np.argmax(fast))
            f.append(f"{abs(v[i]):.2f} m/s in {_label(shape)} at t={t[i]:.1f} s, more than "
                     f"{vmax:g}")
    if e.max_reverse_speed is not None and len(v) and -v.min() > e.max_reverse_speed:
        f.append(f"reversed at {-v.min():.2f} m/s, faster than {e.max_reverse_speed:g}")
    if e.max_reverse_time is not None and len(v):
        longest, run, prev = 0.0, 0.0, None
        for ti, vi in zip(t, v):
            if vi < -0.01 and prev is not None:
                run += ti - prev
            elif vi >= -0.01:
                run = 0.0
            longest = max(longest, run)
            prev = ti
        if longest > e.max_reverse_time:
            f.append(f"reversed for {longest:.1f} s in one go, longer than "
                     f"{e.max_reverse_time:g} s")
    for shape in e.via:
        if not any(shape.contains(x, y) for x, y in zip(rec.xs, rec.ys)):
            f.append(f"never passed through {_label(shape)}")
    for shape in e.avoid:
        hits = [ti for ti, x, y in zip(t, rec.xs, rec.ys) if shape.contains(x, y)]
        if hits:
            f.append(f"entered {_label(shape)} at t={hits[0]:.1f} s")
    if e.preempt_within is not None:
        for name, tg, end in rec.preempts:
            if end - tg > e.preempt_within:
                f.append(f"recovery {name} ran {end - tg:.1f} s after the goal changed, "
                         f"more than {e.preempt_within:g} s")
    return f
