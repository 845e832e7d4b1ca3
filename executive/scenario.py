"""Scripted stuck-robot scenarios (the public names; the code lives in ``executive.scenarios``).

``load_scenario`` parses and validates a file (every problem as ``file:line: what``);
``run_scenario`` runs it against one tree in the simulator and returns a ``ScenarioResult``
saying whether each expectation held. The format is documented in ``docs/scenarios.md``.
"""

from __future__ import annotations

from executive.scenarios import *  # noqa: F401,F403
from executive.scenarios import __all__  # noqa: F401
from executive.scenarios.model import OUTCOMES  # noqa: F401
