"""Whether a run's roll rate has the model's units, judged by the leans its weave implies.

A roll rate logged in deg/s and read as rad/s is 57.3 times too large. Its weave's eigenvalue
is the same (a fit is scale-free), and without a steer angle to compare with
(:mod:`whipple.measurement.steer_sign`) nothing else in the windows shows it; but the lean the
weave implies does. A free weave of roll-rate amplitude A [rad/s] and eigenvalue lambda [1/s]
leans by A / |lambda| [rad]: at the start of a window, after a push, a few tenths of a radian
at most (the bundled and shared real runs: 175 windows, at most 0.26, median 0.10; simulated
runs of the window finder's procedures, 370 windows: at most 0.22). Beyond pi/2 the bicycle
would lie flat on the ground and not weave at all, so a data set whose windows start there
(median) is flagged, whatever the bicycle; in deg/s, a median lean of 0.03 rad already reads
as 1.6.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from whipple.measurement.experiment import WindowMeasurement

#: Lean [rad] beyond which no bicycle weaves: lying flat.
FLAT = np.pi / 2


def roll_unit_problem(measurements: Sequence[WindowMeasurement]) -> str | None:
    """Say why the usable windows' roll rate seems to be in other units than rad/s, or None.

    Parameters
    ----------
    measurements : sequence of WindowMeasurement
        The windows; the usable ones whose fit holds the roll rate are looked at.

    Returns
    -------
    str or None
        A sentence when the median lean at the windows' starts, the roll rate's fitted
        amplitude over the eigenvalue's magnitude, exceeds :data:`FLAT`; else None.
    """
    leans = []
    for m in measurements:
        if m.usable and m.fit is not None and "roll_rate" in m.fit.signal_names and abs(m.fit.eigenvalue) > 0:
            leans.append(m.fit.amplitude("roll_rate") / abs(m.fit.eigenvalue))
    if not leans or np.median(leans) <= FLAT:
        return None
    lean = float(np.median(leans))
    return (f"the weave's roll rate implies leans of {lean:.3g} rad ({np.degrees(lean):.3g} degrees) at the windows' "
            "starts (median), beyond lying flat: is the roll rate in deg/s? (a units row, a unit after the column's "
            "name or a layout's [scale] converts it)")
