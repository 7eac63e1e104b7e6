"""Gaps in a record, which no window spans: samples without a value, and jumps in time.

:func:`whipple.measurement.windows.find_windows` bridges the gaps while it searches a record,
then cuts every window at them (:func:`parts_between`) and lists each gap as a rejected
stretch, saying what it is (:func:`gap_reason`). Short gaps (a dropped row or two, an empty
cell) are filled when a run is read (:mod:`whipple.measurement.short_gaps`); what is left here
is longer.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: A step in time longer than this many median sample intervals is a jump: samples were dropped.
JUMP = 1.5


def contiguous(valid: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """Return the ``(first, stop)`` index ranges of the stretches where `valid` holds."""
    edges = np.diff(np.concatenate(([0], valid.astype(np.int8), [0])))
    return list(zip(np.flatnonzero(edges == 1).tolist(), np.flatnonzero(edges == -1).tolist(), strict=True))


def record_gaps(time: NDArray[np.float64], usable: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """Return ``(first, stop)`` of each gap: unusable samples, or the two samples around a jump in time.

    A jump in time is a step of more than :data:`JUMP` times the median sample interval of `time` [s].
    """
    steps = np.diff(time)
    jumps = np.flatnonzero(steps > JUMP * np.median(steps)) if steps.size else np.array([], dtype=int)
    gaps = contiguous(~usable) + [(int(j), int(j) + 2) for j in jumps if usable[j] and usable[j + 1]]
    return sorted(gaps)


def parts_between(time: NDArray[np.float64], first: int, stop: int,
                  gaps: list[tuple[int, int]]) -> list[tuple[int, int]] | None:
    """Return the ``(first, stop)`` sample ranges of ``first:stop`` between the gaps, or None.

    None when the stretch holds no gap; parts of fewer than 3 samples are left out. A jump in
    time keeps both its samples: the gap lies between them.
    """
    inside = [(a, b) for a, b in gaps if a < stop and b > first]
    if not inside:
        return None
    steps = np.diff(time)
    parts = []
    for a, b in inside:
        if b - a == 2 and np.all(np.isfinite(time[a:b])) and steps[a] > JUMP * np.median(steps):
            a = b = a + 1
        if a - first >= 3:
            parts.append((first, a))
        first = b
    if stop - first >= 3:
        parts.append((first, stop))
    return parts


def gap_reason(time: NDArray[np.float64], first: int, stop: int, usable: NDArray[np.bool_]) -> str:
    """Why the stretch ``first:stop`` is a gap: samples without a value, or a jump in time [s]."""
    missing = int(np.count_nonzero(~usable[first:stop]))
    what = (f"{missing} sample(s) without a value" if missing
            else f"time jumps from {time[first]:.3f} to {time[stop - 1]:.3f} s")
    return f"rejected: gap: {what}; no window spans a gap"
