"""BehaviorTree.CPP 4 built-in nodes beyond navbt's first set (issue 19), and the safe subset
of its scripting language (scripting.py). behaviors.library imports every module."""
