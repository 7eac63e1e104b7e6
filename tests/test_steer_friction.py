"""Coulomb steer friction: its describing function against simulated decay, its candidate, one trial.

The friction's equivalent viscous damping at a window's amplitude
(:func:`whipple.model.steer_friction.describing_gain`, at the window's amplitude-weighted mean
steer amplitude) must predict how the friction, simulated with its nonlinear law, changes each
window's fitted decay rate; the candidate ``steer_friction`` is declared in the registry and
acts on each window through that damping; and a hidden-effect trial of the family names it (or
leaves it leading an ambiguous verdict).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hidden_effects import run_trial, trial_bicycle, trial_options

from whipple.diagnosis.observations import friction_gains, observations, predicted_modes
from whipple.diagnosis.registry import REGISTRY, cause_by_name
from whipple.measurement.experiment import measure_run
from whipple.measurement.runs import run_from_simulation
from whipple.model.assembly import linear_model
from whipple.model.steer_friction import SMOOTHING_RATE, describing_gain, friction_torque
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run


def test_describing_gain_is_the_first_harmonic_of_the_smooth_law():
    # Energy lost per cycle of delta = A sin(w t) by the tanh law, over that of a unit viscous
    # damping: the equivalent damping. Where the steer rate's amplitude is 50 times the
    # smoothing rate the tanh is a sign function to within 1%.
    omega, amplitude, friction = 5.0, 0.2, 0.3
    t = np.linspace(0.0, 2 * np.pi / omega, 200001)
    rate = amplitude * omega * np.cos(omega * t)
    assert amplitude * omega == pytest.approx(1.0) and 1.0 / SMOOTHING_RATE == 50.0
    lost = -np.trapezoid(friction_torque(friction, rate) * rate, t)
    viscous = np.trapezoid(rate * rate, t)
    assert lost / viscous == pytest.approx(friction * float(describing_gain(omega, amplitude)), rel=0.01)
    assert describing_gain(np.array([5.0, 5.0]), np.array([np.nan, 0.0])).tolist() == [0.0, 0.0]


@pytest.mark.parametrize("name", ["benchmark", "browser"])
def test_equivalent_damping_predicts_the_simulated_decay(name):
    """The describing function at each window's amplitude predicts the friction's change of the fitted decay rate.

    Runs at 5-7 m/s with friction of 0.05 and 0.1 N m (equivalent damping 0.2-1.5 N m s/rad),
    simulated with the nonlinear law. Tolerance: the model's decay rate with the equivalent
    damping is within 20% of the friction's change of it (measured minus the model's without
    friction) in the median over windows on the Browser (on the benchmark the friction moves the
    decay rate by less than the window fits' own scatter), and within 8% of the measured decay
    rate in the median over windows, 15% in every window. (Measured: median error 3% on the
    benchmark, 5% on the Browser, worst window 11%; 12% of the friction's change on the Browser.
    Larger friction, 0.2 N m on the Browser, leaves windows off by up to 30%: the weave no longer
    decays like one mode.)
    """
    bicycle = trial_bicycle(name)
    options = trial_options(bicycle)
    errors, changes, relative = [], [], []
    for friction in (0.05, 0.1):
        truth = bicycle.with_extensions(steer_friction=friction)
        for speed in (5.0, 6.0, 7.0):
            run = simulate_run(truth, RunScenario(speed=speed, n_pushes=2, seed=11))
            windows = observations(measure_run(run_from_simulation(run), options=options))
            measured = np.array([o.eigenvalue.real for o in windows])
            with_friction = predicted_modes(truth, windows)[0].real
            without = predicted_modes(bicycle, windows)[0].real
            errors += list(np.abs(with_friction - measured))
            changes += list(np.abs(measured - without))
            relative += list(np.abs(with_friction - measured) / np.abs(measured))
    assert len(errors) >= 8
    assert np.median(relative) < 0.08 and max(relative) < 0.15
    if name == "browser":  # the benchmark's weave damping barely changes with a steer damping
        assert np.median(np.array(errors) / np.array(changes)) < 0.2


def test_the_candidate_is_declared_and_damps_each_window_by_its_amplitude():
    bicycle = trial_bicycle("benchmark")
    assert "steer_friction" in [declaration.name for declaration in REGISTRY]
    cause = cause_by_name(bicycle, "steer_friction")
    assert cause.units == ("N m",) and cause.null == (0.0,)
    changed = cause.apply(bicycle, [0.2])
    assert changed.extensions.steer_friction == 0.2
    # Nonlinear: the linear model leaves it out; each window's model has its equivalent damping.
    assert np.array_equal(linear_model(changed).A, linear_model(bicycle).A)
    run = simulate_run(changed, RunScenario(speed=6.0, n_pushes=2, seed=3))
    windows = observations(measure_run(run_from_simulation(run), options=trial_options(bicycle)))
    gains = friction_gains(windows)
    assert np.all(gains > 0)
    for window, gain in zip(windows, gains, strict=True):
        viscous = bicycle.with_extensions(steer_damping=0.2 * float(gain))
        assert predicted_modes(changed, [window])[0][0] == pytest.approx(predicted_modes(viscous, [window])[0][0])
    # Without a steer angle, the amplitude comes from the roll rate through the model's mode shape.
    roll_only = [replace(w, amplitudes=tuple(a for a in w.amplitudes if a[0] != "steer_angle")) for w in windows]
    assert friction_gains(roll_only).tolist() == [0.0] * len(windows)
    np.testing.assert_allclose(friction_gains(roll_only, bicycle), gains, rtol=0.25)


def test_a_trial_of_steer_friction_names_it_or_leaves_it_leading():
    trial = run_trial("steer_friction", 0, "benchmark")
    assert trial.outcome in ("right", "ambiguous_truth"), (trial.diagnosis.verdict, trial.diagnosis.cause)
