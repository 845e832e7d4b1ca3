"""LayeredCostmap.queue_scan: costmaps fed lazily end up exactly as with every scan added."""

from __future__ import annotations

import os

import numpy as np

from executive.mission import World, build_mission
from executive.scenario import load_scenario, scenario_config
from executive.tree_loader import shipped_tree

HERE = os.path.dirname(os.path.abspath(__file__))


def _mission(scenario):
    config = scenario_config(scenario)
    world = World(scenario.objects, scenario.moving, scenario.phantoms, scenario.faults)
    return build_mission(shipped_tree("smach_recovery"), config, scenario.grid, scenario.start,
                         world=world, seed=scenario.seed)


def test_lazy_scans_give_the_same_costmaps_tick_by_tick_through_clears_and_resets():
    # The phantom obstacle blocks the way until a clearing recovery removes it: the run goes
    # through ClearCostmapExceptRegion (clear_outside) and ClearEntireCostmap (reset_layers).
    s = load_scenario(os.path.join(HERE, "scenarios", "phantom_obstacle.yaml"))
    lazy, eager = _mission(s), _mission(s)
    for k in ("local_costmap", "global_costmap"):
        eager.components[k].defer_scans = False      # eager: every scan added at once
    for m in (lazy, eager):
        m.executive.set_goal(s.goals[0])
    adds = {"lazy": 0, "eager": 0}
    for name, m in (("lazy", lazy), ("eager", eager)):
        for key in ("local_costmap", "global_costmap"):
            cm = m.components[key]
            add = cm.add_scan

            def counted(*a, _add=add, _name=name, **k):
                adds[_name] += 1
                return _add(*a, **k)
            cm.add_scan = counted
    for tick in range(400):
        a, b = lazy.executive.step(), eager.executive.step()
        assert a == b
        for key in ("local_costmap", "global_costmap"):
            ca, cb = lazy.components[key].costmap, eager.components[key].costmap
            assert (ca.origin_x, ca.origin_y) == (cb.origin_x, cb.origin_y)
            assert np.array_equal(np.asarray(ca.costs), np.asarray(cb.costs)), (tick, key)
        if a.name in ("SUCCESS", "FAILURE"):
            break
    fired = {r["type"] for r in lazy.executive.trace.recoveries}
    assert {"ClearCostmapExceptRegion", "ClearEntireCostmap"} <= fired
    assert lazy.executive.trace.poses == eager.executive.trace.poses
    assert adds["lazy"] < 0.6 * adds["eager"]   # most scans were never converted


def test_lazy_scans_match_eager_adds_under_random_scans_updates_clears_and_resets():
    """Random interleavings on two copies of the real costmaps: the lazy copy matches the one
    fed every scan at once after every operation, including clears (which recompose the map
    from the buffers at once) and resets (which empty them)."""
    from executive.stack import build_costmaps
    from navcore.clock import SimClock
    from navcore.types import LaserScan, Pose2D

    s = load_scenario(os.path.join(HERE, "scenarios", "phantom_obstacle.yaml"))
    config = scenario_config(s)
    clock = SimClock()
    eager, lazy = build_costmaps(config, s.grid, clock), build_costmaps(config, s.grid, clock)
    rng = np.random.default_rng(11)
    x0, y0 = s.start.x, s.start.y
    n_ops = {"scan": 0, "update": 0, "clear": 0, "reset": 0, "param": 0}
    for step in range(300):
        op = rng.choice(["scan", "scan", "scan", "update", "clear", "reset", "param"],
                        p=[0.3, 0.2, 0.15, 0.2, 0.07, 0.03, 0.05])
        which = int(rng.integers(0, 2))
        pose = Pose2D(x0 + rng.uniform(-0.5, 0.5), y0 + rng.uniform(-0.5, 0.5),
                      rng.uniform(-3.1, 3.1))
        if op == "scan":
            ranges = rng.uniform(0.2, 3.0, 181).astype(np.float32)
            scan = LaserScan(clock.now(), -np.pi / 2, np.pi / 2, np.pi / 180, 0.0, 0.1, 0.05,
                             4.0, ranges)
            for e, l in zip(eager, lazy):
                e.add_scan(scan, pose)
                l.queue_scan(scan, pose)
        elif op == "update":
            eager[which].update_map(pose)
            lazy[which].update_map(pose)
        elif op == "clear":
            for cm in (eager[which], lazy[which]):
                if step % 2:
                    cm.clear_outside(pose.x, pose.y, 1.0)
                else:
                    cm.clear_inside(pose.x, pose.y, 1.0)
        elif op == "param":
            # a SetParameters on the sensor sources between a scan and the next update: the
            # scan kept aside must still be added with the values it arrived under
            value = {"obstacle_range": float(rng.uniform(0.5, 3.0))}
            for cm in (eager[which], lazy[which]):
                for ns, params in cm.parameter_namespaces().items():
                    if "obstacle_range" in params and ns.count("/") == 2:
                        params.set(value)
        else:
            eager[which].reset_layers()
            lazy[which].reset_layers()
        n_ops[str(op)] += 1
        clock.sleep_until(clock.now() + 0.1)
        for e, l in zip(eager, lazy):
            assert np.array_equal(np.asarray(e.costmap.costs), np.asarray(l.costmap.costs)), \
                (step, op)
    assert min(n_ops.values()) > 0


def test_costmaps_update_at_their_own_fixed_rate():
    # robot.yaml: control at 10 Hz, local costmap 5 Hz, global 2 Hz: every 2nd and 5th tick,
    # never a tick late (a deadline of "now + period" in summed floats slipped by one tick)
    s = load_scenario(os.path.join(HERE, "scenarios", "phantom_obstacle.yaml"))
    m = _mission(s)
    period = m.executive.period
    rates = {k: m.components[k].params.update_frequency
             for k in ("local_costmap", "global_costmap")}
    ticks_of: dict[str, list[int]] = {k: [] for k in rates}
    tick = [0]
    for key in rates:
        cm = m.components[key]
        update = cm.update_map

        def counted(*a, _update=update, _key=key, **k):
            ticks_of[_key].append(tick[0])
            return _update(*a, **k)
        cm.update_map = counted
    m.executive.set_goal(s.goals[0])
    for tick[0] in range(200):
        if m.executive.step().name in ("SUCCESS", "FAILURE"):
            break
    assert tick[0] > 60
    for key, hz in rates.items():
        every = round(1.0 / (hz * period))
        assert every in (2, 5)
        # the first update paints the phantoms and updates once more on the same tick
        steps = np.diff(sorted(set(ticks_of[key])))
        assert steps.min() == steps.max() == every, (key, np.unique(steps))
