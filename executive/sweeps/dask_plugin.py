"""The Dask worker plugin that warms each worker's numba kernels once (imports dask.distributed,
so only ``runner.dask_client`` imports it).

A plugin, not ``client.run``: the scheduler also gives it to every worker that joins later (a
cluster scaled up, a worker its nanny restarted), so no worker pays the kernel loading in a run.
"""

from __future__ import annotations

import asyncio
from typing import Any

from distributed import WorkerPlugin

from executive.sweeps.runner import warm_worker


class WarmKernels(WorkerPlugin):
    name = "navbt-warm-kernels"

    async def setup(self, worker: Any) -> None:
        # in a thread: a cold numba cache compiles for tens of seconds, and the worker's event
        # loop must keep answering the scheduler meanwhile
        await asyncio.to_thread(warm_worker)
