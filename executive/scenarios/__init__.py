"""Scripted stuck-robot scenarios: the format (``parse``), generators, robot profiles, the
runner and the judging of a run. See docs/scenarios.md; ``executive.scenario`` re-exports the
public names."""

from executive.scenarios.check import RunRecord, check
from executive.scenarios.model import (Event, Expectation, Generate, MovingObstacle, Scenario,
                                       Shape, TimeRef, Window)
from executive.scenarios.parse import (REASON_NAMES, file_kind, load_scenario, parse_seeds,
                                       scenario_files, scenario_from_mapping,
                                       scenario_from_source)
from executive.scenarios.profiles import deep_merge, scenario_config
from executive.scenarios.run import (ScenarioResult, Task, Verdict, junit_xml, run_scenario,
                                     run_task, run_tasks, tasks_for, verdicts)
from executive.scenarios.source import ScenarioError, Source, parse_source, read_source

__all__ = ["Event", "Expectation", "Generate", "MovingObstacle", "REASON_NAMES", "RunRecord",
           "Scenario", "ScenarioError", "ScenarioResult", "Shape", "Source", "Task", "TimeRef",
           "Verdict", "Window", "check", "deep_merge", "file_kind", "junit_xml",
           "load_scenario", "parse_seeds", "parse_source", "read_source", "run_scenario",
           "run_task", "run_tasks", "scenario_config", "scenario_files",
           "scenario_from_mapping", "scenario_from_source", "tasks_for", "verdicts"]
