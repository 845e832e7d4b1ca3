"""Decorator nodes, one per file: BT.CPP's retry/repeat/timeout family, Nav2's throttles and goal handling."""
