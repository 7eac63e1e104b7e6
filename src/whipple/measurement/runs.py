"""Measured (or simulated) runs: reading run files into plain :class:`Run` objects.

The native format is the CSV of the run-file spec (``# key: value`` metadata lines, a header
line, SI units, Meijaard et al. 2007 signs). Other layouts are read through a layout file
(:mod:`whipple.measurement.layouts`); the logs of the steer-by-wire treadmill bicycle are recognised
by their header line. Files ending in ``.gz`` are decompressed transparently.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from whipple.errors import InputError, RunFileError
from whipple.measurement.glitches import DEFAULT_RULE, GlitchRule, find_glitches
from whipple.measurement.layouts import SPEC_COLUMNS, RunLayout
from whipple.measurement.record_gaps import contiguous
from whipple.measurement.run_table import read_run_table
from whipple.measurement.short_gaps import FILLED_GAP, fill_short_gaps, fill_speed_gaps
from whipple.measurement.speedometer import speedometer_speed
from whipple.number_text import parse_number
from whipple.simulation.run_limits import MAX_RUN_SPEED, MIN_DURATION, MIN_SAMPLE_RATE
from whipple.simulation.simulator import SimulatedRun

__all__ = ["Readable", "Run", "contiguous", "run_from_simulation", "check_distinct_names", "check_same_bicycle",
           "read_run", "RATE_TOLERANCE", "run_name"]


class Readable(Protocol):
    """A file-like location: a Path or an importlib.resources Traversable."""

    @property
    def name(self) -> str:
        """File name."""

    def read_bytes(self) -> bytes:
        """Whole content."""


@dataclass(frozen=True)
class Run:
    """One measured or simulated run.

    Attributes
    ----------
    name : str
        Name of the run (the file name without ``.gz`` and extension).
    source : str
        Path of the file it was read from.
    time : ndarray, shape (n,)
        Sample times [s], strictly increasing.
    signals : dict of str to ndarray, each shape (n,)
        Signals by run-file column name (``roll_rate`` [rad/s], ``steer_angle`` [rad], ...),
        in SI units; layouts may add extra signals under their own names.
    metadata : dict of str to str
        The file's ``# key: value`` lines and the layout's metadata.
    sample_rate : float
        Sample rate [Hz] (the median one when a time column is given).
    warnings : tuple of str
        What was ignored while reading (unknown columns, gaps: empty, NaN or non-numeric
        cells, negative speeds); never printed by the library.
    """

    name: str
    source: str
    time: NDArray[np.float64]
    signals: dict[str, NDArray[np.float64]]
    metadata: dict[str, str]
    sample_rate: float
    warnings: tuple[str, ...] = field(default=())

    @property
    def duration(self) -> float:
        """Time from the first to the last sample [s]."""
        return float(self.time[-1] - self.time[0])

    def speed(self) -> NDArray[np.float64]:
        """Forward speed at every sample [m/s].

        From the ``speed`` column, else from the ``speedometer`` signal (with the
        ``wheel_radius`` and ``pulses_per_revolution`` metadata), else the constant ``speed``
        metadata.
        """
        if "speed" in self.signals:
            return self.signals["speed"]
        if "speedometer" in self.signals:
            radius = _metadata_number(self.metadata, "wheel_radius", self.source)
            pulses = _metadata_number(self.metadata, "pulses_per_revolution", self.source)
            signal = self.signals["speedometer"]
            speed = np.full(self.time.shape, np.nan)
            # Each stretch between gaps on its own: crossings are not counted across a gap.
            for first, stop in contiguous(np.isfinite(signal)):
                try:
                    staircase = speedometer_speed(self.time[first:stop], signal[first:stop], radius, pulses,
                                                  source=self.source)
                except RunFileError:
                    if first == 0 and stop == signal.size:
                        raise
                    continue  # too short a stretch to hold two crossings: no speed there
                speed[first:stop] = staircase.sampled(self.time[first:stop])
            return speed
        return np.full(self.time.shape, _metadata_number(self.metadata, "speed", self.source))


def run_from_simulation(simulated: SimulatedRun) -> Run:
    """Return the measured part of a simulated run, as if read from its run file.

    Parameters
    ----------
    simulated : SimulatedRun
        A run from :func:`whipple.simulation.simulator.simulate_run`.

    Returns
    -------
    Run
        The run as :func:`read_run` would read it from its file.
    """
    return Run(name=simulated.name, source=f"<simulated {simulated.name}>", time=simulated.time,
               signals=dict(simulated.signals), metadata=dict(simulated.metadata),
               sample_rate=simulated.sample_rate)


def check_distinct_names(runs: Sequence[Run]) -> None:
    """Refuse runs sharing a name: windows files, tables and figures name a run by it.

    Parameters
    ----------
    runs : sequence of Run
        The runs.

    Returns
    -------
    None
        Returns quietly when the names are distinct.

    Raises
    ------
    InputError
        Two runs share a name, naming both.
    """
    names = [run.name for run in runs]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        files = " and ".join([str(run.source) for run in runs if run.name == twice[0]][:2])
        raise InputError(f"two runs are named {twice[0]} ({files}; windows and figures go by run name)")


def check_same_bicycle(runs: Sequence[Run]) -> None:
    """Refuse runs whose metadata name different bicycles (the ``bicycle`` key; runs without it pass).

    Measurements of two bicycles confronted with one model would blame the model for the
    difference between the bicycles.

    Raises
    ------
    InputError
        Naming two runs (files) and the bicycles they name.
    """
    named = [(run, run.metadata["bicycle"].strip()) for run in runs if run.metadata.get("bicycle", "").strip()]
    for run, bicycle in named[1:]:
        first, first_bicycle = named[0]
        if bicycle != first_bicycle:
            raise InputError(f"runs of different bicycles: {first.source} names {first_bicycle!r}, {run.source} names "
                             f"{bicycle!r} (metadata 'bicycle'); give the runs of one bicycle")


def read_run(
    path: str | Path | Readable,
    layout: str | Path | RunLayout | None = None,
    min_duration: float = MIN_DURATION,
    glitches: GlitchRule | None = DEFAULT_RULE,
    filled_gap: float = FILLED_GAP,
) -> Run:
    """Read a run file.

    Parameters
    ----------
    path : str, Path or Traversable
        The run file (native CSV, or a layout's format); ``.gz`` files are decompressed.
    layout : str, Path or RunLayout, optional
        A built-in layout name, a layout file, or a layout. By default the native format,
        unless the first line identifies a built-in layout (e.g. the sbw-treadmill logs).
    min_duration : float
        Shortest acceptable run [s].
    glitches : GlitchRule or None
        Isolated wild samples of the run-file signals (not the time, not a speedometer's pulses)
        found by this rule are left out as gaps, each named in the warnings
        (:mod:`whipple.measurement.glitches`); None keeps every sample.
    filled_gap : float
        Stretches of missing samples (dropped rows, empty cells, glitches) of at most this
        duration [s] between measured ones are filled by interpolation
        (:mod:`whipple.measurement.short_gaps`), each filled sample counted in the warnings;
        longer ones stay gaps, which no window spans. 0 fills none.

    Returns
    -------
    Run
        The run's signals in SI units, its speed, metadata and warnings.

    Raises
    ------
    RunFileError
        If the file cannot be read, misses roll_rate, time or speed information, holds text or
        infinite values in the time, roll_rate, speed or speedometer columns, has
        non-increasing times or is too short, or gives a metadata key twice. Empty and NaN
        cells are gaps (NaN), noted in the run's warnings; text in other columns too. Numbers
        are ASCII decimal text (:func:`whipple.number_text.parse_number`).
    """
    source = str(path)
    table = read_run_table(path, layout, source)
    active, signals, metadata, warnings = table.layout, table.signals, table.metadata, table.notes
    for name, factor in {**table.units, **active.scale}.items():
        if name in signals:
            signals[name] *= factor
    if "time" in signals and np.isnan(signals["time"]).all():
        raise RunFileError("column time has no values (every cell empty or NaN)", source)
    if "time" in signals and np.isnan(signals["time"]).any():
        # A sample without a time cannot be placed: drop the row (the jump is a gap).
        keep = ~np.isnan(signals["time"])
        signals = {name: values[keep] for name, values in signals.items()}
        warnings.append(f"{int((~keep).sum())} row(s) without a time value dropped")
    for name in ("roll_rate", "speed", "speedometer"):
        if name in signals and np.isnan(signals[name]).all():
            raise RunFileError(f"column {name} has no values (every cell empty or NaN)", source)
    warnings += _leave_out_beyond_any_bicycle(signals, source)
    time, sample_rate = _time_base(signals, metadata, active, table.names, source, warnings)
    if time[-1] - time[0] < min_duration:
        raise RunFileError(
            f"run too short ({time[-1] - time[0]:.3g} s; at least {min_duration:g} s needed)", source
        )
    _check_speed_source(signals, metadata, active, source)
    if glitches is not None:
        warnings += _leave_out_glitches(signals, time, glitches)
    time, filled = fill_short_gaps(time, signals, filled_gap)
    warnings += filled
    if "speed" in signals and filled_gap > 0:
        warnings += fill_speed_gaps(time, signals["speed"])
    speed = signals.get("speed")
    fastest = float(np.nanmax(np.abs(speed), initial=0.0)) if speed is not None else 0.0
    if "speed" in metadata and speed is None:
        fastest = _metadata_number(metadata, "speed", source)
    if fastest > MAX_RUN_SPEED:
        raise RunFileError(f"a speed of {fastest:.6g} m/s: no bicycle rides faster than {MAX_RUN_SPEED:g} m/s (a speed "
                           "in other units? a layout's [scale] converts it)", source)
    if speed is not None and np.nanmin(speed, initial=0.0) < 0:
        warnings.append(f"speed is negative in {int(np.sum(speed < 0))} sample(s): the model's forward speed is "
                        "positive, so no window there is fitted (flip the speed's sign with a layout's [scale] "
                        "if that is its convention)")
    for values in signals.values():
        values.flags.writeable = False
    time.flags.writeable = False
    return Run(
        name=run_name(getattr(path, "name", source)),
        source=source,
        time=time,
        signals=signals,
        metadata=metadata,
        sample_rate=sample_rate,
        warnings=tuple(warnings),
    )


#: Largest magnitude of a motion or torque sample (rad, rad/s, N m) taken as measured: a bicycle
#: rolls and steers at a few rad/s at most, and even a wrong unit (deg/s, mrad) stays below a
#: few thousand. Beyond, a sample is a logger's error value or a corrupt cell.
MAX_SIGNAL = 1e6
#: Run-file columns whose magnitude is checked against MAX_SIGNAL (speed has MAX_RUN_SPEED; the
#: time, a speedometer's and the battery's volts are no motion).
_MOTION_COLUMNS = ("roll_rate", "yaw_rate", "steer_angle", "steer_rate", "roll_angle", "steer_torque")


def _leave_out_beyond_any_bicycle(signals: dict[str, NDArray[np.float64]], source: str) -> list[str]:
    """Set samples beyond :data:`MAX_SIGNAL` to NaN (gaps); return a note per signal that had any.

    A roll rate with no sample left is refused (RunFileError): the run holds nothing to fit.
    """
    notes = []
    for name in _MOTION_COLUMNS:
        values = signals.get(name)
        if values is None:
            continue
        with np.errstate(invalid="ignore"):
            beyond = np.abs(values) > MAX_SIGNAL
        if beyond.any():
            largest = float(np.nanmax(np.abs(values)))
            values[beyond] = np.nan
            if name == "roll_rate" and np.isnan(values).all():
                raise RunFileError(f"every roll_rate sample is empty or beyond {MAX_SIGNAL:g} rad/s (up to "
                                   f"{largest:.6g}): no bicycle moves so", source)
            notes.append(f"{int(beyond.sum())} {name} sample(s) beyond {MAX_SIGNAL:g} {SPEC_COLUMNS[name]} (up to "
                         f"{largest:.6g}) left out as gaps: no bicycle moves so")
    return notes


#: Glitches named one by one in a run's warnings; more are counted.
_GLITCHES_NAMED = 3


def _leave_out_glitches(signals: dict[str, NDArray[np.float64]], time: NDArray[np.float64],
                        rule: GlitchRule) -> list[str]:
    """Set the glitches of the run-file signals to NaN; return a note per signal that had any."""
    notes = []
    for name, values in signals.items():
        if name not in SPEC_COLUMNS or name == "speedometer":
            continue  # a layout's extra signals may spike by nature (an accelerometer at a push)
        found = find_glitches(values, rule)
        if not found.size:
            continue
        unit = SPEC_COLUMNS[name]
        named = ", ".join(f"{values[i]:.6g} {unit} at {time[i]:.6g} s" for i in found[:_GLITCHES_NAMED].tolist())
        more = f" and {found.size - _GLITCHES_NAMED} more" if found.size > _GLITCHES_NAMED else ""
        values[found] = np.nan
        notes.append(f"glitch: {found.size} isolated wild {name} sample(s) left out as gaps ({named}{more})")
    return notes


def _time_base(
    signals: dict[str, NDArray[np.float64]],
    metadata: dict[str, str],
    layout: RunLayout,
    names: list[str],
    source: str,
    warnings: list[str],
) -> tuple[NDArray[np.float64], float]:
    if "time" in signals:
        time = signals.pop("time")
        repeated = _repeated_rows(time, signals)
        rows = np.flatnonzero(~repeated)  # the data rows kept, for messages
        if repeated.any():
            # A logger that sends a row twice: the copy adds nothing.
            time = time[~repeated]
            for name in signals:
                signals[name] = signals[name][~repeated]
            warnings.append(f"{int(repeated.sum())} repeated row(s) (the same time and values as the row before) "
                            "dropped")
        if time.size < 2:  # no step to take a sample rate from
            raise RunFileError(f"run too short (one sample; at least {MIN_DURATION:g} s needed)", source)
        steps = np.diff(time)
        restarts = np.flatnonzero(steps <= -MIN_DURATION)
        if restarts.size:
            # A logger that appends trials to one file, its clock restarted for each: each part
            # follows the one before after a pause that no window spans.
            shift = np.zeros(time.size)
            for k in restarts.tolist():
                shift[k + 1:] += time[k] - time[k + 1] + CLOCK_RESTART_PAUSE
            time = time + shift
            steps = np.diff(time)
            shown = ", ".join(str(int(rows[k + 1])) for k in restarts[:3].tolist())
            shown += " ..." if restarts.size > 3 else ""
            warnings.append(f"time goes back at data row(s) {shown} (a clock restarted?): each part read after the one "
                            f"before it, {CLOCK_RESTART_PAUSE:g} s later (a gap no window spans)")
        if steps.size and not (steps > 0).all():
            bad = int(np.argmin(steps > 0)) + 1
            how = ("repeats with other values than the row before" if steps[bad - 1] == 0
                   else "is not strictly increasing")
            raise RunFileError(f"time {how} at data row {int(rows[bad])} (t = {time[bad]:g} s)", source)
        stated = _metadata_number(metadata, "sample_rate", source) if "sample_rate" in metadata else None
        rate = float(1.0 / np.median(steps))
        _check_sample_rate(rate, "from the time column; in ms or us instead of s?", source)
        if stated is not None and abs(stated - rate) > RATE_TOLERANCE * rate:
            raise RunFileError(f"metadata sample_rate {stated:g} Hz contradicts the time column ({rate:.6g} Hz from "
                               f"its median step of {1 / rate:.6g} s): correct or remove one", source)
        return time, rate
    if "sample_rate" in metadata:
        rate = _metadata_number(metadata, "sample_rate", source)
    elif layout.sample_rate is not None:
        rate = layout.sample_rate
    else:
        near = [name for name in names if re.fullmatch(r"(t|time|times|timestamps?|seconds|elapsed)([\s_]*[\[(].*)?",
                                                       name.strip().lower())]
        hint = (f" (the header has {near[0][:40]!r}: the exact name is time, in s; a layout's [columns] maps another "
                "name)") if near else ""
        raise RunFileError(f"no time column and no sample_rate{hint}", source)
    _check_sample_rate(rate, "from sample_rate", source)
    return np.arange(len(signals["roll_rate"])) / rate, rate


#: Pause [s] put between the parts of a run whose clock restarts (time goes back by a second or
#: more): a jump in time, a gap no window spans (far longer than a short gap that is filled).
CLOCK_RESTART_PAUSE = 1.0


def _repeated_rows(time: NDArray[np.float64], signals: dict[str, NDArray[np.float64]]) -> NDArray[np.bool_]:
    """Return where a row repeats the row before it: the same time and the same value (or none) in every column."""
    same = np.concatenate(([False], np.diff(time) == 0))
    for values in signals.values():
        if not same.any():
            break
        previous = np.concatenate(([np.nan], values[:-1]))
        same &= (values == previous) | (np.isnan(values) & np.isnan(previous))
    return same


#: Largest relative difference between a run's metadata sample rate and its time column's: a
#: logger's clock drifts by parts per million, a mistyped or stale rate by a factor.
RATE_TOLERANCE = 0.02


def _check_sample_rate(rate: float, origin: str, source: str) -> None:
    if not rate >= MIN_SAMPLE_RATE:
        raise RunFileError(f"sample rate {rate:.3g} Hz ({origin}) is below {MIN_SAMPLE_RATE:g} Hz: too slow to "
                           "resolve the weave", source)


def _check_speed_source(
    signals: dict[str, NDArray[np.float64]],
    metadata: dict[str, str],
    layout: RunLayout,
    source: str,
) -> None:
    settings = layout.speed
    if settings.get("source") == "constant":
        if "value" not in settings:
            raise RunFileError("bad layout file: [speed] source = \"constant\" needs value", source)
        metadata.setdefault("speed", str(settings["value"]))
    for key in ("wheel_radius", "pulses_per_revolution"):
        if key in settings:
            metadata.setdefault(key, str(settings[key]))
    if "speed" in signals:
        return
    if "speedometer" in signals:
        for key in ("wheel_radius", "pulses_per_revolution"):
            _metadata_number(metadata, key, source)
        return
    if "speed" in metadata:
        _metadata_number(metadata, "speed", source)
        return
    raise RunFileError(
        "missing speed information: needs a speed column, a speedometer column with "
        "wheel_radius and pulses_per_revolution, or speed metadata", source
    )


#: The unit a metadata value may carry after its number (``# sample_rate: 100 Hz``).
_METADATA_UNITS = {"sample_rate": "Hz", "wheel_radius": "m", "speed": "m/s"}


def _metadata_number(metadata: dict[str, str], key: str, source: str) -> float:
    if key not in metadata:
        raise RunFileError(f"missing metadata '{key}'", source)
    text = metadata[key].strip()
    unit = _METADATA_UNITS.get(key)
    if unit is not None and text.lower().endswith(unit.lower()):
        text = text[:-len(unit)].strip()
    try:
        value = parse_number(text)
    except ValueError:
        known = f" (in {unit})" if unit else ""
        raise RunFileError(f"metadata '{key}' is not a number{known}: '{metadata[key]}'", source) from None
    if not np.isfinite(value) or value <= 0:
        raise RunFileError(f"metadata '{key}' must be positive, got {metadata[key]}", source)
    return value


def run_name(file_name: str) -> str:
    """Return the name of the run in a file: its name without folder, ``.gz`` and extension.

    Only a short alphabetic extension is removed (``.csv``, ``.log``), so names with dots in
    them (``..._12.6kph``) survive.
    """
    name = Path(file_name.strip()).name
    if name.endswith(".gz"):
        name = name[:-3]
    return re.sub(r"\.[A-Za-z]{1,4}$", "", name)
