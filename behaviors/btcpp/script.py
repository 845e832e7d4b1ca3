"""Script and ScriptCondition (BehaviorTree.CPP 4): the scripting subset of scripting.py."""

from __future__ import annotations

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from behaviors.btcpp.scripted import STORAGE, Scripted


class Script(Scripted, Leaf):
    """Run ``code`` (the scripting subset: assignments to blackboard entries, arithmetic,
    comparisons, enums) and SUCCEED. A statement that fails (an entry that does not exist) is
    an error of the tree, raised as BT.CPP does. (BT.CPP ``Script``.)"""

    INPUT_PORTS = {"code": PortInformation(str, True, "the script, e.g. \"count := count + 1\"")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    SCRIPT_PORTS = ("code",)

    def update(self) -> Status:
        program = self.program("code")
        if program is not None:
            program.run(STORAGE)
        return SUCCESS


class ScriptCondition(Scripted, Leaf):
    """SUCCESS when ``code`` evaluates to true, else FAILURE (BT.CPP ``ScriptCondition``)."""

    CATEGORY = "Condition"
    INPUT_PORTS = {"code": PortInformation(str, True, "an expression, e.g. \"battery > 0.2\"")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    SCRIPT_PORTS = ("code",)

    def update(self) -> Status:
        program = self.program("code")
        return SUCCESS if program is not None and program.true(STORAGE) else FAILURE
