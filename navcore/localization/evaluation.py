"""Accuracy figures of a pose track against a reference trajectory (for log and sim runs)."""

from __future__ import annotations

import numpy as np


def tracking_errors(estimate: np.ndarray, reference: np.ndarray, times: np.ndarray,
                    lost_threshold: float = 0.5) -> dict[str, float]:
    """Median / 95th-percentile position error (m), median / 95th heading error (deg), and the
    longest time (s) and number of consecutive samples with position error above
    ``lost_threshold``. ``estimate`` and ``reference`` are (N, 3) x, y, theta; ``times`` (N,)."""
    estimate = np.asarray(estimate, dtype=np.float64)
    reference = np.asarray(reference, dtype=np.float64)
    if estimate.shape != reference.shape or estimate.ndim != 2 or estimate.shape[1] != 3:
        raise ValueError(f"tracking_errors: shapes {estimate.shape} and {reference.shape} "
                         f"must both be (N, 3)")
    pos = np.hypot(*(estimate[:, :2] - reference[:, :2]).T)
    head = np.degrees(np.abs((estimate[:, 2] - reference[:, 2] + np.pi) % (2 * np.pi) - np.pi))
    lost_s, lost_n, start, run = 0.0, 0, None, 0
    for i, bad in enumerate(pos > lost_threshold):
        if bad:
            if start is None:
                start, run = i, 0
            run += 1
            # a stretch lasts until the next good sample
            end_t = times[i + 1] if i + 1 < len(times) else times[i]
            lost_s = max(lost_s, float(end_t - times[start]))
            lost_n = max(lost_n, run)
        else:
            start = None
    return {"median_m": float(np.median(pos)), "p95_m": float(np.percentile(pos, 95)),
            "median_deg": float(np.median(head)), "p95_deg": float(np.percentile(head, 95)),
            "max_m": float(pos.max()), "longest_lost_s": lost_s, "longest_lost_updates": lost_n}
