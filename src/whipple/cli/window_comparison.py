"""How the automatic windows of ``whipple fit`` match reference windows (``--windows``, ``--compare``)."""

from __future__ import annotations

import numpy as np

from whipple.measurement.experiment import FitOptions, measure_window
from whipple.measurement.measure import MeasuredRuns
from whipple.measurement.reference_windows import compare_windows
from whipple.measurement.windows import Window


def print_comparison(name: str, reference: tuple[Window, ...], measured: MeasuredRuns,
                      options: FitOptions) -> None:
    """How the automatic windows match the reference ones, and the eigenvalues of both.

    Windows fitted already (the automatic ones, or the reference ones when they were fitted)
    are not fitted again.
    """
    compared = {w.run for w in reference}
    found = [w for run_ in measured if run_.run.name in compared for w in run_.search.windows]
    comparison = compare_windows(found, reference)
    print()
    if not reference:
        print(f"windows of {name}: none for these runs")
        return
    coverage = np.mean([m.coverage for m in comparison.matches if m.found is not None] or [0.0])
    print(f"automatic windows vs {name}: {comparison.matched} of {len(comparison.matches)} "
          f"matched (an automatic window overlaps at least half of the shorter of the two; "
          f"mean coverage of the matched ones {100 * coverage:.0f}%); {len(comparison.extra)} "
          f"automatic window(s) in no reference window")
    for missed in comparison.unmatched:
        print(f"  unmatched: {missed.run} {missed.start:.2f}-{missed.stop:.2f} s")
    runs = {run_.run.name: run_ for run_ in measured}
    fits = {(m.run.name, m.window): m.fit for run_ in measured for m in run_ if m.fit is not None}
    differences = []
    for match in comparison.matches:
        if match.found is None:
            continue
        run_ = runs[match.reference.run]
        pair = []
        for window in (match.found, match.reference):
            fit = fits.get((run_.run.name, window)) or measure_window(run_.run, window, options).fit
            pair.append(None if fit is None else fit.eigenvalue)
        if pair[0] is not None and pair[1] is not None:
            differences.append(pair[0] - pair[1])
    if differences:
        delta = np.array(differences)
        print(f"  eigenvalue on the automatic minus on the reference window, over "
              f"{delta.size} matched pair(s): median |Δd| {np.median(np.abs(delta.real)):.2f} 1/s, "
              f"median |Δw| {np.median(np.abs(delta.imag)):.2f} rad/s")
