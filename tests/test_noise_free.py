"""Observations without noise: what windows of given speeds and uncertainties could tell at best.

The trials' "right given the data" counts an ambiguous verdict as right only where the same
windows without noise are ambiguous too; these tests check the twin itself.
"""

from __future__ import annotations

import numpy as np
from synthetic_windows import synthetic_observations

from whipple.diagnosis.causes import cause_by_name
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.fitting import model_residuals, window_whitening
from whipple.diagnosis.observations import noise_free, predicted_modes
from whipple.model.parameters import load_bicycle

SPEEDS = np.repeat([3.5, 4.5, 5.5, 6.5, 7.5], 4)


def test_the_true_model_fits_its_noise_free_twin_exactly_and_the_windows_keep_their_uncertainties():
    bicycle = load_bicycle("benchmark")
    truth = bicycle.with_extensions(steer_damping=0.6)
    measured = synthetic_observations(truth, 3, SPEEDS)
    twin = noise_free(truth, measured)
    eigenvalues, shapes = predicted_modes(truth, measured)
    assert np.array_equal([o.eigenvalue for o in twin], eigenvalues)
    assert np.array_equal([o.shape for o in twin], shapes)
    assert all(np.array_equal(o.covariance, m.covariance) and o.speed == m.speed and o.signals is None
               for o, m in zip(twin, measured, strict=True))
    # The noise is gone: the true model's whitened residuals vanish, the base model's do not.
    whitening = window_whitening(twin, bicycle)
    assert np.max(np.abs(model_residuals(truth, twin, whitening)[0])) < 1e-8
    assert np.max(np.abs(model_residuals(bicycle, twin, whitening)[0])) > 1.0


def test_a_twin_tells_what_no_luck_in_the_noise_could_single_out():
    # A steer inertia and the front wheel's diametral inertia IFxx predict the benchmark's weave
    # alike (tests/test_ambiguity_gain.py): without noise the windows still cannot tell them
    # apart. A steer damping, on the same windows, is singled out.
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name)
              for name in ("steer_inertia", "parameter:IFxx", "steer_damping", "speed_scale", "parameter:c")]
    inertia = bicycle.with_extensions(steer_inertia=0.04)
    twin = diagnose_observations(bicycle, noise_free(inertia, synthetic_observations(inertia, 0, SPEEDS)), causes)
    assert twin.verdict == "ambiguous" and {twin.cause, *twin.rivals} == {"steer_inertia", "parameter:IFxx"}
    damping = bicycle.with_extensions(steer_damping=0.6)
    twin = diagnose_observations(bicycle, noise_free(damping, synthetic_observations(damping, 0, SPEEDS)), causes)
    assert twin.verdict == "named" and twin.cause == "steer_damping"
