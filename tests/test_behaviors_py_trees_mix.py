"""Stock py_trees behaviours inside navbt trees (and navbt nodes inside py_trees composites)
tick with one semantics, py_trees': statuses and stop() calls checked tick by tick."""

from __future__ import annotations

import itertools

import py_trees
from py_trees.common import Status

from behaviors.base import make

S, F, R, I = Status.SUCCESS, Status.FAILURE, Status.RUNNING, Status.INVALID
_ns = itertools.count()


def logged(cls, log):
    """``cls`` (a stock py_trees behaviour) recording every stop(new_status) in ``log``."""
    class Logged(cls):
        def stop(self, new_status=I):
            log.append((self.name, new_status))
            super().stop(new_status)
    Logged.__name__ = cls.__name__
    return Logged


def tick(root):
    """One tick through py_trees' generator API; the names yielded, in order."""
    return [n.name for n in root.tick()]


def test_reactive_sequence_over_a_py_trees_sequence_of_stock_behaviours():
    log = []
    ok = logged(py_trees.behaviours.Success, log)(name="ok")
    s1 = logged(py_trees.behaviours.Success, log)(name="s1")
    p = logged(py_trees.behaviours.Periodic, log)(name="p", n=1)  # R, S, S, F, F, R, R, ...
    seq = logged(py_trees.composites.Sequence, log)(name="seq", memory=False, children=[s1, p])
    root = make("ReactiveSequence", name="rs", namespace=f"/mix{next(_ns)}", children=[ok, seq])

    def statuses():
        return [n.status for n in (ok, s1, p, seq, root)]

    assert tick(root) == ["ok", "s1", "p", "seq", "rs"]
    assert statuses() == [S, S, R, R, R]
    assert log == [("ok", S), ("s1", S)]            # a leaf's final status stops it
    log.clear()

    tick(root)
    assert statuses() == [S, S, S, S, S]
    # finished children keep their status (py_trees): nothing is halted at the end of a run
    assert log == [("ok", S), ("s1", S), ("p", S), ("seq", S)]
    log.clear()

    tick(root)                                      # a new run: children stopped first
    assert statuses() == [S, S, S, S, S]
    assert log == [("ok", I), ("seq", I), ("s1", I), ("p", I),
                   ("ok", S), ("s1", S), ("p", S), ("seq", S)]
    log.clear()

    tick(root)                                      # p fails: the sequences fail
    assert statuses() == [S, S, F, F, F]
    assert log[-2:] == [("p", F), ("seq", F)]
    log.clear()

    tick(root)
    assert statuses() == [S, S, F, F, F]
    tick(root)                                      # p runs again
    assert statuses() == [S, S, R, R, R]
    log.clear()

    root.stop(I)                                    # a halt stops every child, depth first
    assert statuses() == [I, I, I, I, I]
    assert log == [("ok", I), ("seq", I), ("s1", I), ("p", I)]


def test_navbt_fallback_and_inverter_over_stock_running_and_periodic():
    log = []
    p2 = logged(py_trees.behaviours.Periodic, log)(name="p2", n=1)
    run = logged(py_trees.behaviours.Running, log)(name="run")
    ns = f"/mix{next(_ns)}"
    inv = make("Inverter", name="inv", namespace=ns, child=p2)
    root = make("Fallback", name="fb", namespace=ns, children=[inv, run])

    assert tick(root) == ["p2", "inv", "fb"]
    assert [n.status for n in (p2, inv, run, root)] == [R, R, I, R] and log == []

    assert tick(root) == ["p2", "inv", "run", "fb"]
    assert [n.status for n in (p2, inv, run, root)] == [S, F, R, R]
    assert log == [("p2", S)]                       # the inverter finished: its child keeps S
    log.clear()

    assert tick(root) == ["run", "fb"]              # resumes at the RUNNING child
    assert [n.status for n in (p2, inv, run, root)] == [S, F, R, R] and log == []

    root.stop(I)
    assert [n.status for n in (p2, inv, run, root)] == [I, I, I, I]
    assert log == [("p2", I), ("run", I)]


def test_navbt_nodes_inside_a_py_trees_selector():
    # the other way round: py_trees' Selector ticks navbt nodes through the same generator
    log = []
    ns = f"/mix{next(_ns)}"
    fail = make("AlwaysFailure", name="nope", namespace=ns)
    retry = make("RetryUntilSuccessful", name="retry", namespace=ns, num_attempts=2,
                 child=logged(py_trees.behaviours.Failure, log)(name="f"))
    sel = py_trees.composites.Selector("sel", memory=False, children=[fail, retry])
    assert tick(sel) == ["nope", "f", "retry", "sel"]
    assert [n.status for n in (fail, retry, sel)] == [F, R, R]
    assert log == [("f", F), ("f", I)]             # failed, then reset for the next attempt
    log.clear()
    assert tick(sel) == ["nope", "f", "retry", "sel"]
    assert [n.status for n in (fail, retry, sel)] == [F, F, F]
    assert log == [("f", F)]
