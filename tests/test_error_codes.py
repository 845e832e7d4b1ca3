"""The one table from navcore's results to Nav2's error codes (navcore.error_codes): every
result a planner or controller can emit is in it, and everything in it is emitted somewhere."""

from __future__ import annotations

import pathlib
import re

from navcore.controllers.result import ControlStatus
from navcore.error_codes import (CONTROL_CODES, CONTROLLER_RECOVERABLE, PLAN_CODES,
                                 PLANNER_RECOVERABLE, ROUTE_RECOVERABLE, BackUpError,
                                 ControllerError, DriveOnHeadingError, PlannerError,
                                 RecoveryError, RouteErrorCode, SmootherError, SpinError,
                                 WaitError)
from navcore.planners.result import PlanReason

ROOT = pathlib.Path(__file__).resolve().parent.parent


def emitted(folder: str, enum: type) -> set:
    """Members of ``enum`` named in the sources under ``folder`` (outside their definitions)."""
    found = set()
    for path in (ROOT / folder).rglob("*.py"):
        if path.name == "result.py":
            continue
        for name in re.findall(rf"\b{enum.__name__}\.([A-Z_]+)\b", path.read_text()):
            found.add(enum[name])
    return found


def test_every_plan_reason_the_planners_emit_is_mapped_and_every_mapping_is_emitted():
    emitted_reasons = emitted("navcore/planners", PlanReason)
    assert PlanReason.NO_PATH in emitted_reasons and PlanReason.GOAL_OCCUPIED in emitted_reasons
    assert emitted_reasons == set(PLAN_CODES)        # NONE: the success of every planner
    assert set(PLAN_CODES) == set(PlanReason)        # and no reason outside the table


def test_every_failing_control_status_is_mapped_and_every_mapping_is_emitted():
    emitted_statuses = emitted("navcore/controllers", ControlStatus)
    ok = {ControlStatus.FOLLOWING, ControlStatus.ROTATING_TO_GOAL, ControlStatus.GOAL_REACHED}
    assert emitted_statuses - ok == set(CONTROL_CODES)
    assert set(CONTROL_CODES) | ok == set(ControlStatus)


def test_codes_the_nodes_write_are_nav2_s_and_defined():
    # every code a node writes comes from the table or is named in the node
    node_planner = emitted("behaviors", PlannerError) | set(PLAN_CODES.values())
    node_controller = emitted("behaviors", ControllerError) | set(CONTROL_CODES.values())
    assert {PlannerError.NONE, PlannerError.NO_VALID_PATH, PlannerError.INVALID_PLANNER,
            PlannerError.NO_VIAPOINTS_GIVEN, PlannerError.INVALID_GOAL} <= node_planner
    assert {ControllerError.NONE, ControllerError.NO_VALID_CONTROL, ControllerError.INVALID_PATH,
            ControllerError.PATIENCE_EXCEEDED, ControllerError.FAILED_TO_MAKE_PROGRESS,
            ControllerError.INVALID_CONTROLLER} <= node_controller
    # Nav2's numbers (nav2_msgs/action/*.action)
    assert (PlannerError.NO_VALID_PATH, ControllerError.NO_VALID_CONTROL) == (208, 106)
    assert (SpinError.COLLISION_AHEAD, BackUpError.COLLISION_AHEAD,
            DriveOnHeadingError.COLLISION_AHEAD, WaitError.TIMEOUT) == (703, 714, 723, 741)
    # the ranges do not overlap (a code tells which action wrote it)
    ranges = [{int(m) for m in e if m} for e in (PlannerError, ControllerError, RouteErrorCode,
                                                 SmootherError, SpinError, BackUpError,
                                                 DriveOnHeadingError, WaitError, RecoveryError)]
    assert sum(map(len, ranges)) == len(set().union(*ranges))
    # Nav2's defaults for WouldA...RecoveryHelp
    assert PLANNER_RECOVERABLE == [200, 208, 207]
    assert CONTROLLER_RECOVERABLE == [100, 104, 105, 106]
    assert ROUTE_RECOVERABLE == [400, 405, 404]


def test_a_plain_string_reason_finds_its_code():
    # planners from elsewhere (tests' scripted ones) may return the text: same code
    assert PLAN_CODES["no_path"] is PlannerError.NO_VALID_PATH
    assert CONTROL_CODES["no_valid_trajectory"] is ControllerError.NO_VALID_CONTROL


def test_unobserved_space_is_navbt_s_code_in_each_motion_recovery_range():
    # not Nav2's: the last code of each behaviour's range, navbt's own recoveries' 81x
    assert (SpinError.UNOBSERVED_SPACE, BackUpError.UNOBSERVED_SPACE,
            DriveOnHeadingError.UNOBSERVED_SPACE, RecoveryError.UNOBSERVED_SPACE) == (
                709, 719, 729, 812)
    # written by the nodes (BackUp and DriveOnHeading through their shared ERRORS table)
    assert SpinError.UNOBSERVED_SPACE in emitted("behaviors", SpinError)
    assert RecoveryError.UNOBSERVED_SPACE in emitted("behaviors", RecoveryError)
    source = (ROOT / "behaviors/actions/drive_on_heading.py").read_text()
    assert "self.ERRORS.UNOBSERVED_SPACE" in source
