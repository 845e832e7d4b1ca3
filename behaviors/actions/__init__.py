"""Action nodes, one per file: navigation (plan, follow) and the recoveries (Nav2 behaviours)."""
