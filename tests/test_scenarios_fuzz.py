"""Mutated scenario files get the project's own error (ScenarioError naming file and line), or
load: never another exception. Hypothesis mutates real catalogue files (bounded examples)."""

from __future__ import annotations

import re
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from executive.scenarios import ScenarioError, parse_source, scenario_from_source

HERE = Path(__file__).resolve().parent
SEEDS = [HERE / "scenarios" / n for n in ("goal_changed_during_recovery.yaml",
                                          "laser_dropout_stops_robot.yaml",
                                          "clutter_room_seeds.yaml", "parking_bay_small_yaw.yaml",
                                          "round_robot_narrow_passage.yaml")]
TEXTS = [p.read_text(encoding="utf-8") for p in SEEDS]
TOKENS = ["", "-", "1e999", "nan", "[", "]", "{", "}", ":", "null", "true", "0", "-1",
          "'x'", "1..0", "box", "circle", "at", "goal", "&a", "*a", "<<: *a", "!!binary x",
          "?", "\t", "\"", "99999999999999999999999999", "[1, 2]", "{box: [0,0,0,0]}",
          "after_recovery", "while_recovery", "expect", "seeds", "profile", "data", "#", "\x00"]

NAME = "mut.yaml"
LOCATED = re.compile(r"^mut\.yaml:\d+: ")


def _check(text: str) -> None:
    try:
        scenario_from_source(parse_source(text, NAME))
    except ScenarioError as e:
        for line in e.errors:
            assert LOCATED.match(line), line
            assert "Traceback" not in line


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, len(TEXTS) - 1), st.lists(
    st.tuples(st.floats(0, 1), st.sampled_from(["insert", "delete", "replace", "dupline"]),
              st.sampled_from(TOKENS)), min_size=1, max_size=4))
def test_mutated_scenarios_fail_only_with_located_scenario_errors(which, edits):
    text = TEXTS[which]
    for pos, op, tok in edits:
        i = int(pos * len(text))
        if op == "insert":
            text = text[:i] + tok + text[i:]
        elif op == "delete":
            text = text[:i] + text[i + 1 + len(tok):]
        elif op == "replace":
            j = text.find(" ", i)
            j = len(text) if j < 0 else j
            text = text[:i] + tok + text[j:]
        else:
            lines = text.splitlines(keepends=True)
            k = int(pos * max(len(lines) - 1, 0))
            text = "".join(lines[:k + 1] + lines[k:k + 1] + lines[k + 1:])
    _check(text)


@settings(max_examples=60, deadline=None)
@given(st.text(max_size=200))
def test_arbitrary_text_fails_cleanly(text):
    _check(text)
