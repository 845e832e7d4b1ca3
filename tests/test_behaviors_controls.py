"""Control nodes, tick by tick, with scripted children (STYLE 1.5)."""

from __future__ import annotations

import itertools

import pytest
from py_trees.behaviours import StatusQueue
from py_trees.common import Status

from behaviors.base import make

S, F, R, I = Status.SUCCESS, Status.FAILURE, Status.RUNNING, Status.INVALID
_ns = itertools.count()


def q(name: str, statuses: list[Status], eventually: Status | None = None) -> StatusQueue:
    return StatusQueue(name=name, queue=statuses, eventually=eventually)


def build(node_type: str, children, **ports):
    return make(node_type, namespace=f"/ctl{next(_ns)}", children=children, **ports)


def ticks(node, n: int) -> list[Status]:
    out = []
    for _ in range(n):
        node.tick_once()
        out.append(node.status)
    return out


class Counter(StatusQueue):
    """A StatusQueue that counts its ticks and halts (stop while RUNNING)."""

    def __init__(self, name, queue, eventually=None):
        super().__init__(name=name, queue=queue, eventually=eventually)
        self.ticked = 0
        self.halted = 0

    def update(self):
        self.ticked += 1
        return super().update()

    def terminate(self, new_status):
        if new_status == Status.INVALID and self.status == Status.RUNNING:
            self.halted += 1


def test_sequence_resumes_at_running_child_and_restarts_after_failure():
    a, b = Counter("a", [S, S, S], S), Counter("b", [R, S, F], F)
    seq = build("Sequence", [a, b])
    assert ticks(seq, 1) == [R] and (a.ticked, b.ticked) == (1, 1)
    assert ticks(seq, 1) == [S] and (a.ticked, b.ticked) == (1, 2)  # a not re-ticked
    # py_trees: finished children keep their status until the next run starts (BT.CPP resets
    # them at once; either way the next run ticks them afresh)
    assert a.status == b.status == S
    assert ticks(seq, 1) == [F] and (a.ticked, b.ticked) == (2, 3)
    assert a.status == S and b.status == F and a.halted == b.halted == 0


def test_sequence_with_memory_retries_the_failed_child_not_the_first():
    a, b = Counter("a", [S], S), Counter("b", [F, S], S)
    seq = build("SequenceWithMemory", [a, b])
    assert ticks(seq, 1) == [F]
    assert ticks(seq, 1) == [S]
    assert (a.ticked, b.ticked) == (1, 2)


def test_reactive_sequence_halts_running_child_when_condition_fails():
    cond = Counter("cond", [S, S, F], F)
    act = Counter("act", [R, R, R], R)
    seq = build("ReactiveSequence", [cond, act])
    assert ticks(seq, 2) == [R, R]
    assert cond.ticked == 2 and act.ticked == 2
    assert ticks(seq, 1) == [F]
    assert act.halted == 1 and act.status == I


def test_fallback_and_reactive_fallback():
    a, b = Counter("a", [F, F], F), Counter("b", [R, S], S)
    fb = build("Fallback", [a, b])
    assert ticks(fb, 2) == [R, S]
    assert a.ticked == 1  # Fallback resumes at the running child
    hi, lo = Counter("hi", [F, S], S), Counter("lo", [R, R], R)
    rfb = build("ReactiveFallback", [hi, lo])
    assert ticks(rfb, 2) == [R, S]
    assert lo.halted == 1 and hi.ticked == 2


def test_parallel_thresholds():
    a, b = Counter("a", [R, S], S), Counter("b", [R, R, S], S)
    par = build("Parallel", [a, b], success_count=-1, failure_count=1)
    assert ticks(par, 3) == [R, R, S]
    assert a.ticked == 2  # a finished child is not ticked again
    c, d = Counter("c", [F], F), Counter("d", [R], R)
    par = build("Parallel", [c, d], success_count=1, failure_count=1)
    assert ticks(par, 1) == [F] and d.halted == 1


def test_pipeline_sequence_reticks_earlier_children_while_later_runs():
    plan = Counter("plan", [S, S, S, S], S)
    follow = Counter("follow", [R, R, S], S)
    pipe = build("PipelineSequence", [plan, follow])
    assert ticks(pipe, 3) == [R, R, S]
    assert plan.ticked == 3 and follow.ticked == 3
    plan2 = Counter("plan2", [S, F], F)
    follow2 = Counter("follow2", [R, R], R)
    pipe = build("PipelineSequence", [plan2, follow2])
    assert ticks(pipe, 2) == [R, F]
    assert follow2.halted == 1


def test_recovery_node_recovers_in_the_same_tick_and_counts_retries():
    main = Counter("main", [F, F, S], S)
    fix = Counter("fix", [S, S], S)
    node = build("RecoveryNode", [main, fix], number_of_retries=2)
    assert ticks(node, 1) == [S]                 # F, fix, F, fix, S all in one tick
    assert (main.ticked, fix.ticked) == (3, 2)


def test_recovery_node_gives_up_after_its_retries():
    main = Counter("main", [F, F], F)
    fix = Counter("fix", [S], S)
    node = build("RecoveryNode", [main, fix], number_of_retries=1)
    node.tick_once()
    assert node.status == F
    assert main.status == F and fix.status == I  # main keeps its final status, fix was halted
    assert (main.ticked, fix.ticked) == (2, 1)


def test_recovery_node_running_recovery_and_failing_recovery():
    main = Counter("main", [F, S], S)
    fix = Counter("fix", [R, S], S)
    node = build("RecoveryNode", [main, fix], number_of_retries=1)
    assert ticks(node, 2) == [R, S]
    main = Counter("main", [F], F)
    fix = Counter("fix", [F], F)
    node = build("RecoveryNode", [main, fix], number_of_retries=5)
    assert ticks(node, 1) == [F] and fix.ticked == 1


def test_round_robin_moves_on_and_keeps_position_across_runs():
    kids = [Counter(f"c{i}", [S] * 5, S) for i in range(3)]
    rr = build("RoundRobin", kids, wrap_around=True)
    order = []
    for _ in range(4):
        before = [k.ticked for k in kids]
        rr.tick_once()
        assert rr.status == S
        order.append(next(i for i, k in enumerate(kids) if k.ticked > before[i]))
        rr.stop(I)  # the parent resets it after success: position is kept
    assert order == [0, 1, 2, 0]


def test_round_robin_tries_next_child_in_same_tick_and_fails_when_all_fail():
    kids = [Counter("a", [F], F), Counter("b", [F], F), Counter("c", [S], S)]
    rr = build("RoundRobin", kids, wrap_around=True)
    assert ticks(rr, 1) == [S] and [k.ticked for k in kids] == [1, 1, 1]
    kids = [Counter("a", [F] * 9, F), Counter("b", [F] * 9, F)]
    rr = build("RoundRobin", kids, wrap_around=True)
    assert ticks(rr, 1) == [F] and [k.ticked for k in kids] == [1, 1]


def test_round_robin_without_wrap_is_used_up_once():
    kids = [Counter("a", [S] * 3, S), Counter("b", [S] * 3, S)]
    rr = build("RoundRobin", kids, wrap_around=False)
    assert ticks(rr, 3) == [S, S, F]
    assert [k.ticked for k in kids] == [1, 1]
    assert ticks(rr, 1) == [S] and kids[0].ticked == 2  # starts again after giving up


def test_round_robin_halted_while_running_resets():
    kids = [Counter("a", [S], S), Counter("b", [R, R], R)]
    rr = build("RoundRobin", kids, wrap_around=True)
    rr.tick_once()                       # a succeeds
    rr.stop(I)
    rr.tick_once()
    assert rr.status == R and kids[1].ticked == 1
    rr.stop(I)                           # interrupted while b runs: back to the first child
    rr.tick_once()
    assert kids[0].ticked == 2


@pytest.mark.parametrize("cond,expected,branch", [(S, S, "then"), (F, F, "else")])
def test_if_then_else(cond, expected, branch):
    c = Counter("c", [cond], cond)
    then_, else_ = Counter("then", [R, S], S), Counter("else", [R, F], F)
    node = build("IfThenElse", [c, then_, else_])
    assert ticks(node, 2) == [R, expected]
    assert c.ticked == 1                  # the condition is not re-checked while a branch runs
    assert (then_.ticked, else_.ticked) == ((2, 0) if branch == "then" else (0, 2))


def test_if_then_without_else_fails_on_false():
    node = build("IfThenElse", [Counter("c", [F], F), Counter("t", [S], S)])
    assert ticks(node, 1) == [F]


def test_recovery_node_reset_after_restarts_the_recovery_list():
    from navcore.clock import SimClock
    clock = SimClock()
    # main: fail, run 3 ticks, fail, run 3 ticks, fail ... ; the recovery list is a RoundRobin
    main = Counter("main", [F, R, R, R, F, R, R, R, F, S], S)
    a, b = Counter("a", [S] * 5, S), Counter("b", [S] * 5, S)
    rr = build("RoundRobin", [a, b], wrap_around=False)
    node = build("RecoveryNode", [main, rr], number_of_retries=1, reset_after=0.1)
    node.setup(clock=clock)
    statuses = []
    for _ in range(7):
        node.tick_once()
        statuses.append(node.status)
        clock.advance(0.05)
    # each failure is followed by the *first* recovery again: RUNNING long enough resets
    assert statuses[-1] in (R, S) and F not in statuses
    assert (a.ticked, b.ticked) == (3, 0)
    plain = build("RecoveryNode", [Counter("m", [F, R, R, R, F], F),
                                   Counter("r", [S] * 3, S)], number_of_retries=1)
    plain.setup(clock=SimClock())
    assert F in ticks(plain, 5)                       # Nav2 default: no reset, gives up
