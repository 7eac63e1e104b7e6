"""Mode shape: a second signal's amplitude relative to the roll rate, against the model's eigenvector."""

from __future__ import annotations

import numpy as np
import pytest

from whipple.errors import InputError
from whipple.measurement.experiment import measure_run
from whipple.measurement.mode_shape import amplitude_ratio
from whipple.measurement.runs import run_from_simulation
from whipple.measurement.weavefit import NoOscillationError
from whipple.measurement.windows import Window, find_windows
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle
from whipple.simulation.scenario import RunScenario, Sensor, Sensors
from whipple.simulation.simulator import parse_true_windows, simulate_run
from whipple.stability.nearest_modes import MODE_SHAPE_STATES

QUIET = Sensors(Sensor(1e-6, 0.0), Sensor(1e-6, 0.0), Sensor(1e-6, 0.0))


def _model_ratio(bicycle, speed: float, signal: str = "steer_angle") -> complex:
    values, vectors = np.linalg.eig(linear_model(bicycle).state_matrix(np.array([speed]))[0])
    weave = int(np.argmax(values.imag))
    return complex(vectors[MODE_SHAPE_STATES[signal], weave] / vectors[MODE_SHAPE_STATES["roll_rate"], weave])


def _shapes(bicycle, speed: float, sensors: Sensors, seed: int, within_coasting: bool = False):
    simulated = simulate_run(bicycle, RunScenario(speed=speed, seed=seed, n_pushes=3, sensors=sensors), name="r")
    run = run_from_simulation(simulated)
    windows = None
    if within_coasting:
        # Found windows can run a few samples into the catch (a known limitation of the window
        # finder; the fit's uncertainty then grows accordingly): cut them to the true coasting.
        coasting = parse_true_windows(simulated.metadata["true_windows"])
        windows = [Window(w.run, max(w.start, start), min(w.stop, stop), -1, -1)
                   for w in find_windows(run).windows for start, stop in coasting
                   if w.start < stop and w.stop > start]
    return [m.shape for m in measure_run(run, windows, baseline="auto") if m.usable and m.shape is not None]


@pytest.mark.parametrize("speed", [4.0, 5.0, 6.5, 8.0])
def test_noise_free_ratio_is_the_eigenvector_ratio(speed):
    # The simulated signals are exact sums of the model's modes: the slow mode and the settle
    # time must leave the ratio within a small fraction of a percent of the eigenvector ratio.
    bicycle = load_bicycle("benchmark")
    shapes = _shapes(bicycle, speed, QUIET, seed=2, within_coasting=True)
    assert shapes
    expected = _model_ratio(bicycle, speed)
    for shape in shapes:
        assert abs(shape.ratio - expected) < 2e-3 * abs(expected)


def test_ratio_uncertainty_is_calibrated():
    # Whitened errors of a calibrated (Re, Im) estimate have mean squared norm 2.
    bicycle = load_bicycle("benchmark")
    norms = []
    for seed in range(4):
        for speed in (5.0, 7.0):
            expected = _model_ratio(bicycle, speed)
            for shape in _shapes(bicycle, speed, Sensors(), seed):
                error = np.array([(shape.ratio - expected).real, (shape.ratio - expected).imag])
                norms.append(float(error @ np.linalg.solve(shape.covariance, error)))
    assert len(norms) >= 15
    assert 1.0 < np.mean(norms) < 3.5
    assert np.mean(np.array(norms) < 6.18) > 0.85  # chi2(2) 95% point


def test_ratio_rejects_mismatched_or_short_windows():
    bicycle = load_bicycle("benchmark")
    run = run_from_simulation(simulate_run(bicycle, RunScenario(speed=6.0, seed=1, n_pushes=1), name="r"))
    fit = next(m.fit for m in measure_run(run) if m.usable)
    with pytest.raises(InputError, match="finite samples"):
        amplitude_ratio(fit, np.zeros(fit.time.size - 1), "steer_angle")
    with pytest.raises(NoOscillationError, match="half a weave period"):
        amplitude_ratio(fit, np.zeros(fit.time.size), "steer_angle", settle=fit.stop - fit.start)
    # A steer angle stuck in the window (its weights would be infinite): no ratio, not a NaN.
    with pytest.raises(NoOscillationError, match="steer_angle does not change in the window"):
        amplitude_ratio(fit, np.full(fit.time.size, 0.0123), "steer_angle")


def test_runs_without_a_steer_signal_have_no_shape():
    bicycle = load_bicycle("benchmark")
    scenario = RunScenario(speed=6.0, seed=1, n_pushes=1, columns=("roll_rate", "speed"))
    run = run_from_simulation(simulate_run(bicycle, scenario, name="r"))
    measurements = [m for m in measure_run(run) if m.usable]
    assert measurements and all(m.shape is None for m in measurements)


def test_settle_leaves_the_start_of_each_window_out():
    bicycle = load_bicycle("benchmark")
    run = run_from_simulation(simulate_run(bicycle, RunScenario(speed=6.0, seed=1, n_pushes=2), name="r"))
    plain = [m for m in measure_run(run) if m.usable]
    settled = [m for m in measure_run(run, settle=0.3) if m.usable]
    assert plain and len(settled) == len(plain)
    for a, b in zip(plain, settled, strict=True):
        assert b.fit.start == pytest.approx(a.fit.start + 0.3, abs=0.011) and b.fit.stop == a.fit.stop
        # The shape's own settle time counts from the window's start, not again from the fit's.
        assert b.shape is not None and abs(b.shape.ratio - a.shape.ratio) < 5 * np.sqrt(np.trace(a.shape.covariance))
