"""Simulated measured runs: launch, pushes, free coasting, catches, sensor noise and bias.

The true motion is the linear model ``x' = A(v(t)) x + B(v(t)) f(t)`` of the bicycle
(:func:`whipple.model.assembly.linear_model`, so its extensions and controller act). It is integrated
exactly for inputs and speed held constant over each sample interval (matrix exponential of
the augmented system), so stiff castering modes cost nothing in accuracy at any sample rate.
On a treadmill the speed is constant and free coasting is the exact solution of the model;
on the ground the speed changes by ``deceleration / sample_rate`` per interval, taken at the
interval's midpoint.

The catch and the upright hold are a hand acting on roll and steer: a torque that cancels the
bicycle's own dynamics and replaces them with a stiff critically damped spring, plus a little
random wobble. The catch starts at the first sample where |roll| or |roll rate| exceeds the
scenario's limit, or at a scheduled time; every switch between regimes happens on a sample,
while the push pulses are integrated exactly over each interval.

Examples
--------
>>> from whipple.model.parameters import load_bicycle
>>> from whipple.simulation.scenario import RunScenario
>>> run = simulate_run(load_bicycle("benchmark"), RunScenario(speed=5.0, n_pushes=1))
>>> len(run.segments)
1
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import expm

from whipple.model.assembly import linear_model
from whipple.model.linear import WHIPPLE_STATES, LinearModel
from whipple.model.parameters import Bicycle
from whipple.simulation.discretization import zero_order_hold
from whipple.simulation.run_writer import format_true_windows, parse_true_windows, write_run_csv
from whipple.simulation.scenario import SIGNALS, Push, RunScenario, ScenarioError
from whipple.simulation.speedometer_signal import speedometer_signal

__all__ = ["SimulatedRun", "format_true_windows", "parse_true_windows", "simulate_run",
           "write_run_csv"]

#: Catch spring: (1 + w t) exp(-w t) = 0.5 % at w t = 7.5.
_CATCH_DECAY = 7.5
#: Automatic pushes: horizon [s] and step [s] of the sizing response, share of the roll limit.
_SIZING_HORIZON, _SIZING_STEP, _SIZING_ROLL = 2.0, 0.005, 2 / 3


@dataclass(frozen=True)
class SimulatedRun:
    """A simulated run: the truth and what the sensors measured.

    Attributes
    ----------
    name : str
        Name of the run.
    time : ndarray, shape (n,)
        Sample times [s], ``k / sample_rate``.
    states : ndarray, shape (n, n_states)
        True state at each sample (units of ``state_names``: rad, rad/s, ...).
    state_names : tuple of str
        Names of the model's states.
    speed : ndarray, shape (n,)
        True forward speed [m/s].
    truth : dict of str to ndarray
        Noise-free, bias-free values of every signal of ``whipple.simulation.scenario.SIGNALS``:
        ``speed`` is the true speed [m/s], ``speedometer`` the pick-up's signal [V] before
        noise and offset (which, like the speed column, sees the bicycle's speed scale).
    signals : dict of str to ndarray
        Measured signals of the scenario's columns (with the bicycle's ``speed_scale``
        applied to speed and speedometer), in run-file units.
    segments : tuple of (float, float)
        Free-coasting windows [s]: from the end of each push to the catch (or the record's
        end); pushes caught before they ended have none.
    pushes : tuple of Push
        The pushes, with their roll impulses [N m s] filled in.
    catches : tuple of float
        Start times of the catches [s].
    metadata : dict of str to str
        Run-file metadata (``sample_rate``, ``wheel_radius``, ``pulses_per_revolution``,
        ``bicycle``, ``true_windows``, ``seed``, ...).
    scenario : RunScenario
        What was simulated.
    """

    name: str
    time: NDArray[np.float64]
    states: NDArray[np.float64]
    state_names: tuple[str, ...]
    speed: NDArray[np.float64]
    truth: dict[str, NDArray[np.float64]]
    signals: dict[str, NDArray[np.float64]]
    segments: tuple[tuple[float, float], ...]
    pushes: tuple[Push, ...]
    catches: tuple[float, ...]
    metadata: dict[str, str]
    scenario: RunScenario

    @property
    def sample_rate(self) -> float:
        """[Hz]."""
        return self.scenario.sample_rate

    def state(self, name: str) -> NDArray[np.float64]:
        """Return the true trajectory of one state, by name."""
        return self.states[:, self.state_names.index(name)]


def simulate_run(
    bicycle: Bicycle, scenario: RunScenario, model: LinearModel | None = None, name: str = ""
) -> SimulatedRun:
    """Simulate one run of a bicycle.

    Parameters
    ----------
    bicycle : Bicycle
        Supplies the geometry (wheelbase, trail, steer tilt, rear wheel radius), the name and
        ``extensions.speed_scale`` (measured speed / true speed).
    scenario : RunScenario
        Speed, pushes, catches, sensors, seed.
    model : LinearModel, optional
        The true dynamics (one parameter set; states start with roll, steer, roll rate,
        steer rate; inputs roll and steer torque). Default: ``linear_model(bicycle)``.
    name : str
        Name of the run (default: from the bicycle, setting and speed).

    Raises
    ------
    ScenarioError
        If the model does not fit, or a speedometer signal would alias at the sample rate.
    """
    if model is None:
        model = linear_model(bicycle)
    _check_model(model)
    geometry = {k: float(bicycle.parameters[k]) for k in ("w", "c", "lam", "rR")}
    scale = float(bicycle.extensions.speed_scale)
    fs = scenario.sample_rate
    n = int(math.floor(scenario.end_time() * fs + 1e-9)) + 1
    if n < 3:
        raise ScenarioError(f"a run of {scenario.end_time():g} s at {fs:g} Hz has fewer than 3 "
                            "samples")
    time = np.arange(n) / fs
    speed = _speed(scenario, time)
    if "speedometer" in scenario.columns:
        _check_aliasing(scenario, float(bicycle.measured_speed(speed.max())), geometry["rR"])
    mid_speed = _speed(scenario, time[:-1] + 0.5 / fs)
    rng = np.random.default_rng(scenario.seed)
    wobble = rng.standard_normal((max(n - 1, 0), 2))

    omega = _CATCH_DECAY / scenario.catch_duration
    pushes = _size_pushes(scenario, model)
    torque = _push_torque(pushes, time, model.B.shape[-1])
    dynamics = _Dynamics(model, mid_speed, omega, 1.0 / fs)
    # Stationary std hold_std of a critically damped spring driven by white acceleration.
    wobble *= scenario.hold_std * math.sqrt(4 * omega**3 * fs)
    states, segments, catches = _integrate(scenario, pushes, time, torque, wobble, dynamics)

    truth = _true_signals(model, states, speed, geometry)
    truth["speedometer"] = speedometer_signal(bicycle.measured_speed(_distance(scenario, time)), geometry["rR"],
                                              scenario.pulses_per_revolution,
                                              phase=float(rng.uniform(0, 2 * np.pi)))
    measured = {}
    for signal in SIGNALS:  # every signal draws its noise, so columns do not change others
        sensor = getattr(scenario.sensors, signal)
        value = bicycle.measured_speed(truth[signal]) if signal == "speed" else truth[signal]
        measured[signal] = value + sensor.bias + sensor.noise * rng.standard_normal(n)
    signals = {column: measured[column] for column in scenario.columns}
    for array in (time, states, speed, *truth.values(), *signals.values()):
        array.flags.writeable = False
    label = name or f"{bicycle.name or 'bicycle'}_{scenario.setting}_{scenario.speed:.2f}ms"
    metadata = _metadata(bicycle, scenario, scale, segments, geometry["rR"])
    return SimulatedRun(label, time, states, model.state_names, speed, truth, signals,
                        segments, pushes, catches, metadata, scenario)


def _check_model(model: LinearModel) -> None:
    if model.batch_shape:
        raise ScenarioError("simulate_run needs the model of one bicycle, not a batch")
    if model.state_names[:4] != WHIPPLE_STATES or model.B.shape[-1] != 2:
        raise ScenarioError("the model's states must start with roll, steer, roll_rate, "
                            "steer_rate and its inputs be roll and steer torque")


def _speed(scenario: RunScenario, t: NDArray[np.float64]) -> NDArray[np.float64]:
    if scenario.setting == "ground":
        return scenario.speed - scenario.deceleration * t
    return np.full(t.shape, float(scenario.speed))


def _distance(scenario: RunScenario, t: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distance rolled since t = 0 [m] (exact integral of the speed profile)."""
    decel = scenario.deceleration if scenario.setting == "ground" else 0.0
    return scenario.speed * t - 0.5 * decel * t**2


def _check_aliasing(scenario: RunScenario, top_speed: float, radius: float) -> None:
    frequency = 0.5 * scenario.pulses_per_revolution * top_speed / (2 * np.pi * radius)
    if frequency >= 0.5 * scenario.sample_rate:
        raise ScenarioError(
            f"the speedometer signal ({frequency:.3g} Hz at {top_speed:.3g} m/s) would alias at "
            f"{scenario.sample_rate:g} Hz; raise the sample rate above {2 * frequency:.3g} Hz")


def _size_pushes(scenario: RunScenario, model: LinearModel) -> tuple[Push, ...]:
    """Fill in the roll impulse of automatic pushes (alternating direction).

    The roll torque also kicks the steer, whose fast response feeds back into the roll, so
    the impulse is scaled on the free response to a unit impulse over its first
    ``_SIZING_HORIZON`` seconds: its peak |roll rate| becomes ``push_roll_rate``, unless the
    peak |roll| would then pass ``_SIZING_ROLL`` of the catch's roll limit (the push an
    experimenter gives who wants the bicycle to coast).
    """
    sized = []
    for i, push in enumerate(scenario.resolved_pushes()):
        impulse = push.roll_impulse
        if impulse is None:
            speed = _speed(scenario, np.array(push.time))
            step = expm(model.state_matrix(speed) * _SIZING_STEP)
            x = model.input_matrix(speed)[:, 0]
            peak_rate, peak_roll = abs(x[2]), 0.0
            for _ in range(int(round(_SIZING_HORIZON / _SIZING_STEP))):
                x = step @ x
                peak_rate, peak_roll = max(peak_rate, abs(x[2])), max(peak_roll, abs(x[0]))
            if not peak_rate > 0:
                raise ScenarioError("the model's roll rate does not respond to roll torque")
            roll_cap = _SIZING_ROLL * scenario.roll_limit / peak_roll if peak_roll else math.inf
            impulse = (-1) ** i * min(scenario.push_roll_rate / peak_rate, roll_cap)
        sized.append(Push(push.time, float(impulse), push.steer_impulse, push.duration))
    return tuple(sized)


def _push_torque(pushes: tuple[Push, ...], time: NDArray[np.float64], m: int) -> NDArray[np.float64]:
    """Mean torque of the half-sine pulses over each sample interval [N m], shape (n-1, m)."""
    torque = np.zeros((max(time.size - 1, 0), m))
    t0, t1 = time[:-1], time[1:]
    for push in pushes:
        a = np.clip(t0, push.time, push.time + push.duration)
        b = np.clip(t1, push.time, push.time + push.duration)
        # Integral of sin(pi s / T) over [a, b] for a pulse of unit impulse: peak pi / (2 T).
        share = 0.5 * (np.cos(np.pi * (a - push.time) / push.duration)
                       - np.cos(np.pi * (b - push.time) / push.duration))
        torque[:, 0] += float(push.roll_impulse or 0.0) * share / (t1 - t0)
        torque[:, 1] += push.steer_impulse * share / (t1 - t0)
    return torque


class _Dynamics:
    """Transition matrices of each sample interval, free and held by the hand."""

    def __init__(self, model: LinearModel, speeds: NDArray[np.float64], omega: float,
                 dt: float):
        unique, self.index = np.unique(speeds, return_inverse=True)
        A, B = model.state_matrix(unique), model.input_matrix(unique)
        # The hand: f = -K x + F w turns the roll and steer accelerations into
        # -omega^2 q - 2 omega q' + w, whatever the bicycle's own dynamics.
        target = np.zeros((2, A.shape[-1]))
        target[:, 0:2] = omega**2 * np.eye(2)
        target[:, 2:4] = 2 * omega * np.eye(2)
        try:
            self.force = np.linalg.inv(B[:, 2:4, :])
        except np.linalg.LinAlgError:
            raise ScenarioError("the model's roll and steer torques do not act independently "
                                "on roll and steer: the catch cannot hold it") from None
        held = A - B @ (self.force @ (A[:, 2:4, :] + target))
        transition, inputs = zero_order_hold(np.stack([A, held]), np.stack([B, B]), dt)
        self.transition, self.input = transition, inputs


def _integrate(
    scenario: RunScenario,
    pushes: tuple[Push, ...],
    time: NDArray[np.float64],
    torque: NDArray[np.float64],
    wobble: NDArray[np.float64],
    dynamics: _Dynamics,
) -> tuple[NDArray[np.float64], tuple[tuple[float, float], ...], tuple[float, ...]]:
    """Step through the regimes: held, free (pushed, coasting), caught and held again."""
    states = np.zeros((time.size, dynamics.transition.shape[-1]))
    tolerance = 1e-9 / scenario.sample_rate
    held, launched, current = True, False, -1
    scheduled = math.inf
    segments: list[tuple[float, float]] = []
    catches: list[float] = []

    def close(stop: float) -> None:
        if current >= 0 and stop > pushes[current].time + pushes[current].duration:
            segments.append((pushes[current].time + pushes[current].duration, stop))

    for k in range(time.size - 1):
        x = states[k]
        if current + 1 < len(pushes) and time[k + 1] > pushes[current + 1].time + tolerance:
            if not held:
                close(float(time[k]))  # pushed again before any catch
            current += 1
            held, launched = False, True
            scheduled = _scheduled_catch(scenario, pushes, current)
        elif not launched and time[k + 1] > scenario.release + tolerance:
            held, launched = False, True
        elif not held and (abs(x[0]) > scenario.roll_limit or abs(x[2]) > scenario.roll_rate_limit
                           or time[k] >= scheduled - tolerance):
            held, scheduled = True, math.inf
            catches.append(float(time[k]))
            close(float(time[k]))
        phase, u = int(held), dynamics.index[k]
        f = torque[k] + (dynamics.force[u] @ wobble[k] if held else 0.0)
        states[k + 1] = dynamics.transition[phase, u] @ x + dynamics.input[phase, u] @ f
        if not np.all(np.isfinite(states[k + 1])):
            raise ScenarioError(f"the simulation diverged at t = {time[k + 1]:.3g} s")
    if not held:
        close(float(time[-1]))
    return states, tuple(segments), tuple(catches)


def _scheduled_catch(scenario: RunScenario, pushes: tuple[Push, ...], i: int) -> float:
    push = pushes[i]
    due = push.time + push.duration + scenario.max_coast
    if i + 1 < len(pushes):
        due = min(due, pushes[i + 1].time - scenario.settle)
    return due


def _true_signals(
    model: LinearModel,
    states: NDArray[np.float64],
    speed: NDArray[np.float64],
    geometry: dict[str, float],
) -> dict[str, NDArray[np.float64]]:
    names = model.state_names
    roll, steer, roll_rate, steer_rate = (states[:, names.index(s)] for s in WHIPPLE_STATES)
    if "yaw_rate" in names:
        yaw_rate = states[:, names.index("yaw_rate")]
    else:
        # Nonholonomic kinematics of the knife-edge front wheel, to first order.
        yaw_rate = ((speed * steer + geometry["c"] * steer_rate) * np.cos(geometry["lam"])
                    / geometry["w"])
    return {"roll_rate": roll_rate, "yaw_rate": yaw_rate, "steer_angle": steer,
            "steer_rate": steer_rate, "roll_angle": roll, "speed": speed.copy()}


def _metadata(
    bicycle: Bicycle,
    scenario: RunScenario,
    scale: float,
    segments: tuple[tuple[float, float], ...],
    radius: float,
) -> dict[str, str]:
    metadata = {
        "sample_rate": f"{scenario.sample_rate:g}",
        "wheel_radius": f"{radius:g}",
        "pulses_per_revolution": str(scenario.pulses_per_revolution),
        "bicycle": bicycle.name or "unnamed",
        "speed_scale": f"{scale:.9g}",
    }
    if "speed" not in scenario.columns and "speedometer" not in scenario.columns:
        metadata["speed"] = f"{scale * scenario.speed:.9g}"
    metadata.update({
        "simulated": "whipple.simulation.simulator",
        "setting": scenario.setting,
        "true_speed": f"{scenario.speed:.9g}",
        "deceleration": f"{scenario.deceleration if scenario.setting == 'ground' else 0.0:g}",
        "true_windows": format_true_windows(segments),
        "seed": str(scenario.seed),
    })
    return metadata
