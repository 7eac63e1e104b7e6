"""Linearity at the measured amplitude: the nonlinear model's weave against the linear one.

The diagnosis compares measured weave eigenvalues with the linear model, which holds for
small motions only. For each usable window this module asks how far the nonlinear Whipple
model's weave, at the amplitude measured in that window, differs from the linear one:

1. the linear mode the diagnosis compares with the window: at the window's model speed, the
   eigenvalue of the bicycle's linear model (controller included) nearest the measured one,
   and its eigenvector;
2. the measured oscillation at the fit's start: the fitted roll rate's cosine and sine
   coefficients give its amplitude [rad/s] and phase;
3. the nonlinear model (same parameters, controller and steer damping; the rear wheel driven
   at constant speed, as on a treadmill and in the linear model) starts in that linear mode,
   scaled and turned so that its roll rate is the measured oscillation; it coasts for the
   fitted window's length, sampled at the window's times;
4. its roll rate is fitted with :func:`whipple.measurement.weavefit.fit_weave` and the
   window's own baseline, as the measurement was. The linear model started in its mode gives
   a pure damped sinusoid, whose fit is its eigenvalue exactly; what the nonlinear fit differs
   by is the nonlinearity at that amplitude, over that window.

A window is **flagged** (linearity does not hold at its amplitude) when the difference
exceeds what the window's own fit resolves, one standard deviation of the measured damping
or frequency (|Δd| > σ_d or |Δω| > σ_ω), or when it exceeds :data:`RELATIVE_LIMIT` of the
eigenvalue's magnitude whatever the window's uncertainty, or when the nonlinear model started
at that amplitude falls over or shows no oscillation to fit (its weave is then no longer the
linear one in any sense).

The linear mode shape fixes the other states from the roll rate: where it holds much steer per
roll rate (at low speed), the measured roll rate implies large steer angles; each check
reports the steer amplitude it started with.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from whipple.errors import AnalysisError, InputError
from whipple.measurement.experiment import WindowMeasurement
from whipple.measurement.weavefit import fit_weave
from whipple.model.fleet import Fleet, Model, members_of
from whipple.model.parameters import Bicycle
from whipple.simulation.nonlinear_bicycle import ForcedBicycle, coast
from whipple.stability.nearest_modes import nearest_eigen

#: A difference above this fraction of |eigenvalue| flags a window whatever its uncertainty.
RELATIVE_LIMIT = 0.05
#: Tolerances of the nonlinear coasting (the differences of interest are above 1e-4 1/s; the
#: roll rate then stays within about 1e-10 rad/s of a reference integration at 1e-12).
RTOL, ATOL = 1e-10, 1e-12
#: The flag, in words (the report prints it).
FLAG_DEFINITION = (
    "flagged: the nonlinear model's weave at the window's measured roll-rate amplitude differs from the linear "
    "eigenvalue by more than the window's fit resolves (|difference| > 1 std of the measured damping or frequency), "
    f"or by more than {100 * RELATIVE_LIMIT:g}% of |eigenvalue|, or the nonlinear model falls over or shows no "
    "oscillation to fit")


@dataclass(frozen=True)
class AmplitudeCheck:
    """The nonlinear weave at one window's amplitude.

    Attributes
    ----------
    run : str
        Run name.
    start, stop : float
        The window [s].
    speed : float
        Model (true) speed [m/s].
    amplitude : float
        Measured roll-rate amplitude at the fit's start [rad/s].
    steer_amplitude : float
        Steer amplitude of the linear mode at that roll-rate amplitude [rad].
    measured_steer_amplitude : float
        The measured steer amplitude at the fit's start, where the window has a steer-angle mode
        shape (its amplitude relative to the roll rate) [rad]; NaN otherwise.
    duration : float
        Length of the fitted stretch [s].
    linear : complex
        The linear model's eigenvalue compared with the window [1/s].
    nonlinear : complex
        Fitted eigenvalue of the nonlinear model's coasting [1/s] (NaN when not computed).
    std : tuple of float
        Standard deviation of the measured damping and frequency [1/s].
    flagged : bool
        Whether linearity does not hold at this amplitude (see :data:`FLAG_DEFINITION`).
    note : str
        Why there is no nonlinear eigenvalue ("" when there is).
    """

    run: str
    start: float
    stop: float
    speed: float
    amplitude: float
    steer_amplitude: float
    measured_steer_amplitude: float
    duration: float
    linear: complex
    nonlinear: complex
    std: tuple[float, float]
    flagged: bool
    note: str = ""

    @property
    def difference(self) -> complex:
        """Nonlinear minus linear eigenvalue [1/s]."""
        return self.nonlinear - self.linear

    @property
    def relative(self) -> float:
        """|difference| / |linear eigenvalue|."""
        return float(abs(self.difference) / abs(self.linear))

    def to_dict(self) -> dict[str, Any]:
        """Return the check as JSON-ready data (eigenvalues as [real, imaginary] [1/s])."""
        def pair(value: complex) -> list[float] | None:
            return [float(value.real), float(value.imag)] if np.isfinite(value) else None

        def number(value: float) -> float | None:
            return float(value) if np.isfinite(value) else None

        return {"amplitude": number(self.amplitude), "steer_amplitude": number(self.steer_amplitude),
                "measured_steer_amplitude": number(self.measured_steer_amplitude), "speed": self.speed,
                "duration": self.duration,
                "eigenvalue": pair(self.nonlinear), "linear_eigenvalue": pair(self.linear),
                "difference": pair(self.difference),
                "relative_difference": self.relative if np.isfinite(self.relative) else None,
                "flagged": self.flagged, "note": self.note or None}


@dataclass(frozen=True)
class AmplitudeReport:
    """The nonlinear weave at every usable window's amplitude.

    Attributes
    ----------
    checks : tuple of AmplitudeCheck
        One per usable window, in the order of the windows (empty when unavailable).
    estimated : tuple of str
        Parameters the linear model does not need and the nonlinear model estimated
        (see :func:`whipple.simulation.nonlinear_bicycle.nonlinear_parameters`).
    note : str
        Why there are no checks ("" when there are).
    """

    checks: tuple[AmplitudeCheck, ...]
    estimated: tuple[str, ...] = ()
    note: str = ""

    @property
    def flagged(self) -> int:
        """Number of flagged windows."""
        return sum(check.flagged for check in self.checks)

    def by_speed(self) -> list[dict[str, Any]]:
        """Per speed group: mean speed [m/s], windows, amplitudes, differences, flagged windows.

        Amplitudes: measured roll rate [rad/s], the linear mode's steer angle at it and the
        measured steer angle [rad].

        Differences (mean nonlinear minus linear damping and frequency [1/s]; median and range of
        |difference| / |eigenvalue|) are over the windows whose nonlinear weave was fitted
        (``fitted``); None where there is none.
        """
        if not self.checks:
            return []
        rows = []
        for group in _groups(self.checks):
            chosen = [self.checks[i] for i in group]
            fitted = [c for c in chosen if np.isfinite(c.nonlinear)]
            differences = np.array([c.difference for c in fitted])
            relative = [c.relative for c in fitted]
            amplitudes = [c.amplitude for c in chosen if np.isfinite(c.amplitude)]
            steer = [c.steer_amplitude for c in chosen if np.isfinite(c.steer_amplitude)]
            measured_steer = [c.measured_steer_amplitude for c in chosen if np.isfinite(c.measured_steer_amplitude)]
            rows.append({
                "speed": float(np.mean([c.speed for c in chosen])), "windows": len(chosen), "fitted": len(fitted),
                "amplitude": [float(min(amplitudes)), float(max(amplitudes))] if amplitudes else None,
                "steer_amplitude": [float(min(steer)), float(max(steer))] if steer else None,
                "measured_steer_amplitude": ([float(min(measured_steer)), float(max(measured_steer))]
                                             if measured_steer else None),
                "damping_difference": float(np.mean(differences.real)) if fitted else None,
                "frequency_difference": float(np.mean(differences.imag)) if fitted else None,
                "median_relative_difference": float(np.median(relative)) if fitted else None,
                "relative_difference": [float(min(relative)), float(max(relative))] if fitted else None,
                "flagged": sum(c.flagged for c in chosen)})
        return rows

    def summary(self) -> str:
        """One line on linearity at the measured amplitudes."""
        if not self.checks:
            return f"linearity at the measured amplitude not checked: {self.note}"
        amplitudes = [c.amplitude for c in self.checks if np.isfinite(c.amplitude)]
        speeds = "; ".join(f"{row['speed']:.2f} m/s {100 * row['median_relative_difference']:.2g}%"
                           for row in self.by_speed() if row["fitted"])
        failed = sum(1 for c in self.checks if c.flagged and not np.isfinite(c.nonlinear))
        text = (f"nonlinear vs linear weave at the measured roll-rate amplitudes ({min(amplitudes):.2f}-"
                f"{max(amplitudes):.2f} rad/s): {self.flagged} of {len(self.checks)} windows flagged")
        if failed:
            text += f" ({failed} where the nonlinear model falls over or does not oscillate)"
        return text + (f"; median |difference| / |eigenvalue| by speed: {speeds}" if speeds else "")

    def to_dict(self) -> dict[str, Any]:
        """Return the summary as JSON-ready data (the per-window checks go with their windows)."""
        return {"summary": self.summary(), "flag_definition": FLAG_DEFINITION, "flagged": self.flagged,
                "windows": len(self.checks), "by_speed": self.by_speed(), "estimated_parameters": list(self.estimated),
                "note": self.note or None}


def _groups(checks: Sequence[AmplitudeCheck], gap: float = 0.3) -> list[list[int]]:
    """Return indices of checks grouped by speed: a new group where sorted speeds jump > gap [m/s]."""
    order = np.argsort([c.speed for c in checks])
    groups: list[list[int]] = [[int(order[0])]]
    for previous, current in zip(order[:-1], order[1:], strict=True):
        if checks[current].speed - checks[previous].speed > gap:
            groups.append([])
        groups[-1].append(int(current))
    return groups


def check_amplitudes(bicycle: Model, used: Sequence[WindowMeasurement],
                     linear: NDArray[np.complex128] | None = None) -> AmplitudeReport:
    """Compare the nonlinear model's weave at each window's amplitude with the linear one.

    Parameters
    ----------
    bicycle : Bicycle
        The base bicycle (its controller and steer damping act).
    used : sequence of WindowMeasurement
        The usable windows (each with a fit and a speed).
    linear : ndarray of complex, optional
        The linear eigenvalue compared with each window [1/s] (the diagnosis' base
        prediction); by default the linear model's eigenvalue nearest the measured one.

    Returns
    -------
    AmplitudeReport
        One check per window; none, with a note, when the nonlinear model cannot represent the
        bicycle (an extension it does not hold).
    """
    if not isinstance(bicycle, Bicycle):
        return _fleet_amplitudes(bicycle, used, linear)
    try:
        forced = ForcedBicycle(bicycle, "driven")
    except InputError as error:
        return AmplitudeReport((), (), error.problem)
    if not used:
        return AmplitudeReport((), forced.estimated, "no usable window")
    fits = [m.fit for m in used]
    speeds = np.array([float(bicycle.model_speed(m.speed.mean)) for m in used if m.speed is not None])
    measured = np.array([f.eigenvalue for f in fits if f is not None])
    if speeds.size != len(used) or measured.size != len(used):
        raise InputError("every window checked needs a fit and a speed")
    targets = measured if linear is None else np.asarray(linear)
    nearest, vectors = nearest_eigen(bicycle, speeds, targets, np.arange(len(used)))
    # A given prediction is the linear eigenvalue itself (the report shows one number for it);
    # the mode's full eigenvector starts the nonlinear model.
    eigenvalues = nearest if linear is None else targets
    checks = []
    for n, measurement in enumerate(used):
        checks.append(_check(forced, measurement, float(speeds[n]), complex(eigenvalues[n]), vectors[n]))
    return AmplitudeReport(tuple(checks), forced.estimated)


def _check(forced: ForcedBicycle, measurement: WindowMeasurement, speed: float, eigenvalue: complex,
           vector: NDArray[np.complex128]) -> AmplitudeCheck:
    fit = measurement.fit
    assert fit is not None
    std = (float(fit.eigenvalue_std[0]), float(fit.eigenvalue_std[1]))
    check = AmplitudeCheck(measurement.run.name, measurement.window.start, measurement.window.stop, speed,
                           amplitude=np.nan, steer_amplitude=np.nan, measured_steer_amplitude=np.nan,
                           duration=float(fit.time[-1] - fit.time[0]),
                           linear=eigenvalue, nonlinear=complex(np.nan, np.nan), std=std, flagged=False)
    if "roll_rate" not in fit.signal_names:
        return replace(check, note="no roll rate fitted")
    cosine, sine = fit.coefficients[fit.signal_names.index("roll_rate"), -2:]
    check = replace(check, amplitude=fit.amplitude("roll_rate"))
    shape = measurement.shape
    if shape is not None and (shape.signal, shape.reference) == ("steer_angle", "roll_rate"):
        check = replace(check, measured_steer_amplitude=float(abs(shape.ratio)) * check.amplitude)
    if not (eigenvalue.imag > 0 and abs(vector[2]) > 0):
        return replace(check, note="the linear mode compared is not oscillatory")
    # roll_rate(tau) = Re(z exp(lambda tau)) with z = cosine - i sine: the mode scaled to it.
    mode = (complex(cosine, -sine) / vector[2]) * vector[:4]
    check = replace(check, steer_amplitude=float(abs(mode[1])))
    start = np.real(mode)
    state = forced.upright(speed, roll=start[0], steer=start[1], roll_rate=start[2], steer_rate=start[3])
    tau = np.asarray(fit.time - fit.time[0], dtype=float)
    try:
        roll_rate = coast(forced, state, tau, RTOL, ATOL)[:, 7]
    except AnalysisError:
        return replace(check, flagged=True, note="the nonlinear model falls over from this amplitude")
    try:
        nonlinear = complex(fit_weave(tau, roll_rate, ("roll_rate",), noise="white", baseline=fit.baseline).eigenvalue)
    except (AnalysisError, InputError) as error:
        return replace(check, flagged=True, note=f"the nonlinear model's roll rate has no weave to fit: {error}")
    difference = nonlinear - eigenvalue
    flagged = bool(abs(difference.real) > std[0] or abs(difference.imag) > std[1]
                   or abs(difference) > RELATIVE_LIMIT * abs(eigenvalue))
    return replace(check, nonlinear=nonlinear, flagged=flagged)


def amplitude_markdown(report: AmplitudeReport) -> list[str]:
    """Return the report's Markdown section on linearity at the measured amplitude (lines)."""
    lines = ["## 5. Linearity at the measured amplitude", ""]
    if not report.checks:
        return lines + [f"Not checked: {report.note}."]
    lines += ["The nonlinear Whipple model (same parameters and controller, the rear wheel at constant speed) "
              "started in the linear mode compared with each window, scaled to the window's measured roll-rate "
              "amplitude, coasts for the window's length; its roll rate is fitted as the measurement was. "
              "The linear mode's steer amplitude is the one it has at the measured roll rate, beside the measured "
              "steer amplitude (from the window's mode shape, where measured); where they are large, the linear model "
              f"is out of its range. {FLAG_DEFINITION[0].upper()}{FLAG_DEFINITION[1:]}.", "",
              f"**{report.summary()}.**", "",
              "| speed [m/s] | windows | roll-rate amplitude [rad/s] | steer amplitude, linear mode [rad] "
              "| steer amplitude, measured [rad] | mean Δd [1/s] | mean Δω [1/s] | median \\|Δλ\\|/\\|λ\\| | flagged |",
              "|---|---|---|---|---|---|---|---|---|"]
    for row in report.by_speed():
        amplitude, steer, measured = (("-" if row[key] is None else f"{row[key][0]:.2f}-{row[key][1]:.2f}")
                                      for key in ("amplitude", "steer_amplitude", "measured_steer_amplitude"))
        if row["fitted"]:
            numbers = (f"{row['damping_difference']:+.3f} | {row['frequency_difference']:+.3f} | "
                       f"{100 * row['median_relative_difference']:.2g}%")
        else:
            numbers = "- | - | -"
        lines.append(f"| {row['speed']:.2f} | {row['windows']} ({row['fitted']} fitted) | {amplitude} | {steer} "
                     f"| {measured} | {numbers} | {row['flagged']} |")
    if report.estimated:
        lines += ["", f"Not in the bicycle file and estimated for the nonlinear model (perpendicular-axis theorem): "
                  f"{', '.join(report.estimated)}."]
    return lines


def _fleet_amplitudes(fleet: Fleet, used: Sequence[WindowMeasurement],
                      linear: NDArray[np.complex128] | None) -> AmplitudeReport:
    """:func:`check_amplitudes` of an experiment's groups: each group's windows with its bicycle, in order."""
    checks: list[AmplitudeCheck | None] = [None] * len(used)
    estimated: tuple[str, ...] = ()
    notes = []
    for member, index in members_of(fleet, [m.group for m in used]):
        chosen = list(range(len(used))) if index is None else [int(n) for n in index]
        part = check_amplitudes(member, [used[n] for n in chosen], None if linear is None else linear[chosen])
        estimated = estimated or part.estimated
        if part.note:
            notes.append(part.note)
        for n, check in zip(chosen, part.checks, strict=False):
            checks[n] = check
    if any(check is None for check in checks):
        return AmplitudeReport((), estimated, "; ".join(dict.fromkeys(notes)) or "not every group could be checked")
    return AmplitudeReport(tuple(check for check in checks if check is not None), estimated)
