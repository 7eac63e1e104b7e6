"""Simulated measured runs: launch, pushes, free coasting, catches, sensor noise and bias.

The true motion is the linear model ``x' = A(v(t)) x + B(v(t)) f(t)`` of the bicycle
(:func:`whipple.model.assembly.linear_model`, so its extensions and controller act). It is integrated
exactly for inputs and speed held constant over each sample interval (matrix exponential of
the augmented system), so stiff castering modes cost nothing in accuracy at any sample rate.
On a treadmill the speed is constant and free coasting is the exact solution of the model.
On the ground the speed falls (:mod:`whipple.simulation.coasting`) and the model is a linear
time-varying system along v(t): each interval takes A at the speed of its midpoint (the
exponential midpoint rule, second order in the interval; at 100 Hz a coast differs from a
dense ``solve_ivp`` of the same system by about 1e-6 of its amplitude), and the terms a
changing speed adds, ``-v' B Ka q`` (:mod:`whipple.model.speed_change`; without them a
ground run differs from the nonlinear model's by a few per cent at 0.05-0.1 m/s^2).

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

import numpy as np
from numpy.typing import NDArray

from whipple.model.assembly import linear_model
from whipple.model.linear import WHIPPLE_STATES, LinearModel
from whipple.model.parameters import Bicycle
from whipple.model.speed_change import acceleration_stiffness
from whipple.model.steer_friction import SMOOTHING_RATE, friction_torque
from whipple.simulation.coasting import coasting_deceleration
from whipple.simulation.discretization import zero_order_hold
from whipple.simulation.disturbance import disturbance_torque
from whipple.simulation.procedure import (
    SimulatedRun,
    check_aliasing,
    distance_rolled,
    freeze,
    hand_frequency,
    hand_wobble,
    run_metadata,
    sample_times,
    scheduled_catch,
    sense,
    size_pushes,
    speed_profile,
)
from whipple.simulation.run_writer import format_true_windows, parse_true_windows, write_run_csv
from whipple.simulation.scenario import Push, RunScenario, ScenarioError

#: The most a sub-step of the free motion lets the steer friction's steepest slope decay the
#: steer rate, as a fraction of it (explicit steps are stable below 2; 0.5 keeps them accurate).
FRICTION_STEP = 0.5

__all__ = ["SimulatedRun", "format_true_windows", "parse_true_windows", "simulate_run",
           "write_run_csv"]


def simulate_run(
    bicycle: Bicycle, scenario: RunScenario, model: LinearModel | None = None, name: str = "",
    acceleration_terms: bool = True,
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
    acceleration_terms : bool
        On the ground, add the terms a changing speed brings, ``-v'(t) B Ka q``
        (:func:`whipple.model.speed_change.acceleration_stiffness`, from the bicycle's
        Whipple parameters and payloads); False: ``x' = A(v(t)) x`` alone. No effect on a treadmill.

    Returns
    -------
    SimulatedRun
        The measured signals, the true states and speed, and the true windows of free coasting.

    Raises
    ------
    ScenarioError
        If the model does not fit, or a speedometer signal would alias at the sample rate.
    """
    if model is None:
        model = linear_model(bicycle)
    _check_model(model)
    geometry = {k: float(bicycle.parameters[k]) for k in ("w", "c", "lam", "rR")}
    fs = scenario.sample_rate
    time = sample_times(scenario)
    speed = speed_profile(scenario, time)
    check_aliasing(scenario, bicycle, float(speed.max()))
    mid_time = time[:-1] + 0.5 / fs
    mid_speed = speed_profile(scenario, mid_time)
    rng = np.random.default_rng(scenario.seed)
    wobble = hand_wobble(scenario, time.size, rng)
    pushes = size_pushes(scenario, model)
    torque = _push_torque(pushes, time, model.B.shape[-1])
    torque += disturbance_torque(scenario.disturbance, scenario.disturbance_band, fs, torque.shape[0], scenario.seed)
    speed_change = None
    if acceleration_terms and scenario.setting == "ground":
        slowing = coasting_deceleration(scenario.speed, scenario.deceleration, scenario.drag, mid_time)
        speed_change = (-slowing, acceleration_stiffness(bicycle))
    dynamics = _Dynamics(model, mid_speed, hand_frequency(scenario), 1.0 / fs, speed_change,
                         float(bicycle.extensions.steer_friction))
    states, segments, catches = _integrate(scenario, pushes, time, torque, wobble, dynamics)
    truth, signals = sense(bicycle, scenario, _true_signals(model, states, speed, geometry),
                           distance_rolled(scenario, time), rng)
    freeze(time, states, speed, *truth.values(), *signals.values())
    label = name or f"{bicycle.name or 'bicycle'}_{scenario.setting}_{scenario.speed:.2f}ms"
    metadata = run_metadata(bicycle, scenario, segments, "whipple.simulation.simulator")
    return SimulatedRun(label, time, states, model.state_names, speed, truth, signals,
                        segments, pushes, catches, metadata, scenario)


def _check_model(model: LinearModel) -> None:
    if model.batch_shape:
        raise ScenarioError("simulate_run needs the model of one bicycle, not a batch")
    if model.state_names[:4] != WHIPPLE_STATES or model.B.shape[-1] != 2:
        raise ScenarioError("the model's states must start with roll, steer, roll_rate, "
                            "steer_rate and its inputs be roll and steer torque")


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
    """Transition matrices of each sample interval, free and held by the hand.

    With Coulomb steer friction (``friction`` [N m], :mod:`whipple.model.steer_friction`), the
    free motion is the linear model plus the friction's torque on the steer, a function of the
    steer rate held over sub-steps of the interval short enough for its steepest slope
    (``F / w`` about zero steer rate) to be integrated stably: each sub-step's decay of the
    steer rate by that slope is at most :data:`FRICTION_STEP` of it. The hand, which replaces
    the bicycle's own dynamics, replaces the friction too.
    """

    def __init__(self, model: LinearModel, speeds: NDArray[np.float64], omega: float, dt: float,
                 speed_change: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
                 friction: float = 0.0):
        unique, first, self.index = np.unique(speeds, return_index=True, return_inverse=True)
        A, B = model.state_matrix(unique), model.input_matrix(unique)
        if speed_change is not None:
            # The forward acceleration v' (a function of the speed) adds the torques -v' Ka q.
            acceleration, stiffness = speed_change
            A = A.copy()
            A[:, :, 0:2] -= acceleration[first][:, None, None] * (B @ stiffness)
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
        self.friction, self.substeps = friction, 1
        if friction > 0.0:
            slope = friction / SMOOTHING_RATE * float(np.max(np.abs(B[:, 3, 1])))
            self.substeps = max(1, math.ceil(dt * slope / FRICTION_STEP))
            self.fine_transition, self.fine_input = zero_order_hold(A, B, dt / self.substeps)

    def free_with_friction(self, x: NDArray[np.float64], u: int, f: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return the state after one free interval with the steer friction, from ``x`` at speed index ``u``."""
        for _ in range(self.substeps):
            torque = f.copy()
            torque[1] += float(friction_torque(self.friction, x[3]))
            x = self.fine_transition[u] @ x + self.fine_input[u] @ torque
        return x


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
            scheduled = scheduled_catch(scenario, pushes, current)
        elif not launched and time[k + 1] > scenario.release + tolerance:
            held, launched = False, True
        elif not held and (abs(x[0]) > scenario.roll_limit or abs(x[2]) > scenario.roll_rate_limit
                           or time[k] >= scheduled - tolerance):
            held, scheduled = True, math.inf
            catches.append(float(time[k]))
            close(float(time[k]))
        phase, u = int(held), dynamics.index[k]
        f = torque[k] + (dynamics.force[u] @ wobble[k] if held else 0.0)
        if dynamics.friction > 0.0 and not held:
            states[k + 1] = dynamics.free_with_friction(x, u, f)
        else:
            states[k + 1] = dynamics.transition[phase, u] @ x + dynamics.input[phase, u] @ f
        if not np.all(np.isfinite(states[k + 1])):
            raise ScenarioError(f"the simulation diverged at t = {time[k + 1]:.3g} s")
    if not held:
        close(float(time[-1]))
    return states, tuple(segments), tuple(catches)


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
