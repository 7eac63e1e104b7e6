"""Short gaps in a record filled by interpolation: a dropped row or two, an empty cell.

Loggers on a radio link or writing to a card drop a sample now and then, and a sensor can miss
a reading; a glitch (:mod:`whipple.measurement.glitches`) is left out as a missing sample too.
No window spans a gap (:mod:`whipple.measurement.record_gaps`), so a record that misses one
sample in twenty would be cut into pieces too short to fit (a simulated run with 5 % of its
rows dropped at random: 6 windows fitted and 134 stretches skipped, against 3 windows of 3-4 s
each without the drops).

A gap of at most :data:`FILLED_GAP` of missing samples holds nothing the window finder resolves
(it reads records at :data:`~whipple.measurement.swings.ANALYSIS_RATE`, two samples of which
span that time), so it is filled: a missing row gets the time between its neighbours and every
signal a value from the cubic through the two samples on each side (a straight line where a
side has one; a speedometer's pulses always a straight line, since a cubic overshoots a pulse's
edge). The cubic's error grows as the fourth power of the weave's angular frequency times the
gap: for a weave of 10 rad/s and two missing samples at 100 Hz it is at most 5e-5 of the
weave's amplitude (over every phase), far below any sensor's noise. Each filled sample stands
for the mean of its neighbours and carries less noise than a measured one, so a record with a
share p of its samples filled weighs its windows' noise and uncertainty as if it held up to
about p more samples than it does; the run's notes count the filled samples. Longer gaps, and
those at a record's ends, stay gaps.

The forward speed is filled further (:func:`fill_speed_gaps`): loggers that merge a GPS or a
wheel sensor read at 1-10 Hz into the rows of an inertial sensor read at 100 Hz or more leave
the speed's cells empty in between, and every window would have a gap. A speed changes slowly
(a coasting bicycle loses 0.02-0.08 m/s per second, steadily), so a straight line between
speeds up to :data:`SPEED_GAP` apart follows it to far below a speed sensor's noise.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from whipple.measurement.record_gaps import JUMP, contiguous

#: Longest stretch of missing samples that is filled [s]: two samples at the rate the window
#: finder reads records at (at least one of the record's own samples is always filled).
FILLED_GAP = 0.02
#: Signals filled by straight lines only: a speedometer's pulses.
LINEAR_ONLY = ("speedometer",)
#: Longest stretch without a forward speed that is filled by a straight line [s]: a speed
#: logged at 0.5 Hz or faster.
SPEED_GAP = 2.0


def longest_filled(step: float, longest: float = FILLED_GAP) -> int:
    """Return how many successive missing samples are filled, at a sample interval `step` [s]."""
    return max(1, int(np.floor(longest / step + 1e-9))) if step > 0 else 0


def fill_short_gaps(time: NDArray[np.float64], signals: dict[str, NDArray[np.float64]],
                    longest: float = FILLED_GAP) -> tuple[NDArray[np.float64], list[str]]:
    """Fill the record's short gaps in place; return the times with the dropped rows put back, and notes.

    Parameters
    ----------
    time : ndarray, shape (n,)
        Sample times [s], strictly increasing.
    signals : dict of str to ndarray, shape (n,)
        The record's signals (NaN where a sample has no value); replaced, in the dict, by
        arrays with the dropped rows put back and the short gaps filled.
    longest : float
        Longest stretch of missing samples filled [s] (at least one sample; 0 fills none).

    Returns
    -------
    time : ndarray, shape (m,)
        The times with a time for each dropped row of a short jump (evenly between its
        neighbours).
    notes : list of str
        What was filled, for the run's warnings.
    """
    steps = np.diff(time)
    if longest <= 0 or not steps.size:
        return time, []
    step = float(np.median(steps))
    most = longest_filled(step, longest)
    dropped = np.rint(steps / step).astype(np.int64) - 1
    jumps = np.flatnonzero((steps > JUMP * step) & (dropped >= 1) & (dropped <= most))
    notes = []
    inserted = np.zeros(time.size, dtype=bool)
    if jumps.size:
        counts = dropped[jumps]
        where = np.repeat(jumps + 1, counts)
        fractions = np.concatenate([np.arange(1, c + 1) / (c + 1) for c in counts.tolist()])
        time = np.insert(time, where, time[where - 1] + fractions * steps[np.repeat(jumps, counts)])
        inserted = np.insert(inserted, where, True)
        for name, values in signals.items():
            signals[name] = np.insert(values, where, np.nan)
        notes.append(f"{int(counts.sum())} dropped row(s) put back in {jumps.size} jump(s) in time of up to "
                     f"{int(counts.max())} sample(s), their values filled by interpolation")
    for name, values in signals.items():
        filled = _fill(time, values, most, linear=name in LINEAR_ONLY)
        own = int(np.count_nonzero(~inserted[filled]))
        if own:
            notes.append(f"{name}: {own} missing sample(s) in gaps of up to {most} sample(s) filled by "
                         "interpolation")
    return time, notes


def _fill(time: NDArray[np.float64], values: NDArray[np.float64], most: int, linear: bool) -> NDArray[np.intp]:
    """Fill the runs of at most `most` NaN samples between finite ones in place; return the filled indices."""
    missing = [(a, b) for a, b in contiguous(np.isnan(values)) if b - a <= most and a > 0 and b < values.size]
    if not missing:
        return np.array([], dtype=np.intp)
    finite = np.isfinite(values)
    targets = []
    for a, b in missing:
        before = [i for i in (a - 2, a - 1) if i >= 0 and finite[i]]
        after = [i for i in (b, b + 1) if i < values.size and finite[i]]
        used = before + after if not linear and len(before) == 2 and len(after) == 2 else [a - 1, b]
        for k in range(a, b):
            # The polynomial through the nodes, in powers of the time from the missing sample: its
            # value there is the constant coefficient.
            values[k] = np.polynomial.polynomial.polyfit(time[used] - time[k], values[used], len(used) - 1)[0]
            targets.append(k)
    return np.array(targets, dtype=np.intp)


def fill_speed_gaps(time: NDArray[np.float64], speed: NDArray[np.float64], longest: float = SPEED_GAP) -> list[str]:
    """Fill the gaps of up to `longest` [s] between forward speeds in place, by straight lines; return notes.

    Parameters
    ----------
    time : ndarray, shape (n,)
        Sample times [s], strictly increasing.
    speed : ndarray, shape (n,)
        Forward speed [m/s], NaN where a row has none; gaps at the record's ends stay.
    longest : float
        Longest gap filled [s] (0 fills none).
    """
    steps = np.diff(time)
    if longest <= 0 or not steps.size or not np.isnan(speed).any():
        return []
    filled = _fill(time, speed, longest_filled(float(np.median(steps)), longest), linear=True)
    if not filled.size:
        return []
    return [f"speed: {filled.size} missing sample(s) in gaps of up to {longest:g} s filled by straight lines (a "
            "speed logged at a lower rate than the other signals?)"]
