"""Control nodes, one per file (a family per file where they share a shape): BT.CPP and Nav2 semantics."""
