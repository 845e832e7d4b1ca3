"""Nav2 behaviour-tree nodes that navbt's first node set lacked (issue 19): path handling,
goal lists, selectors, costmap queries, the route-graph nodes, the cancel nodes and Nav2's
extra sequences, with Nav2's ports and semantics. behaviors.library imports every module."""
