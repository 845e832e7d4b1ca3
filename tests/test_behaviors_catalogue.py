"""Every registered node: documented, ports described, buildable and tickable with defaults."""

from __future__ import annotations

import itertools

import pytest
from py_trees.behaviours import StatusQueue
from py_trees.common import Status

from behaviors.base import Control, DecoratorNode, make, node_classes
from behaviors.registry import catalogue
from behaviors.testing import ScriptedWorld
from navcore.types import Pose2D

_ns = itertools.count()
CLASSES = node_classes()
# Required ports without a default or well-known key, given a value for the smoke tick.
REQUIRED = {"Timeout": {"msec": 100}, "Delay": {"delay_msec": 100},
            "SetParameters": {"namespace": "DWAPlannerROS", "values": {"occdist_scale": 0.02}},
            "AreErrorCodesPresent": {"error_code": "{follow_path_error_code}",
                                     "error_codes_to_check": [105]}}


def test_catalogue_is_complete_and_documented():
    issue_nodes = """Sequence Fallback ReactiveSequence ReactiveFallback SequenceWithMemory Parallel
        PipelineSequence RecoveryNode RoundRobin IfThenElse RateController DistanceController
        SpeedController GoalUpdater SingleTrigger Inverter RetryUntilSuccessful Repeat Timeout
        Delay ForceSuccess ForceFailure ComputePathToPose ComputePathThroughPoses FollowPath
        NavigateToPose ClearEntireCostmap ClearCostmapExceptRegion ClearCostmapAroundRobot Spin
        BackUp DriveOnHeading Wait TemporaryGoal BackOffToPreviousPose SetParameters GoalReached
        GoalUpdated IsPathValid IsStuck IsOscillating IsLocalized IsBatteryLow TimeExpired
        DistanceTraveled IsGoalNearby WouldAPlannerRecoveryHelp WouldAControllerRecoveryHelp"""
    missing = set(issue_nodes.split()) - set(CLASSES)
    assert not missing
    for name, doc in catalogue().items():
        assert len(doc.summary) > 20, name
        for port in doc.ports:
            assert port.description, f"{name}.{port.name} has no description"


@pytest.mark.parametrize("name", sorted(CLASSES))
def test_every_node_builds_sets_up_and_ticks(name):
    cls = CLASSES[name]
    kwargs = {}
    if issubclass(cls, Control) and cls.MIN_CHILDREN > 0:
        n = cls.MIN_CHILDREN
        kwargs["children"] = [StatusQueue(f"c{i}", [Status.SUCCESS], Status.SUCCESS)
                              for i in range(n)]
    elif issubclass(cls, DecoratorNode):
        kwargs["child"] = StatusQueue("c", [Status.SUCCESS], Status.SUCCESS)
    ns = f"/cat{next(_ns)}"
    node = make(name, namespace=ns, port_values=REQUIRED.get(name, {}), **kwargs)
    world = ScriptedWorld()
    for m in node.iterate():
        m.setup(**world.components())
    from py_trees.blackboard import Client
    from py_trees.common import Access
    bb = Client(name="cat", namespace=ns)
    bb.register_key("goal", access=Access.WRITE)
    bb.goal = Pose2D(1.0, 0.0, 0.0)
    node.tick_once()
    assert node.status in (Status.SUCCESS, Status.FAILURE, Status.RUNNING)
    node.stop(Status.INVALID)
    assert node.status == Status.INVALID
