"""Short robot motions the recoveries make: geometry (arcs, candidate poses, trails), footprint
collision checks along a motion, pure pursuit, and the search for a way out of a tight spot."""
