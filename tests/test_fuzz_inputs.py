"""Fuzz: mutated user files and device bytes get only our error types, never hang, and stay
within bounded memory (issue 18). bench/bench_robustness.py runs the large campaign."""

from __future__ import annotations

import signal
import tempfile
import tracemalloc

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from executive import fuzz

HANG_S = 20.0           # a load that runs this long is a hang (a guard, not a timing check)
MEMORY_BYTES = 256e6    # traced allocations of one load


class _Hang(Exception):
    pass


def _alarm(_signum: int, _frame: object) -> None:
    raise _Hang()


def _bounded(call):
    """Run ``call`` under a hang guard and tracemalloc; return (its result, peak bytes)."""
    old = signal.signal(signal.SIGALRM, _alarm)
    tracemalloc.start()
    signal.setitimer(signal.ITIMER_REAL, HANG_S)
    try:
        result = call()
    except _Hang:
        result = f"crash: hang past {HANG_S} s"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        signal.signal(signal.SIGALRM, old)
    return result, peak


FUZZ = settings(max_examples=30, deadline=None, derandomize=True, database=None,
                suppress_health_check=list(HealthCheck))


@pytest.mark.parametrize("area", fuzz.AREAS)
@FUZZ
@given(seed=st.integers(0, 2**32 - 1), which=st.integers(0, 100))
def test_loader_gives_only_its_own_error(area: str, seed: int, which: int) -> None:
    seeds = fuzz.seed_files(area)
    data = fuzz.mutate(seeds[which % len(seeds)], np.random.default_rng(seed))
    with tempfile.TemporaryDirectory() as folder:
        outcome, peak = _bounded(lambda: fuzz.load(area, data, folder))
    assert outcome in ("ok", "clean"), (outcome, data[:300])
    assert peak < MEMORY_BYTES


@pytest.mark.parametrize("area", fuzz.AREAS)
def test_unmutated_seed_files_load(area: str) -> None:
    """The seeds are valid: a refusal in the fuzz test comes from the damage."""
    with tempfile.TemporaryDirectory() as folder:
        for data in fuzz.seed_files(area):
            assert fuzz.load(area, data, folder) == "ok"


@pytest.mark.parametrize("name", fuzz.CODECS)
@settings(max_examples=4, deadline=None, derandomize=True, database=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_codec_gives_only_its_own_error(name: str, seed: int) -> None:
    (fed, chunks, refused, outcome), peak = _bounded(
        lambda: fuzz.feed_codec(name, 16 * 1024, np.random.default_rng(seed)))
    assert outcome == "clean" and fed >= 16 * 1024 and chunks > 0
    assert refused > 0   # the damage reached the parsers, not only the framing
    assert peak < MEMORY_BYTES
