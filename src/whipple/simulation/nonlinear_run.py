"""Simulated measured runs whose true motion is the nonlinear Whipple bicycle.

The same procedure as :func:`whipple.simulation.simulator.simulate_run` (the shared parts are
in :mod:`whipple.simulation.procedure`): held upright, released, pushed (the pushes sized on
the linear model, so both simulators push alike), free coasting, caught by the same hand at
the same kind of sample, held with the same wobble, measured by the same sensors; the same
seed draws the same random numbers. Only the true motion differs: the nonlinear equations
(:class:`whipple.simulation.nonlinear_bicycle.ForcedBicycle`), with the bicycle's controller
and steer damping, integrated by scipy's ``solve_ivp`` (DOP853) between the points where the
forces change: sample intervals while held (the hand's wobble is constant over each), the
ends of each push pulse, and the catch. A catch by a limit comes, as in the linear
simulator, at the first sample beyond it: the crossing is located by an event, integrated on
to the next sample and checked there.

Speed: the rear wheel is driven along the scenario's speed profile (constant on a treadmill,
decaying on the ground) by a hub torque (``speed_control="driven"``), or left free
(``"free"``: no resistance, the speed exchanging energy with the lateral motion; the
scenario's deceleration must then be zero or the setting a treadmill).

Every evaluation re-solves the pitch and the dependent rates, so the constraints cannot
drift; the run reports their residuals at the samples (evaluated with the generated NumPy
code) and the energy balance ``E - E(0) - W``, W the work of every torque, integrated along
with the motion (:class:`whipple.simulation.procedure.NonlinearChecks`, also in the run
file's metadata).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import solve_ivp

from whipple.errors import AnalysisError
from whipple.model.assembly import linear_model
from whipple.model.nonlinear import STATES, energy
from whipple.model.parameters import Bicycle
from whipple.simulation.coasting import coasting_deceleration
from whipple.simulation.nonlinear import with_diagnostics
from whipple.simulation.nonlinear_bicycle import ForcedBicycle
from whipple.simulation.procedure import (
    NonlinearChecks,
    SimulatedRun,
    check_aliasing,
    freeze,
    hand_frequency,
    hand_wobble,
    push_torque,
    run_metadata,
    sample_times,
    scheduled_catch,
    sense,
    size_pushes,
)
from whipple.simulation.scenario import Push, RunScenario, ScenarioError

#: Tolerances of solve_ivp (relative; absolute in the state's units: m, rad, rad/s, J).
RTOL, ATOL = 1e-9, 1e-10

_Event = Callable[[float, NDArray[np.float64]], float]


def simulate_nonlinear_run(bicycle: Bicycle, scenario: RunScenario, name: str = "",
                           speed_control: str = "driven") -> SimulatedRun:
    """Simulate one run of a bicycle with the nonlinear model.

    Parameters
    ----------
    bicycle : Bicycle
        Parameters, controller, steer damping and speed scale; a payload, extra steer inertia
        or tyre compliance is refused; an absent IByy or IHyy is estimated (see
        :func:`whipple.simulation.nonlinear_bicycle.nonlinear_parameters`, reported in the
        metadata as ``estimated_parameters``).
    scenario : RunScenario
        Speed, pushes, catches, sensors, seed.
    name : str
        Name of the run (default: from the bicycle, setting and speed).
    speed_control : {"driven", "free"}
        Rear wheel rate held on the speed profile by a hub torque, or free.

    Returns
    -------
    SimulatedRun
        With the nonlinear state (:data:`whipple.model.nonlinear.STATES`) and ``checks``.

    Raises
    ------
    InputError
        An extension the nonlinear model does not hold, a free rear wheel asked to decelerate,
        a speedometer that would alias (ScenarioError).
    AnalysisError
        The integration fails (e.g. the bicycle falls over with the catch's limits raised).
    """
    forced = ForcedBicycle(bicycle, speed_control)
    if any(scenario.disturbance):
        raise ScenarioError("random disturbances are simulated on the linear model only (not with --nonlinear)")
    if speed_control == "free" and scenario.setting == "ground" and (scenario.deceleration != 0 or scenario.drag > 0):
        raise ScenarioError("a free rear wheel cannot follow the ground's deceleration: set it and the drag to 0 "
                            "or drive the wheel")
    time = sample_times(scenario)
    radius = float(forced.parameters["rR"])
    check_aliasing(scenario, bicycle, scenario.speed)
    rng = np.random.default_rng(scenario.seed)
    wobble = hand_wobble(scenario, time.size, rng)
    pushes = size_pushes(scenario, linear_model(bicycle))
    states, segments, catches = _Integration(forced, scenario, pushes, wobble, time).run()
    samples = with_diagnostics(forced.parameters, time, states[:, :10], forced.evaluations, "duration")
    balance = samples.energy - samples.energy[0] - states[:, 10]
    x = states[:, :10]
    speed = -radius * x[:, 9]
    truth = {"roll_rate": x[:, 7].copy(), "yaw_rate": samples.rates[:, 0].copy(), "steer_angle": x[:, 4].copy(),
             "steer_rate": x[:, 8].copy(), "roll_angle": x[:, 3].copy(), "speed": speed.copy()}
    # The speedometer's magnets turn with the wheel relative to the frame carrying the pick-up.
    truth, signals = sense(bicycle, scenario, truth, -radius * (x[:, 5] - x[0, 5]), rng)
    checks = NonlinearChecks(
        holonomic_drift=samples.holonomic_drift, velocity_drift=samples.velocity_drift,
        energy_error=float(np.max(np.abs(balance))), energy_scale=float(energy(forced.parameters, x[0])[0]),
        work=float(states[-1, 10]), evaluations=forced.evaluations)
    states = np.ascontiguousarray(x)
    freeze(time, states, speed, *truth.values(), *signals.values())
    label = name or f"{bicycle.name or 'bicycle'}_{scenario.setting}_{scenario.speed:.2f}ms_nonlinear"
    metadata = run_metadata(bicycle, scenario, segments, "whipple.simulation.nonlinear_run")
    metadata.update({
        "model": "nonlinear",
        "speed_control": speed_control,
        "estimated_parameters": ", ".join(f"{n} = {forced.parameters[n]:.6g}" for n in forced.estimated) or "none",
        "holonomic_drift": f"{checks.holonomic_drift:.3g} m",
        "velocity_drift": f"{checks.velocity_drift:.3g} m/s",
        "energy_error": f"{checks.energy_error:.3g} J (|E - E0 - work of the torques|, "
                        f"initial kinetic energy {checks.energy_scale:.4g} J)",
    })
    return SimulatedRun(label, time, states, STATES, speed, truth, signals, segments, pushes, catches, metadata,
                        scenario, checks)


class _Integration:
    """The regimes of a run (held, free; pushes; catches), integrated piece by piece."""

    def __init__(self, forced: ForcedBicycle, scenario: RunScenario, pushes: tuple[Push, ...],
                 wobble: NDArray[np.float64], time: NDArray[np.float64]):
        self.forced, self.scenario, self.pushes, self.wobble, self.time = forced, scenario, pushes, wobble, time
        self.n = time.size
        self.tolerance = 1e-9 / scenario.sample_rate
        self.omega = hand_frequency(scenario)
        self.driven_ground = forced.speed_control == "driven" and scenario.setting == "ground"
        # Rear wheel rate -v(t)/rR with v' = -(deceleration + drag v^2).
        self.rear_acceleration = scenario.deceleration / float(forced.parameters["rR"]) if self.driven_ground else 0.0
        self.breaks = np.array(sorted({t for p in pushes for t in (p.time, p.time + p.duration)}))
        self.states = np.full((self.n, len(STATES) + 1), np.nan)
        self.states[0] = np.append(forced.upright(scenario.speed), 0.0)

        def roll_limit(t: float, y: NDArray[np.float64]) -> float:
            return scenario.roll_limit - abs(y[3])

        def rate_limit(t: float, y: NDArray[np.float64]) -> float:
            return scenario.roll_rate_limit - abs(y[7])

        for event in (roll_limit, rate_limit):
            event.terminal, event.direction = True, -1  # type: ignore[attr-defined]
        self.limits: tuple[_Event, ...] = (roll_limit, rate_limit)

    def first_interval(self, t: float) -> int:
        """Index k of the first sample interval whose end is past ``t`` [s]."""
        return int(np.searchsorted(self.time[1:], t + self.tolerance, side="right"))

    def run(self) -> tuple[NDArray[np.float64], tuple[tuple[float, float], ...], tuple[float, ...]]:
        """Integrate the whole run: states (n, 11, the last entry the work [J]), windows, catches."""
        n, time, pushes = self.n, self.time, self.pushes
        starts = [self.first_interval(p.time) for p in pushes]
        release = self.first_interval(self.scenario.release)
        held, launched, current, due = True, False, -1, n - 1
        segments: list[tuple[float, float]] = []
        catches: list[float] = []

        def close(stop: float) -> None:
            if current >= 0 and stop > pushes[current].time + pushes[current].duration:
                segments.append((pushes[current].time + pushes[current].duration, stop))

        k = 0
        while k < n - 1:
            next_push = starts[current + 1] if current + 1 < len(pushes) else n - 1
            if held:
                stop = min(next_push, n - 1) if launched else min(next_push, release, n - 1)
                self.hold(k, stop)
            else:
                stop = min(next_push, due, n - 1)
                caught = self.coast(k, stop)
                if caught is not None:
                    k, held, due = caught, True, n - 1
                    catches.append(float(time[k]))
                    close(float(time[k]))
                    continue
            k = stop
            if k >= n - 1:
                break
            if current + 1 < len(pushes) and k == starts[current + 1]:
                if not held:
                    close(float(time[k]))  # pushed again before any catch
                current += 1
                scheduled = scheduled_catch(self.scenario, pushes, current)
                due = int(np.searchsorted(time, scheduled - self.tolerance, side="left"))
                held, launched = False, True
            elif held:  # the release
                held, launched = False, True
            else:  # the scheduled catch
                held, due = True, n - 1
                catches.append(float(time[k]))
                close(float(time[k]))
        if not held:
            close(float(time[-1]))
        return self.states, tuple(segments), tuple(catches)

    def rhs(self, wobble: NDArray[np.float64] | None) -> Callable[[float, NDArray[np.float64]], NDArray[np.float64]]:
        """State derivative with the work; held by the hand when ``wobble`` [rad/s^2] is given."""
        forced, pushes, omega = self.forced, self.pushes, self.omega

        def derivative(t: float, y: NDArray[np.float64]) -> NDArray[np.float64]:
            torques = push_torque(pushes, t)
            rear = self.rear_wheel_acceleration(t)
            if wobble is None:
                return forced.free(y[:10], torques, rear)
            return forced.held(y[:10], torques, omega, wobble, rear)

        return derivative

    def rear_wheel_acceleration(self, t: float) -> float:
        """Angular acceleration [rad/s^2] of the driven rear wheel at time t [s] (0 when free)."""
        scenario = self.scenario
        if not self.driven_ground or scenario.drag == 0:
            return self.rear_acceleration
        slowing = coasting_deceleration(scenario.speed, scenario.deceleration, scenario.drag, t)
        return float(slowing) / float(self.forced.parameters["rR"])

    def hold(self, k: int, stop: int) -> None:
        """Held by the hand from sample k to sample stop (its wobble constant per interval)."""
        for i in range(k, stop):
            self.through(float(self.time[i]), self.states[i], float(self.time[i + 1]), self.rhs(self.wobble[i]))

    def coast(self, k: int, stop: int) -> int | None:
        """Free from sample k towards sample stop; the sample of a catch by a limit, or None."""
        free = self.rhs(None)
        while True:
            event = self.through(float(self.time[k]), self.states[k], float(self.time[stop]), free, self.limits)
            if event is None:
                return None
            t_event, y_event = event
            j = int(np.searchsorted(self.time, t_event - self.tolerance, side="left"))
            self.through(t_event, y_event, float(self.time[j]), free)
            if j >= min(stop, self.n - 1):
                if j < stop:  # past the last sample checked: coast on to the end
                    self.through(float(self.time[j]), self.states[j], float(self.time[stop]), free)
                return None
            x = self.states[j]
            if abs(x[3]) > self.scenario.roll_limit or abs(x[7]) > self.scenario.roll_rate_limit:
                return j
            k = j  # the limit was touched between samples only

    def through(self, t0: float, y0: NDArray[np.float64], t1: float,
                rhs: Callable[[float, NDArray[np.float64]], NDArray[np.float64]],
                events: tuple[_Event, ...] = ()) -> tuple[float, NDArray[np.float64]] | None:
        """Integrate from t0 to t1 [s], split at the push pulses' ends, recording the samples.

        Returns the time and state of a terminal event, or None when t1 was reached.
        """
        y = np.array(y0, dtype=float)
        inner = self.breaks[(self.breaks > t0 + self.tolerance) & (self.breaks < t1 - self.tolerance)]
        for a, b in zip(np.append(t0, inner), np.append(inner, t1), strict=True):
            result = self.piece(float(a), y, float(b), rhs, events)
            if isinstance(result, tuple):
                return result
            y = result
        return None

    def piece(self, t0: float, y0: NDArray[np.float64], t1: float,
              rhs: Callable[[float, NDArray[np.float64]], NDArray[np.float64]],
              events: tuple[_Event, ...]) -> NDArray[np.float64] | tuple[float, NDArray[np.float64]]:
        """One smooth piece: the state at t1, or (time, state) of a terminal event."""
        lo = int(np.searchsorted(self.time, t0 + self.tolerance, side="left"))
        hi = int(np.searchsorted(self.time, t1 - self.tolerance, side="left"))
        inner = np.arange(lo, hi)
        t_eval = np.append(self.time[inner], t1)
        solution = solve_ivp(rhs, (t0, t1), y0, method="DOP853", t_eval=t_eval, events=events or None,
                             rtol=RTOL, atol=ATOL)
        if not solution.success:
            raise AnalysisError(f"the nonlinear run's integration failed at t = {solution.t[-1]:.4g} s: "
                                f"{solution.message}")
        recorded = min(solution.t.size, inner.size)
        self.states[inner[:recorded]] = solution.y.T[:recorded]
        if solution.status == 1:
            fired = next(i for i, times in enumerate(solution.t_events) if times.size)
            return float(solution.t_events[fired][0]), np.asarray(solution.y_events[fired][0], dtype=float)
        if hi < self.n and abs(self.time[hi] - t1) <= self.tolerance:
            self.states[hi] = solution.y[:, -1]
        return np.asarray(solution.y[:, -1], dtype=float)
