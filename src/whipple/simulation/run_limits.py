"""What every command accepts as a run, in one place: the simulator writes no run the reader refuses.

``whipple simulate`` checks its scenario against these limits before simulating, and
:func:`whipple.measurement.runs.read_run` checks every file against them, so that a file one
command writes the other reads.
"""

from __future__ import annotations

#: Lowest sample rate [Hz] of a run: a weave of 0.5-3 Hz needs several samples per period.
MIN_SAMPLE_RATE = 10.0
#: Shortest run [s]: a shorter one cannot hold a weave cycle (at most about 3 Hz at riding speeds,
#: 1 Hz and less below 4 m/s). Whether a longer run holds one, the fit of its windows says (a cut
#: segment of a published data set often holds just one cycle or two).
MIN_DURATION = 1.0
#: Fastest speed [m/s] of a run: beyond the fastest a bicycle has been ridden (82.8 m/s, paced
#: behind a vehicle). Only a unit or scale error gives more (a wild single sample is a glitch).
MAX_RUN_SPEED = 100.0
#: Largest standard deviation of a speed sensor's noise, as a share of the lowest speed of the
#: run: a speed 10 standard deviations above zero never reads negative (a chance of 1e-23 per
#: sample), and a sensor noisier than that is no speed sensor.
MAX_SPEED_NOISE_SHARE = 0.1

__all__ = ["MAX_RUN_SPEED", "MAX_SPEED_NOISE_SHARE", "MIN_DURATION", "MIN_SAMPLE_RATE"]
