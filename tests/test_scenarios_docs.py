"""Every example scenario in docs/scenarios.md loads and meets its expectation against the
SMACH-style tree (multi-seed ones by their k-of-n rule; the real-map one is skipped with the
reason when the real data is absent)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from executive.scenarios import (load_scenario, parse_source, run_tasks, scenario_from_source,
                                 tasks_for, verdicts)

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "scenarios.md"
SMACH = str(ROOT / "trees" / "smach_recovery.yaml")


def _examples() -> list[tuple[str, str]]:
    blocks = re.findall(r"```yaml\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S)
    out = []
    for b in blocks:
        m = re.match(r"name: (doc_\w+)", b)
        if m:
            out.append((m.group(1), b))
    return out


EXAMPLES = _examples()


def test_every_feature_has_an_example():
    names = [n for n, _ in EXAMPLES]
    assert len(names) >= 7 and len(set(names)) == len(names)
    text = "\n".join(b for _, b in EXAMPLES)
    for feature in ("events:", "add:", "remove:", "fault:", "end_fault:", "phantom:",
                    "move_phantom:", "set:", "goal:", "add_goal:", "recoveries:", "any_of:",
                    "none_of:", "at_least:", "reason:", "final_pose:", "goals_reached:",
                    "stopped:", "slow_in:", "reverse:", "via:", "avoid:", "generate:",
                    "clutter:", "patrol:", "start_goal:", "seeds:", "pass_at_least:",
                    "profile:", "data:", "unknown: solid"):
        assert feature in text, f"no example uses {feature}"


@pytest.mark.parametrize("name,text", EXAMPLES, ids=[n for n, _ in EXAMPLES])
def test_doc_example_runs_and_meets_its_expectation(name, text, tmp_path, monkeypatch):
    from tests.conftest import data_root
    root = data_root()
    if root is not None:      # the example is written to a temporary folder: say where data is
        monkeypatch.setenv("NAVBT_DATA", str(root))
    path = tmp_path / f"{name}.yaml"
    path.write_text(text)
    s = load_scenario(path, check_config=True)
    results = run_tasks(tasks_for([(str(path), s)], [SMACH]))
    (v,) = verdicts(results, {s.name: s.needed()})
    if v.skipped:
        pytest.skip(results[0].detail)
    assert all(r.outcome != "error" for r in results), [r.detail for r in results]
    assert v.passed, [(r.seed, r.outcome, r.reason, r.failures) for r in results]
    assert sum(r.collisions for r in results) == 0


def test_doc_examples_parse_with_lines():
    for name, text in EXAMPLES:
        src = parse_source(text, f"{name}.yaml")
        assert src.line(("expect",)) is not None
        scenario_from_source(src)
