"""behaviors.base: py_trees' generator ticking, lazy feedback."""

from __future__ import annotations

import itertools

import pytest
from py_trees.behaviours import StatusQueue
from py_trees.common import Status

from behaviors.base import Leaf, PortInformation, make

S, F, R, I = Status.SUCCESS, Status.FAILURE, Status.RUNNING, Status.INVALID
_ns = itertools.count()


def q(name, statuses, eventually=None):
    return StatusQueue(name=name, queue=statuses, eventually=eventually)


def recovery_tree():
    ns = f"/base{next(_ns)}"
    main = make("Sequence", namespace=ns, children=[q("a", [S, F, S], S), q("b", [R, F, S], S)])
    rec = make("Inverter", namespace=ns, child=q("c", [F, F], F))
    return make("RecoveryNode", namespace=ns, children=[main, rec], number_of_retries=3)


def test_tick_yields_each_node_as_it_finishes_with_its_status_then():
    # RecoveryNode re-ticks its main child in the same tick: nodes come more than once, in
    # order, each with the status it had when it finished its tick (before any later halt).
    root = recovery_tree()
    seen = [[(n.name, n.status) for n in root.tick()] for _ in range(3)]
    assert seen[0] == [("a", S), ("b", R), ("Sequence", R), ("RecoveryNode", R)]
    assert seen[1] == [("b", F), ("Sequence", F), ("c", F), ("Inverter", S),
                       ("a", F), ("Sequence", F), ("c", F), ("Inverter", S),
                       ("a", S), ("b", S), ("Sequence", S), ("RecoveryNode", S)]
    assert seen[2] == [("a", S), ("b", S), ("Sequence", S), ("RecoveryNode", S)]


def test_feedback_is_formatted_when_read():
    node = make("Wait", namespace=f"/base{next(_ns)}", wait_duration=1.0)
    node.say("{:.2f} m of path left, {}", 1.23456, "ok")
    assert node.feedback_message == "1.23 m of path left, ok"
    node.say("plain")
    assert node.feedback_message == "plain"
    node.feedback_message = "set directly"
    assert node.feedback_message == "set directly"


def test_a_wired_port_holding_the_wrong_type_is_an_error_naming_it():
    import py_trees
    import pytest

    ns = f"/base{next(_ns)}"
    node = make("FollowPath", namespace=ns, path="{plan}")
    py_trees.blackboard.Blackboard.storage[f"{ns}/plan"] = "not a path"
    with pytest.raises(TypeError, match=r"port 'path' \(/base\d+/plan\) holds str, expected Path"):
        node.read("path")
    del py_trees.blackboard.Blackboard.storage[f"{ns}/plan"]
    assert node.read("path") is None


def test_later_instances_of_a_class_are_built_as_py_trees_builds_the_first():
    # the first instance of a node class goes through PortsMixin.__init__ (its abstract-class
    # check included); later ones skip the check: same attributes, same values otherwise
    class Probe(Leaf, register=False):
        INPUT_PORTS = {"x": PortInformation(float, False, "x", 1.0)}
        OUTPUT_PORTS: dict = {}

        def update(self):
            return S

    first, second = Probe(name="p"), Probe(name="p")
    third = Probe(name="q", behaviour_class_name="Alias")
    assert sorted(vars(first)) == sorted(vars(second)) == sorted(vars(third))
    for attr in ("_blackboard_client", "_subtree_namespace", "_ports_logger", "_literals",
                 "namespace", "status", "children", "parent", "blackboards"):
        assert getattr(first, attr) == getattr(second, attr), attr
    assert (first._behaviour_class_name, second._behaviour_class_name,
            third._behaviour_class_name) == ("Probe", "Probe", "Alias")
    assert first.id != second.id and third.name == "q"
    for node in (first, second):  # both wire and tick
        node.wire(f"/base{next(_ns)}")
        assert list(node.tick()) == [node] and node.status is S
        assert node.get_input("x") == 1.0


def test_a_class_without_port_declarations_is_refused_every_time():
    class NoPorts(Leaf, register=False):
        def update(self):
            return S

    for _ in range(2):
        with pytest.raises(TypeError, match="INPUT_PORTS and OUTPUT_PORTS"):
            NoPorts(name="n")
