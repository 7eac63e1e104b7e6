"""The payload's rigid-load form: a point mass refined by its own inertia."""

from __future__ import annotations

import numpy as np
import pytest
from synthetic_windows import synthetic_observations

from whipple.diagnosis import candidate_fits
from whipple.diagnosis.causes import payload_form
from whipple.diagnosis.fitting import fit_cause, window_whitening
from whipple.diagnosis.registry import payload_causes
from whipple.diagnosis.starts import refinement_starts
from whipple.model.parameters import load_bicycle

BROWSER = "tests/data/bicycleparameters/bicycles/BrowserBenchmark.txt"


def test_a_refinement_starts_from_the_simpler_fit_off_its_flat_start():
    rigid = payload_form(load_bicycle("benchmark"), "payload", "mxzk")
    starts = refinement_starts(rigid, [8.0, -0.2, -0.7])
    # Not at zero radius, where the added inertia m k^2 has no slope in k.
    assert starts == [[8.0, -0.2, -0.7, pytest.approx(0.03), pytest.approx(0.03)],
                      [8.0, -0.2, -0.7, pytest.approx(0.15), pytest.approx(0.15)]]


def test_a_rigid_load_on_a_light_frame_is_found_from_the_point_mass_fit():
    # A 10 kg box on the Browser's rack (its own roll inertia a third of the 0.53 kg m^2 frame's):
    # the rigid form, started from the point mass's fit, fits at least as well as the point
    # mass (here barely better: weave eigenvalues alone let a point mass placed elsewhere
    # mimic the box), covers the load's mass, and reaches the optimum of a search of its own.
    bicycle = load_bicycle(BROWSER)
    rigid = payload_form(bicycle, "payload", "mxzk")
    truth_values = [10.0, -0.15, -0.7, 0.13, 0.11]
    observations = synthetic_observations(rigid.apply(bicycle, truth_values), 3, np.repeat([3.0, 4.0, 5.0, 6.0], 4))
    whitening = window_whitening(observations, bicycle)
    forms = payload_causes(bicycle, "payload", rigid=True)
    _, fits = candidate_fits.fit_all(bicycle, forms, observations, whitening)
    point, refined = fits[-2], fits[-1]
    assert refined.parameters == rigid.parameters and refined.chi2 <= point.chi2 * (1 + 1e-9)
    assert abs(refined.values[0] - truth_values[0]) < 3 * refined.std[0]
    searched = fit_cause(bicycle, rigid, observations, whitening)
    assert refined.chi2 <= searched.chi2 * (1 + 1e-6)
