"""Free-coasting windows: where a run's roll rate oscillates freely after a perturbation.

The roll rate is cut into swings (:mod:`whipple.measurement.swings`), the moves between successive
extremes of the low-passed signal. A free oscillation with eigenvalue ``d + i w`` changes its
swing height by a steady factor ``r = exp(d pi / w)`` per swing, and its half periods last
alike; pushes and catches break that pattern. From the swings:

* A **push** is a swing at least a quarter as high as the record's large swings (or twice
  its typical swing) that starts from rest, or at least doubles the swings of the period
  before it. Doubling is the most a free swing can do from rest (from ``-A`` to ``+r A``)
  unless the oscillation is growing, which the next swings reveal.
* A **push from rest** (out of a still stretch, quicker and lower than the swing back) need
  only stand out of the noise; its swing back is free whatever its height (a sharp push,
  blunted by the low-pass filter, looks far smaller than the 1 + r times its swing back), and
  the swing factor is read from the swings after it. Where the held bicycle's wobble stands
  out of the noise (a quiet sensor), a swing from rest no higher than twice the hold's own
  swings, followed by one higher than any free swing back that does not go on growing, is a
  wobble: the hand's push is the next swing.
* A weave **growing out of the noise** with no push seen (two swings each growing 1.2 to 4
  times, at the record's pace) starts a window too; so does the first sample of a record that
  starts in free motion (a segment cut after its push).
* The **window** starts at the extreme that ends the push (the roll rate turns back: the push
  is over) and runs while the swings follow one decay (or growth) factor. It ends when the
  oscillation sinks below the background (one period after its last clear extreme, or where a
  quick swing in that period starts: a held bicycle's wobble, plain above a quiet sensor's
  noise), comes to rest, stops oscillating (a swing lasting over two half periods), when a
  swing outgrows the trend or is over in under half the time of its neighbours (outside
  forcing: a new push, a hand), when a swing collapses far below the trend or is halfway
  through its height at once (a catch), when the signal saturates, or at the end of the
  record.
* The **record's end** may be where a segment was cut as a hand took hold: a window that
  reaches it leaves out its last samples, the low-pass filter's spread (in which a hand's
  mark cannot be told from the noise with no swing after it). A record that ends within the
  period after the last clear extreme of a dying oscillation ends that window at its last
  turn, less the same spread: its unfinished last swing is left out.
* A **grab**: the first swing after a push that is over in under half the record's half
  period and half the push's time, starting while the bicycle moves fast, is a hand catching
  the falling bicycle, not a free swing; it ends the window and starts none itself. A swing
  right after the push that starts slowly but is as quick, and over in under half the time of
  each swing beside it, is a catch too (a growing weave caught at its largest lean, where the
  roll rate turns): it ends the window, but the search for the next push still looks at it.
  So is a first swing over in under half the push's time that starts slower (the low-pass
  filter spreads the hand's sharp stop back to the extreme before it) when it, and every swing
  after it until the bicycle is still, is over in under half the record's half period: the
  hand's catch and return, then its hold.
* An unstable run may grow out of the noise and be caught within a swing or two, with no
  visible push: the swings that grew up to the catch form the window. They swing at the
  record's pace: the growth reaches back across no quick swing (a hand's catch out of a still
  stretch looks like a push from rest), nor to a swing that grows into the next by more than
  the growth's trend allows (``TREND_TOLERANCE`` times the next swing's growth: a push).
* A stretch with no free swing, or a single swing back followed by stillness (a push or a
  catch and its return), is rejected: no oscillation.

Every level comes from the record itself: the noise from the median absolute deviation of the
high-passed roll rate (read in the band of a record sampled at 100 Hz too, so that a record
sampled faster is read alike), the background from its typical swing, the filter and the
periods from its dominant frequency. Nothing depends on the bicycle. The rules use only
the roll rate; outside forcing that leaves no mark on it (e.g. a steer torque that the
bicycle's controller also applies) is not detected.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from whipple.errors import RunFileError
from whipple.measurement.record_gaps import gap_reason, parts_between, record_gaps
from whipple.measurement.rejections import no_oscillation
from whipple.measurement.runs import Run
from whipple.measurement.swings import Swings, swings_of
from whipple.measurement.window_search import Window, WindowSearch

__all__ = ["PUSH_RATIO", "TREND_TOLERANCE", "GROWTH", "STIR", "QUICK_PUSH", "SLOW_SWING_BACK", "ALIKE", "EARLY",
           "FIRST_GROWTH", "Window", "WindowSearch", "find_windows"]

#: Largest ratio of a free swing to the swing before it when starting from rest.
PUSH_RATIO = 2.0
#: A swing outgrowing the window's decay trend by more than this factor is forced.
TREND_TOLERANCE = 1.3
#: Successive swing ratios above this mean the oscillation is growing (unstable).
GROWTH = 1.2
#: A swing from rest this many times the noise floor of swing heights is a push.
STIR = 2.0
#: A push from rest is over in less than this share of the free swing after it.
QUICK_PUSH = 0.75
#: ... and that swing back lasts at most this many times the swing after it (half periods alike).
SLOW_SWING_BACK = 1.25
#: Half periods of a free oscillation differ by less than this factor (a growth's three swings).
ALIKE = 1.5
#: A swing halfway through its height within this share of its own time and of the swing
#: before it was stopped (a catch).
EARLY = 0.25
#: Before a free oscillation's swing ratio is known, a swing may outgrow the one before by this
#: factor (a weave growing at +1 1/s with a period of 2.5 s grows 3.5 times a swing).
FIRST_GROWTH = PUSH_RATIO**2


def find_windows(run: Run, signal: str = "roll_rate", valid: NDArray[np.bool_] | None = None) -> WindowSearch:
    """Find the free-coasting windows of a run automatically.

    Parameters
    ----------
    run : Run
        The run; its `signal` (default the roll rate [rad/s]) is analysed.
    signal : str
        Name of the oscillating signal to use.
    valid : ndarray of bool, optional
        Samples usable in a window (e.g. where every signal a fit needs has a value); by
        default where `signal` has one. Gaps (unusable samples, and jumps in time of more than
        1.5 sample intervals) are bridged by straight lines while the record is searched, so
        that its noise and levels, and the windows away from a gap, are those of the whole
        record; then every window is cut at the gaps, so that none spans one, and each gap is
        listed as a rejected stretch.

    Returns
    -------
    WindowSearch
        The windows found and the stretches rejected, each with its reason.

    Raises
    ------
    RunFileError
        If the run has no such signal.
    """
    if signal not in run.signals:
        raise RunFileError(f"no {signal} signal to find windows in", run.source)
    x = np.asarray(run.signals[signal], dtype=float)
    usable = np.isfinite(x) if valid is None else np.asarray(valid, dtype=bool) & np.isfinite(x)
    gaps = record_gaps(run.time, usable)
    if not usable.any():
        return WindowSearch(run.name, (), tuple(_gap(run, a, b, usable) for a, b in gaps), np.nan, np.nan, np.nan)
    if gaps:
        index = np.arange(x.size)
        x = np.interp(index, index[usable], x[usable])
    swings = swings_of(x, run.sample_rate)
    if swings.heights.size == 0:
        windows: list[Window] = []
        rejected: list[Window] = []
    else:
        windows, rejected = _Finder(run, x, swings).search()
    if gaps:
        windows = [part for window in windows for part in _cut(run, window, gaps)]
        rejected = sorted(rejected + [_gap(run, a, b, usable) for a, b in gaps], key=lambda w: w.start)
    return WindowSearch(run.name, tuple(windows), tuple(rejected), swings.noise,
                        swings.background, swings.frequency, tuple(int(i) for i in swings.stills))


def _cut(run: Run, window: Window, gaps: list[tuple[int, int]]) -> list[Window]:
    """Return the parts of `window` between the gaps (the whole window when it holds none)."""
    parts = parts_between(run.time, window.start_index, window.stop_index, gaps)
    if parts is None:
        return [window]
    time = run.time
    return [replace(window, start=float(time[a]), stop=float(time[b - 1]), start_index=a, stop_index=b,
                    notes=(*window.notes, f"cut at a gap ({time[a]:.2f}-{time[b - 1]:.2f} s of "
                                          f"{window.start:.2f}-{window.stop:.2f} s kept)"))
            for a, b in parts]


def _gap(run: Run, first: int, stop: int, usable: NDArray[np.bool_]) -> Window:
    """Return a rejected stretch for the gap ``first:stop``: unusable samples, or a jump in time."""
    return Window(run.name, float(run.time[first]), float(run.time[stop - 1]), first, stop,
                  gap_reason(run.time, first, stop, usable))


class _Finder:
    """Scan the swings of one run for windows (the state of one search)."""

    def __init__(self, run: Run, x: NDArray[np.float64], swings: Swings):
        self.run, self.x, self.smooth = run, x, swings.smooth
        # Swing j runs from extremes[j] to extremes[j + 1]; it starts from rest at a wake,
        # where rest[j] is the sample the still stretch began.
        self.extremes, self.rest = swings.extremes, swings.rest
        self.wakes = self.rest >= 0
        self.swings = swings.heights
        self.noise, self.quiet, self.loud = swings.threshold, swings.background, swings.loud
        # A swing from rest (the bicycle held, then let go) is a push from a lower height than
        # one out of motion: nothing moves before it, so standing out of the noise is enough.
        self.stir = min(self.loud, STIR * self.noise)
        # Where the still stretches end (sorted), for windows that must end at one.
        self.rests = self.rest[self.wakes]
        # The record's pace: its clear swings' typical duration (in a short segment the spectrum
        # cannot resolve the weave's frequency) [samples].
        clear = self.swings >= self.stir
        self.pace = float(np.median(np.diff(self.extremes)[clear])) if clear.any() else np.inf
        self.margin = max(1, int(run.sample_rate / (4 * swings.cutoff)))
        self.ratios = self.swings[1:] / np.maximum(self.swings[:-1], 1e-300)
        self.durations = np.diff(self.extremes)
        # Half a period of the record's dominant oscillation [samples].
        self.half_period = 0.5 * run.sample_rate / swings.frequency
        limit = 0.98 * np.max(np.abs(x))
        flat = np.r_[False, x[1:] == x[:-1]] & (np.abs(x) >= limit)
        # Three equal samples at the top of the range: the sensor (or the bicycle) hit a stop.
        self.saturated = np.flatnonzero(flat[1:] & flat[:-1])

    def ratio(self, j: int) -> float:
        return float(self.ratios[j - 1]) if j >= 1 else np.inf

    def sustained(self, j: int) -> bool:
        """Whether swing j's growth goes on (an unstable oscillation rather than a push).

        After a push, a free swing at most doubles; more than that, or growth over the next
        two swings, is the oscillation's own growth.
        """
        nxt = [self.ratio(i) for i in (j + 1, j + 2) if i < self.swings.size]
        if not nxt or self.abrupt(j + 1):
            return False
        return nxt[0] > PUSH_RATIO or (len(nxt) == 2 and min(nxt) > GROWTH)

    def abrupt(self, j: int) -> bool:
        """Whether swing j is over in under half the time of the swings around it.

        Successive half periods of one oscillation last about as long; a much quicker swing is
        driven (a hand catching the bicycle, a push).
        """
        if not 1 <= j < self.swings.size:
            return False
        around = self.durations[j - 1:j + 2:2]
        return bool(self.durations[j] < 0.5 * around.min())

    def grab(self, j: int) -> bool:
        """Whether swing j is a hand grabbing the moving bicycle (a catch as it falls).

        The record's oscillation sets how quick a free swing can be: a swing over in under half
        the record's half period and half the time of the swing before it, that starts while
        the bicycle moves fast (a roll rate of twice a push's least height), is a catch,
        whatever follows it (the return after a catch can be as quick). A push is quick too,
        but starts from near rest.
        """
        return 1 <= j < self.swings.size and bool(
            self.quick(j) and self.durations[j] < 0.5 * self.durations[j - 1]
            and abs(self.smooth[self.extremes[j]]) >= 2 * self.loud)

    def caught(self, j: int) -> bool:
        """Whether swing j is a hand catching the moving bicycle: a grab, or a catch it holds.

        A grab (:meth:`grab`) starts fast. A catch may start slower (the low-pass filter spreads
        the hand's sharp stop back to the extreme before it), but the hand then holds the
        bicycle: swing j, over in under half the time of the swing before it, and every swing
        after it until the bicycle is still, are each over in under half the record's half
        period. A free oscillation swings at its own pace until it sinks into the noise.
        """
        if self.grab(j):
            return True
        if not (1 <= j < self.swings.size and self.durations[j] < 0.5 * self.durations[j - 1]):
            return False
        later = int(np.searchsorted(self.rests, self.extremes[j], side="right"))
        if later >= self.rests.size:
            return False
        rest, i = int(self.rests[later]), j
        while i < self.swings.size and self.extremes[i] < rest:
            # A swing that runs on into the still stretch ends where the stillness begins.
            if min(int(self.extremes[i + 1]), rest) - int(self.extremes[i]) >= 0.5 * self.half_period:
                return False
            i += 1
        return i > j

    def quick(self, j: int) -> bool:
        """Whether swing j is over in under half the record's half period."""
        return bool(self.durations[j] < 0.5 * self.half_period)

    def is_push(self, j: int) -> bool:
        """Whether a window starts after swing j (a push, or the rise of an unstable one)."""
        # The push stands out from the motion before it (two swings: about a period), or
        # starts from rest.
        if (self.pushed_from_rest(j) or self.starts_growth(j)) and self.swings[j] >= self.stir:
            return True
        previous = 0.0 if self.wakes[j] else self.swings[max(j - 2, 0):j].max(initial=0.0)
        return self.swings[j] >= self.loud and (
            previous < self.quiet
            or self.swings[j] > PUSH_RATIO * previous
            or (self.ratio(j) > GROWTH and self.sustained(j))
        )

    def pushed_from_rest(self, j: int) -> bool:
        """Whether swing j is a push from rest: from a still stretch, quicker and lower than the swing back.

        The swing back after a push is a free half period, at the record's pace; the push itself
        is over sooner (a hand's hit). A weave that grows slowly out of the noise also starts from a still
        stretch, but its first clear swing lasts a half period too.
        """
        if not (self.wakes[j] and j + 1 < self.swings.size and self.durations[j] < QUICK_PUSH * self.durations[j + 1]):
            return False
        # The swing back goes from the push's height past the start (1 + r times the push), so
        # it is the higher; a hand's wobble while it holds the bicycle is followed by more of
        # the same.
        if self.swings[j + 1] < self.swings[j] or not self.at_pace(float(self.durations[j + 1])):
            return False
        # Where the sensor is quiet, the held bicycle's wobble stands out of the noise. A swing
        # from the still stretch no higher than STIR times the wobble in it, followed by one
        # higher than any free swing back (1 + r times the push, r at most FIRST_GROWTH) that
        # does not go on growing, is a wobble and the hand's push after it.
        if (self.swings[j] < STIR * self.wobble(j) and self.swings[j + 1] > (1 + FIRST_GROWTH) * self.swings[j]
                and not self.sustained(j + 1)):
            return False
        # A swing back slower than the swing after it is still pushed (a hand that hits, then
        # pushes on): the push ends with it.
        return j + 2 >= self.swings.size or bool(self.durations[j + 1] <= SLOW_SWING_BACK * self.durations[j + 2])

    def wobble(self, j: int) -> float:
        """Return the largest swing inside the still stretch that wake swing j leaves (0 if none)."""
        inside = (self.extremes[:-1] >= self.rest[j]) & (self.extremes[1:] <= self.extremes[j])
        return float(self.swings[inside].max(initial=0.0))

    def starts_growth(self, j: int) -> bool:
        """Whether swing j starts a weave growing out of the noise, with no push to be seen.

        The two swings after it each grow by more than ``GROWTH`` and at most ``FIRST_GROWTH``
        (a weave growing at up to about +1 1/s), none of them from a still stretch (that is a
        push from rest), and none of the three is quick: they swing at the pace of the record's
        oscillation (a push and the hand's catch do not), each lasting about as long as the
        others (within a factor ``ALIKE``).
        """
        if j + 2 >= self.swings.size or self.quick(j):
            return False
        # Half periods alike, as a free oscillation's are.
        durations = self.durations[j:j + 3]
        return bool(durations.max() <= ALIKE * durations.min()) and all(
            GROWTH < self.ratio(i) <= FIRST_GROWTH and not self.quick(i) and not self.wakes[i] for i in (j + 1, j + 2))

    def stops_early(self, j: int) -> bool:
        """Whether swing j gets halfway through its height within ``EARLY`` of its time and of the last swing's.

        A free swing, a damped or growing cosine from one extreme to the next, passes halfway
        between them a third to two thirds of the way through, about a third to two thirds of a
        half period (the swing before it) after it begins; one that a hand stops as it begins gets there at
        once and then stays still (a heavily damped free swing settles too, but at the pace of
        the oscillation). A swing that ends where the signal wakes from a still stretch has no
        extreme at its end to measure halfway to.
        """
        if j < 1 or (j + 1 < self.swings.size and self.wakes[j + 1]):
            return False
        a, b = int(self.extremes[j]), int(self.extremes[j + 1])
        middle = 0.5 * (self.smooth[a] + self.smooth[b])
        beyond = np.flatnonzero((self.smooth[a:b + 1] - middle) * np.sign(self.smooth[a] - middle) <= 0)
        # Early both within the swing (the rest of it is still) and against the swing before (a
        # heavily damped free swing settles early in a long swing too, but at the oscillation's
        # pace).
        return bool(beyond.size and beyond[0] < EARLY * min(b - a, self.durations[j - 1]))

    def in_motion_at_start(self) -> bool:
        """Whether the record starts in free motion: a segment cut after its push.

        The record does not start still, one of its first two swings (the first may be the end
        of one, cut short) stands out as a push out of motion would, and its first swings last
        about as long as the record's clear swings (within a factor ``ALIKE``), as the weave's
        do: a record that starts while the bicycle is handled swings at another pace.
        """
        starts_still = self.rests.size > 0 and self.rests[0] <= self.extremes[0]
        if not self.swings.size or starts_still or self.wakes[0] or self.swings[:2].max() < self.loud:
            return False
        return self.at_pace(float(np.median(self.durations[:3])))

    def at_pace(self, duration: float) -> bool:
        """Whether a swing of `duration` samples swings at the record's pace (within ``ALIKE``)."""
        return self.pace / ALIKE <= duration <= ALIKE * self.pace

    def held(self, j: int) -> bool:
        """Whether the two swings after swing j are no more than noise (the bicycle held)."""
        after = self.swings[j + 1:j + 3]
        return after.size > 0 and bool((after < 2 * self.noise).all())

    def is_growth(self, j: int) -> bool:
        """Whether swing j rises out of a growing oscillation rather than from rest."""
        previous = self.swings[j - 1] if j >= 1 else 0.0
        return previous >= self.quiet and self.sustained(j)

    def onset(self, j: int) -> int:
        """Sample at which forced swing j leaves the extreme it starts from."""
        a, b = self.extremes[j], self.extremes[j + 1]
        departure = np.abs(self.smooth[a:b + 1] - self.smooth[a])
        calm = np.flatnonzero(departure <= 0.1 * self.swings[j])
        return int(max(a, a + calm[-1] - self.margin))

    def search(self) -> tuple[list[Window], list[Window]]:
        windows: list[Window] = []
        rejected: list[Window] = []
        j = 0
        if self.in_motion_at_start():
            # A segment cut after its push: the free motion runs from the first sample. Its
            # first swing is partial where the record starts on it (its extreme lies before the
            # cut): it stands in for the push.
            window, j = self.follow(0 if self.extremes[0] <= self.margin else -1, at_start=True)
            (windows if not window.reason.startswith("rejected") else rejected).append(window)
        while j < self.swings.size:
            if not self.is_push(j):
                j += 1
                continue
            window, following = self.follow(j)
            if window.reason.startswith("rejected"):
                # Nothing free follows: the push was a catch, or the swing before one, perhaps
                # of an oscillation that grew.
                earliest = windows[-1].stop_index if windows else 0
                catch = min(following, self.swings.size - 1)
                window = self.growth_before(catch, earliest) or window
            (windows if not window.reason.startswith("rejected") else rejected).append(window)
            # A hand that grabbed the bicycle right after the push starts nothing; other
            # forcing may be the next push.
            grabbed = following == j + 1 and self.caught(following)
            j = max(following + grabbed, j + 1)
        return windows, rejected

    def growth_before(self, catch: int, earliest: int) -> Window | None:
        """Return the growing oscillation that catch swing `catch` ends, if any.

        The oscillation starts no earlier than sample `earliest`.

        Below the weave speed the oscillation grows out of the noise and is caught within a
        swing or two: the push that started it is too small to see.
        """
        first = catch - 1
        if first < 1 or self.swings[first] < self.loud:
            return None
        # Back through the swings that grew clearly (by half at least), down to twice the
        # background and four times the noise floor. A growing weave swings at the pace of the
        # record's oscillation: a quick swing is a hand (a catch out of a still stretch, which
        # looks like a push, or a push), and the growth does not reach back across it. Nor to a
        # swing that grows into the next by more than the growth's own trend (the next swing's
        # growth) allows: that swing was pushed. (Sampled fast, a push from rest is not always
        # quick; a fixed bound such as FIRST_GROWTH would cut weaves growing faster than +1 1/s.)
        floor = max(2 * self.quiet, 4 * self.noise)
        while (first > 0 and self.extremes[first - 1] >= earliest and not self.quick(first - 1)
               and floor <= self.swings[first - 1] < self.swings[first] / 1.5
               and (first + 1 >= catch or self.swings[first] / self.swings[first - 1]
                    <= TREND_TOLERANCE * self.swings[first + 1] / self.swings[first])):
            first -= 1
        if first == catch - 1:
            return None
        start, end = int(self.extremes[first]), self.onset(catch)
        if end - start < 3:
            return None
        time = self.run.time
        return Window(self.run.name, float(time[start]), float(time[end - 1]), start, end,
                      f"growth from {time[start]:.2f} s; ends: caught at {time[end]:.2f} s",
                      (f"growing oscillation caught after {catch - first} swing(s)",))

    def follow(self, push: int, at_start: bool = False) -> tuple[Window, int]:
        """Return the window after push swing `push`, and the swing to resume the scan at.

        `at_start`: the record starts in free motion, with no push in it (a segment cut after
        its push); the window starts at its first sample, and `push` is the partial swing the
        record starts on (-1 if none).
        """
        start = 0 if at_start else int(self.extremes[push + 1])
        # After a push from rest (where the bicycle was held) the first free swing starts from
        # rest: from -A to +r A it is (1 + r) times the push, at most twice unless the
        # oscillation grows; a sharp push, which the low-pass filter blunts, looks smaller still.
        # Its swing back is then free whatever its height, and the swing factor is read from the
        # swings after it. Out of a growing oscillation the push simply continues the growth.
        from_rest = at_start or self.pushed_from_rest(push)
        # Out of the noise (no push seen), the growth's first ratio is the first trend.
        rising = not from_rest and not self.is_growth(push) and self.starts_growth(push)
        growth = not from_rest and (self.is_growth(push) or rising)
        trend: list[float] = [self.ratio(push + 1 if rising else push)] if growth else []
        j = push + 1
        end, why, resume, tail = self.x.size, "end of record", self.swings.size, False
        # The oscillation has died out when its swings sink into the background, or below a
        # tenth of where they began when the record's background is itself oscillation.
        first = self.swings[max(push, 0):push + 2].max()
        level = max(self.noise, min(self.quiet, 0.1 * first))
        while j < self.swings.size:
            a = self.swings[j]
            half = np.median(np.diff(self.extremes[push + 1:j + 1])) if j > push + 1 else 0
            # The first estimate of the swing factor r: (1 + r) times the push for the first free
            # swing; a decaying oscillation is allowed a factor of 1 until two free swings give
            # the trend.
            if trend:
                factor = float(np.median(trend))
            else:
                factor = 1.0 if from_rest else max(1.0, self.ratio(push + 1) - 1)
            if (j > push + 1 or growth) and factor > GROWTH and self.ratio(j) < 1:
                # A growing oscillation that shrinks has been caught at the extreme before.
                end, why = int(self.extremes[j]) - self.margin, "caught (growth stops)"
                resume = j + 1
                break
            if trend and factor <= GROWTH and a < factor * self.swings[j - 1] / 3 and (
                factor * self.swings[j - 1] > 2 * level
            ):
                # A clear swing collapses far below the decay trend: the bicycle was caught.
                end, why = int(self.extremes[j]) - self.margin, "collapsed (a catch?)"
                resume = j + 1
                break
            # The first free swing may be quick after a slow push; quick and followed by
            # stillness, or far quicker than the record's oscillation, it is a catch (the
            # bicycle grabbed, perhaps as it fell). A catch at the largest lean starts slowly
            # (the roll rate turns there): quickness against both neighbours stands in for the
            # fast start.
            grabbed = j == push + 1 and (self.caught(j) or self.abrupt(j) and self.quick(j))
            if a >= level and (grabbed or self.abrupt(j) and (j > push + 1 or growth or self.held(j + 1))):
                end, resume = self.onset(j), j
                why = f"abrupt swing at {self.run.time[end]:.2f} s"
                break
            if a >= level and self.stops_early(j):
                # The swing is over at its start: a hand stopped the bicycle (or pushed it) as
                # the swing began.
                end, resume = int(self.extremes[j]) - self.margin, j
                why = f"stopped at {self.run.time[self.extremes[j]]:.2f} s (a catch?)"
                break
            if self.wakes[j]:
                end, why, resume = int(max(self.rest[j], start + 1)), "came to rest", j
                break
            if a < level:
                end, why = int(self.extremes[j] + 2 * half), "decayed into the background"
                resume, tail = j, True
                break
            if j > push + 1 and self.extremes[j + 1] - self.extremes[j] > 2 * half:
                end, why = int(self.extremes[j] + 2 * half), "oscillation stops (slow swing)"
                resume, tail = j, True
                break
            if j == push + 1 and not growth:
                expected = np.inf if from_rest else PUSH_RATIO * self.swings[push]
            elif not trend and from_rest:
                # The first swing ratio of the free oscillation: any growth up to FIRST_GROWTH.
                expected = FIRST_GROWTH * self.swings[j - 1] + 0.25 * level
            else:
                expected = TREND_TOLERANCE * factor * self.swings[j - 1] + 0.25 * level
            if a > expected and not self.sustained(j):
                end, resume = self.onset(j), j
                why = f"forcing at {self.run.time[end]:.2f} s"
                break
            if j > push + 1 or growth:
                trend.append(self.ratio(j))
            j += 1
        else:
            # No swing above the noise after the last extreme: the rest is quiet.
            spans = np.diff(self.extremes[max(push, 0):])
            half = np.median(spans) if spans.size else self.half_period
            end, why = int(self.extremes[-1] + 2 * half), "decayed into the noise"
        # A tail added after the last clear extreme must not reach into the next push, nor into a
        # hand's hold: a swing there that stands out of the noise but is quick (over in under
        # half the record's half period) is no free swing of the decay. (A swing the record's
        # end cuts short is no quicker than the cut.)
        later = next((i for i in range(j, self.swings.size) if self.is_push(i)), None)
        hand = next((i for i in range(j, self.swings.size) if self.extremes[i] < end and self.quick(i)
                     and self.extremes[i + 1] < self.x.size - 1), None) if tail else None
        if hand is not None and self.onset(hand) < end and (later is None or hand < later):
            end = self.onset(hand)
            why = f"quick swing at {self.run.time[end]:.2f} s (a hand?)"
        elif tail and later is not None and self.onset(later) < end:
            end = self.onset(later)
            why = f"next push at {self.run.time[end]:.2f} s"
        elif tail and end > self.x.size:
            # The record ends inside the tail: a segment cut where the bicycle was caught, as
            # the motion died out. Its last swing is unfinished, and no rule can tell a hand on
            # it (one that holds the bicycle turns the roll rate at the record's last turn); the
            # tail ends before that turn, by the filter's spread, as at a catch, or at the last
            # clear extreme when the roll rate does not turn again.
            turns = self.extremes[(self.extremes > self.extremes[j]) & (self.extremes < self.x.size - 1)]
            end = int(self.extremes[j]) + 1
            if turns.size:
                end = max(int(turns[-1]) - self.margin, end)
            why += f" (the record ends at {self.run.time[-1]:.2f} s: its last swing left out)"
        # Nothing moves while the bicycle is held: a still stretch ends the window.
        held = int(np.searchsorted(self.rests, start, side="right"))
        if held < self.rests.size and self.rests[held] < end:
            end, why = int(self.rests[held]), "came to rest"
        clipped = int(np.searchsorted(self.saturated, start, side="right"))
        if clipped < self.saturated.size and self.saturated[clipped] < end:
            end, why = int(self.saturated[clipped]), "signal saturates"
        end = min(end, self.x.size)
        notes = []
        if trend and np.median(trend) > 1:
            notes.append(f"growing oscillation (swing ratio {np.median(trend):.2f})")
        time = self.run.time
        # Free swings: those ending inside the window and standing out from the background.
        ends = self.extremes[1:]
        inside = slice(int(np.searchsorted(ends, start, side="right")), int(np.searchsorted(ends, end, side="left")))
        free = int(np.count_nonzero(self.swings[inside] >= level))
        began = (f"perturbation at {time[self.extremes[push]]:.2f} s" if not at_start
                 else f"free motion from the record's first sample at {time[0]:.2f} s (no push in it)")
        reason = f"{began}; ends: {why}"
        if end == self.x.size:
            # A segment is cut where its author saw the coast end, often as the hand took hold:
            # the filter spreads a hand's mark over the record's last margin samples, and with
            # no swing after them no rule can tell it. (The swing they end still counts above.)
            end -= self.margin
        # One swing back and then stillness is a push (or a catch) and its return, unless the
        # swing back overshoots where the push began: a heavily damped oscillation.
        still = why.startswith(("decayed", "came to rest", "quick swing")) or self.held(j)
        overshoot = self.swings[push + 1] - self.swings[push] if 0 <= push < self.swings.size - 1 else 0
        if free < 1 or (free == 1 and still and overshoot <= 2 * self.noise) or end - start < 3:
            after = time[self.extremes[push]] if not at_start else time[0]
            reason = f"rejected: no oscillation after {after:.2f} s: {no_oscillation(free, why, end - start < 3)}"
        window = Window(self.run.name, float(time[start]), float(time[max(end, start + 1) - 1]),
                        start, max(end, start + 1), reason, tuple(notes))
        return window, resume
