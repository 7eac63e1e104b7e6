"""The parts of a simulated run that do not depend on the model integrated.

Both simulators, the linear one (:mod:`whipple.simulation.simulator`) and the nonlinear one
(:mod:`whipple.simulation.nonlinear_run`), follow the same procedure (Kooijman & Schwab 2009,
sections 4.1-4.4): the same samples, speed profile, pushes (sized on the linear model), the
same catch spring and hand wobble, the same sensors and run-file metadata. With the same
scenario and seed they draw the same random numbers in the same order, so their runs differ
only by the model of the true motion.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import expm

from whipple.model.linear import LinearModel
from whipple.model.parameters import Bicycle
from whipple.simulation.disturbance import disturbance_metadata
from whipple.simulation.run_writer import format_true_windows
from whipple.simulation.scenario import SIGNALS, Push, RunScenario, ScenarioError
from whipple.simulation.sensor_faults import fault_metadata, faulty_signals
from whipple.simulation.speedometer_signal import speedometer_signal

#: Catch spring: (1 + w t) exp(-w t) = 0.5 % at w t = 7.5.
CATCH_DECAY = 7.5
#: Automatic pushes: horizon [s] and step [s] of the sizing response, share of the roll limit.
_SIZING_HORIZON, _SIZING_STEP, _SIZING_ROLL = 2.0, 0.005, 2 / 3
#: Key of the random stream of the pushes' directions and sizes and the coasts' lengths: apart
#: from the run's own stream, so that a scenario without these options draws what it always did.
_PROCEDURE_STREAM = 51


@dataclass(frozen=True)
class NonlinearChecks:
    """How well a nonlinear run keeps its constraints and its energy balance.

    Attributes
    ----------
    holonomic_drift : float
        Largest |front contact height| at the samples [m].
    velocity_drift : float
        Largest |front contact velocity| at the samples [m/s].
    energy_error : float
        Largest |E - E(0) - W| over the samples [J]: E the kinetic plus potential energy, W the
        work done by every torque (pushes, hand, controller, steer damping, rear wheel drive).
        It measures the integration error.
    energy_scale : float
        The initial kinetic energy [J], to which ``energy_error`` may be compared.
    work : float
        W at the end of the run [J].
    evaluations : int
        Evaluations of the equations of motion.
    """

    holonomic_drift: float
    velocity_drift: float
    energy_error: float
    energy_scale: float
    work: float
    evaluations: int

    @property
    def energy_error_relative(self) -> float:
        """``energy_error / energy_scale``."""
        return self.energy_error / max(self.energy_scale, np.finfo(float).tiny)


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
        True state at each sample (units of ``state_names``: m, rad, rad/s, ...).
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
    checks : NonlinearChecks or None
        Constraint drift and energy balance of a nonlinear run (None for the linear model).
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
    checks: NonlinearChecks | None = None

    @property
    def sample_rate(self) -> float:
        """[Hz]."""
        return self.scenario.sample_rate

    def state(self, name: str) -> NDArray[np.float64]:
        """Return the true trajectory of one state, by name."""
        return self.states[:, self.state_names.index(name)]


def sample_times(scenario: RunScenario) -> NDArray[np.float64]:
    """Sample times of the run [s], ``k / sample_rate`` up to the scenario's end."""
    fs = scenario.sample_rate
    n = int(math.floor(scenario.end_time() * fs + 1e-9)) + 1
    if n < 3:
        raise ScenarioError(f"a run of {scenario.end_time():g} s at {fs:g} Hz has fewer than 3 "
                            "samples")
    return np.arange(n) / fs


def speed_profile(scenario: RunScenario, t: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the true forward speed [m/s] at times ``t`` [s]: constant, or coasting on the ground."""
    return scenario.true_speed(t)


def distance_rolled(scenario: RunScenario, t: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distance rolled since t = 0 [m] (exact integral of the speed profile)."""
    return scenario.distance_rolled(t)


def check_aliasing(scenario: RunScenario, bicycle: Bicycle, top_speed: float) -> None:
    """Refuse a speedometer signal that would alias at the sample rate (top true speed [m/s])."""
    if "speedometer" not in scenario.columns:
        return
    radius, measured = float(bicycle.parameters["rR"]), float(bicycle.measured_speed(top_speed))
    frequency = 0.5 * scenario.pulses_per_revolution * measured / (2 * np.pi * radius)
    if frequency >= 0.5 * scenario.sample_rate:
        raise ScenarioError(
            f"the speedometer signal ({frequency:.3g} Hz at {measured:.3g} m/s) would alias at "
            f"{scenario.sample_rate:g} Hz; raise the sample rate above {2 * frequency:.3g} Hz")


def size_pushes(scenario: RunScenario, model: LinearModel) -> tuple[Push, ...]:
    """Fill in the roll impulse of automatic pushes (alternating direction).

    The roll torque also kicks the steer, whose fast response feeds back into the roll, so
    the impulse is scaled on the linear model's free response to a unit impulse over its first
    ``_SIZING_HORIZON`` seconds: its peak |roll rate| becomes ``push_roll_rate``, unless the
    peak |roll| would then pass ``_SIZING_ROLL`` of the catch's roll limit (the push an
    experimenter gives who wants the bicycle to coast).
    """
    sized = []
    for i, push in enumerate(scenario.resolved_pushes()):
        impulse = push.roll_impulse
        if impulse is None:
            speed = speed_profile(scenario, np.array(push.time))
            step = expm(model.state_matrix(speed) * _SIZING_STEP)
            x = model.input_matrix(speed)[:, 0]
            peak_rate, peak_roll = abs(x[2]), 0.0
            for _ in range(int(round(_SIZING_HORIZON / _SIZING_STEP))):
                x = step @ x
                peak_rate, peak_roll = max(peak_rate, abs(x[2])), max(peak_roll, abs(x[0]))
            if not peak_rate > 0:
                raise ScenarioError("the model's roll rate does not respond to roll torque")
            roll_cap = _SIZING_ROLL * scenario.roll_limit / peak_roll if peak_roll else math.inf
            sign, size, _ = procedure_draws(scenario, i)
            impulse = sign * min(size * scenario.push_roll_rate / peak_rate, roll_cap)
        sized.append(Push(push.time, float(impulse), push.steer_impulse, push.duration))
    return tuple(sized)


def procedure_draws(scenario: RunScenario, i: int) -> tuple[int, float, float]:
    """Direction (+1 or -1) and size factor of automatic push ``i``, and the factor of its coast.

    The size factor multiplies ``push_roll_rate``, the coast factor ``max_coast``
    (:attr:`RunScenario.push_signs`, ``push_spread``, ``coast_spread``). Without those options:
    alternating directions, factors 1, and no random number drawn.
    """
    if scenario.push_signs == "alternate" and scenario.push_spread == 0 and scenario.coast_spread == 0:
        return (-1) ** i, 1.0, 1.0
    # Three numbers per push from a stream of the procedure's own, so that the i-th push's
    # draws do not depend on which options are set.
    draws = np.random.default_rng([scenario.seed, _PROCEDURE_STREAM]).uniform(size=(i + 1, 3))[i]
    sign = (1 if draws[0] < 0.5 else -1) if scenario.push_signs == "random" else (-1) ** i
    return sign, 1.0 + scenario.push_spread * (2 * draws[1] - 1), 1.0 - scenario.coast_spread * draws[2]


def cut_run(run: SimulatedRun, start: float, stop: float) -> SimulatedRun:
    """Return the samples of a simulated run from `start` to `stop` [s]: a cut segment.

    Published data sets often hold segments cut from longer records: the free coasting and a
    little around it, beginning after the push that started it. The cut keeps the samples'
    times; its free-coasting ``segments`` (and ``true_windows``) are those of the run clipped to
    the cut, and its pushes and catches those inside it.

    Raises
    ------
    ScenarioError
        If the cut holds fewer than 3 samples.
    """
    keep = (run.time >= start - 1e-9) & (run.time <= stop + 1e-9)
    if np.count_nonzero(keep) < 3:
        raise ScenarioError(f"a cut from {start:g} to {stop:g} s holds fewer than 3 samples")
    first, last = float(run.time[keep][0]), float(run.time[keep][-1])
    segments = tuple((max(a, first), min(b, last)) for a, b in run.segments if min(b, last) > max(a, first))
    metadata = {**run.metadata, "true_windows": format_true_windows(segments)}

    def part(values: NDArray[np.float64]) -> NDArray[np.float64]:
        values = values[keep].copy()
        values.flags.writeable = False
        return values

    return replace(run, time=part(run.time), states=part(run.states), speed=part(run.speed),
                   truth={name: part(values) for name, values in run.truth.items()},
                   signals={name: part(values) for name, values in run.signals.items()}, segments=segments,
                   pushes=tuple(push for push in run.pushes if first <= push.time <= last),
                   catches=tuple(t for t in run.catches if first <= t <= last), metadata=metadata)


def push_torque(pushes: tuple[Push, ...], t: float) -> NDArray[np.float64]:
    """Roll and steer torque of the half-sine pulses at time ``t`` [s] [N m]."""
    torque = np.zeros(2)
    for push in pushes:
        if push.time <= t <= push.time + push.duration:
            # A pulse of unit impulse peaks at pi / (2 T).
            shape = 0.5 * np.pi / push.duration * np.sin(np.pi * (t - push.time) / push.duration)
            torque += shape * np.array([float(push.roll_impulse or 0.0), push.steer_impulse])
    return torque


def scheduled_catch(scenario: RunScenario, pushes: tuple[Push, ...], i: int) -> float:
    """Time [s] of the catch after push ``i`` unless a limit brings it earlier."""
    push = pushes[i]
    due = push.time + push.duration + scenario.max_coast * procedure_draws(scenario, i)[2]
    if i + 1 < len(pushes):
        due = min(due, pushes[i + 1].time - scenario.settle)
    return due


def hand_frequency(scenario: RunScenario) -> float:
    """Natural frequency [rad/s] of the critically damped spring of the catch and hold."""
    return CATCH_DECAY / scenario.catch_duration


def hand_wobble(scenario: RunScenario, n: int, rng: np.random.Generator) -> NDArray[np.float64]:
    """Random roll and steer accelerations of the hand [rad/s^2], constant over each interval.

    Shape (n - 1, 2). Scaled so that the critically damped spring driven by this white
    acceleration has a stationary standard deviation of ``hold_std`` [rad]. The first random
    numbers of a run's generator.
    """
    wobble = rng.standard_normal((max(n - 1, 0), 2))
    omega = hand_frequency(scenario)
    return wobble * (scenario.hold_std * math.sqrt(4 * omega**3 * scenario.sample_rate))


def sense(
    bicycle: Bicycle,
    scenario: RunScenario,
    truth: dict[str, NDArray[np.float64]],
    distance: NDArray[np.float64],
    rng: np.random.Generator,
) -> tuple[dict[str, NDArray[np.float64]], dict[str, NDArray[np.float64]]]:
    """Add the speedometer's signal to the truth, and measure every signal with its sensor.

    The scenario's sensor faults act on the true signals before each sensor's noise and bias
    (:func:`whipple.simulation.sensor_faults.faulty_signals`).

    Parameters
    ----------
    truth : dict
        True values of every signal but ``speedometer`` (SI units).
    distance : ndarray
        Distance rolled by the rear wheel since t = 0 [m], as the speedometer sees it
        (before the bicycle's speed scale).

    Returns
    -------
    truth, signals : dict of str to ndarray
        The truth with ``speedometer`` [V], and the scenario's measured columns.
    """
    truth = dict(truth)
    truth["speedometer"] = speedometer_signal(bicycle.measured_speed(distance), float(bicycle.parameters["rR"]),
                                              scenario.pulses_per_revolution,
                                              phase=float(rng.uniform(0, 2 * np.pi)))
    n = distance.size
    seen = faulty_signals(truth, scenario.faults, scenario.sample_rate, scenario.seed)
    measured = {}
    for signal in SIGNALS:  # every signal draws its noise, so columns do not change others
        sensor = getattr(scenario.sensors, signal)
        value = bicycle.measured_speed(seen[signal]) if signal == "speed" else seen[signal]
        measured[signal] = value + sensor.bias + sensor.noise * rng.standard_normal(n)
    return truth, {column: measured[column] for column in scenario.columns}


def run_metadata(
    bicycle: Bicycle,
    scenario: RunScenario,
    segments: tuple[tuple[float, float], ...],
    simulated_by: str,
) -> dict[str, str]:
    """Run-file metadata of a simulated run (``simulated_by``: the simulator's module)."""
    scale = float(bicycle.extensions.speed_scale)
    metadata = {
        "sample_rate": f"{scenario.sample_rate:g}",
        "wheel_radius": f"{float(bicycle.parameters['rR']):g}",
        "pulses_per_revolution": str(scenario.pulses_per_revolution),
        "bicycle": bicycle.name or "unnamed",
        "speed_scale": f"{scale:.9g}",
    }
    if "speed" not in scenario.columns and "speedometer" not in scenario.columns:
        metadata["speed"] = f"{scale * scenario.speed:.9g}"
    metadata.update({
        "simulated": simulated_by,
        "setting": scenario.setting,
        "true_speed": f"{scenario.speed:.9g}",
        "deceleration": f"{scenario.deceleration if scenario.setting == 'ground' else 0.0:g}",
        **({"drag": f"{scenario.drag:g}"} if scenario.drag else {}),
        **fault_metadata(scenario.faults),
        **disturbance_metadata(scenario.disturbance, scenario.disturbance_band),
        "true_windows": format_true_windows(segments),
        "seed": str(scenario.seed),
    })
    return metadata


def freeze(*arrays: NDArray[np.float64]) -> None:
    """Make the arrays of a finished run read-only."""
    for array in arrays:
        array.flags.writeable = False
