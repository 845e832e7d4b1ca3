"""Condition nodes, one per file: answer a question in one tick, never RUNNING."""
