"""NonblockingSequence and PersistentSequence (Nav2 main controls)."""

from __future__ import annotations

import py_trees

from behaviors.base import FAILURE, RUNNING, SUCCESS, Control, PortInformation, Ticking


class NonblockingSequence(Control):
    """Tick every child each tick, in order, whatever the earlier ones returned: a FAILURE
    halts all and fails at once; SUCCESS (all halted) when every child succeeded this tick;
    otherwise RUNNING. (Nav2 main ``NonblockingSequence``: children that succeed are ticked
    again while others run.)"""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick_children(self) -> Ticking:
        all_done = True
        for child in self.children:
            self.current_child = child
            yield from child.tick()
            if child.status is FAILURE:
                self.halt_children()
                return FAILURE
            if child.status is not SUCCESS:
                all_done = False
        return SUCCESS if all_done else RUNNING


class PersistentSequence(Control):
    """A sequence whose position lives on the blackboard (``current_child_idx``), so it
    survives halts and tree reloads: it resumes at that child; a RUNNING child: RUNNING; a
    FAILURE: position 0, FAILURE; past the last child: position 0, SUCCESS. (Nav2 main
    ``PersistentSequence``; its trees set the key first, e.g. with a Script.)"""

    INPUT_PORTS = {"current_child_idx": PortInformation(int, True, "index of the child to "
                                                        "tick; written back as it moves")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def _store(self, index: int) -> None:
        key = self._keys.get("current_child_idx")
        if key is not None:  # a literal index cannot be written back (as a constant in BT.CPP)
            py_trees.blackboard.Blackboard.storage[key] = index

    def tick_children(self) -> Ticking:
        index = self.read("current_child_idx")
        if index is None:
            self.say("current_child_idx is not set (set it with a Script or SetBlackboard)")
            return FAILURE
        while index < len(self.children):
            child = self.children[index]
            self.current_child = child
            yield from child.tick()
            if child.status is RUNNING:
                return RUNNING
            if child.status is FAILURE:
                self._store(0)
                self.halt_children()
                return FAILURE
            index += 1
            self._store(index)
        self._store(0)
        self.halt_children()
        return SUCCESS
