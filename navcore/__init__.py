"""navbt's algorithms and message types (docs/architecture.md)."""

from navcore.kernel_cache import refresh_navbt

# before any kernel loads from numba's cache: drop kernels compiled from older sources
refresh_navbt()
