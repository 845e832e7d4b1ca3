"""SequenceStar: BehaviorTree.CPP 3's name of SequenceWithMemory (BT.CPP 4 still registers it
for backward compatibility; Humble's trees use it)."""

from __future__ import annotations

from behaviors.controls.sequence import SequenceWithMemory


class SequenceStar(SequenceWithMemory):
    """SequenceWithMemory under its BehaviorTree.CPP 3 name: a child that FAILs makes the
    next tick resume at that child, not at the first."""
