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

    def tick(self) -> Ticking:
        self.begin_tick()
        all_done = True
        for child in self.children:
            self.current_child = child
            yield from child.tick()
            if child.status is FAILURE:
                self.halt_children()
                yield self.finish(FAILURE)
                return
            if child.status is not SUCCESS:
                all_done = False
        yield self.finish(SUCCESS if all_done else RUNNING)


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

    def tick(self) -> Ticking:
        self.begin_tick()
        index = self.read("current_child_idx")
        if index is None:
            self.say("current_child_idx is not set (set it with a Script or SetBlackboard)")
            yield self.finish(FAILURE)
            return
        while index < len(self.children):
            child = self.children[index]
            self.current_child = child
            yield from child.tick()
            if child.status is RUNNING:
                yield self.finish(RUNNING)
                return
            if child.status is FAILURE:
                self._store(0)
                self.halt_children()
                yield self.finish(FAILURE)
                return
            index += 1
            self._store(index)
        self._store(0)
        self.halt_children()
        yield self.finish(SUCCESS)
