"""Closed-form modes of second-order models against numpy.linalg.eig of the first-order form."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from eig_modes import nearest_modes_by_eig

from whipple.diagnosis.registry import candidate_causes
from whipple.model.assembly import linear_model, second_order_matrices
from whipple.model.linear import second_order_model
from whipple.model.parameters import Controller, TyreCompliance, load_bicycle
from whipple.stability.nearest_modes import MODE_SHAPE_STATES, nearest_modes
from whipple.stability.quartic import (
    VIETA_TOLERANCE,
    matrix_quartic,
    quartic_roots,
    second_order_eigenvalues,
    second_order_eigenvectors,
    vieta_mismatch,
)

BICYCLES = ("benchmark", "kooijman2008", "sbw2024")


def _speeds(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.concatenate([np.linspace(0.0, 12.0, 1201), rng.uniform(0.0, 60.0, 300)])


def _matched_difference(expected: np.ndarray, found: np.ndarray) -> np.ndarray:
    """Per eigenvalue of ``expected``, relative distance to the nearest of ``found`` (same row)."""
    distance = np.abs(expected[..., :, None] - found[..., None, :]).min(axis=-1)
    return distance / (1.0 + np.abs(expected))


@pytest.mark.parametrize("name", BICYCLES)
def test_eigenvalues_equal_eig_of_the_state_matrix(name):
    bicycle = load_bicycle(name)
    speeds = _speeds(1)
    M, C, K = second_order_matrices(bicycle, speeds)
    expected = np.linalg.eigvals(linear_model(bicycle).state_matrix(speeds))
    found = second_order_eigenvalues(M, C, K)
    assert np.max(_matched_difference(expected, found)) < 1e-12
    assert np.max(_matched_difference(found, expected)) < 1e-12
    # Real eigenvalues come back exactly real, as eig's do (the diagnosis tells weave by Im > 0).
    assert np.sum(found.imag == 0) == np.sum(expected.imag == 0)


@pytest.mark.parametrize("name", BICYCLES)
def test_eigenvectors_give_eigs_mode_shapes(name):
    bicycle = load_bicycle(name)
    speeds = _speeds(2)
    M, C, K = second_order_matrices(bicycle, speeds)
    values, vectors = np.linalg.eig(linear_model(bicycle).state_matrix(speeds))
    ours = second_order_eigenvectors(M, C[:, None], K[:, None], values)
    steer, roll_rate = MODE_SHAPE_STATES["steer_angle"], MODE_SHAPE_STATES["roll_rate"]
    expected = vectors[:, steer, :] / vectors[:, roll_rate, :]
    found = ours[..., steer] / ours[..., roll_rate]
    assert np.max(np.abs(found - expected) / np.abs(expected)) < 1e-9
    # And each is an eigenvector: A x = lambda x.
    A = linear_model(bicycle).state_matrix(speeds)
    residual = np.einsum("nij,nkj->nki", A, ours) - values[..., None] * ours
    assert np.max(np.abs(residual) / (1.0 + np.abs(values[..., None]))) < 1e-9


def test_roots_of_known_quartics():
    # Roots spread over six orders of magnitude, a complex pair beside real roots, two pairs.
    cases = [np.array([-1e-3, -1e3, 2.0 + 5.0j, 2.0 - 5.0j]), np.array([-3.0, -2.0, 1j, -1j]),
             np.array([0.5 + 1j, 0.5 - 1j, -4.0 + 0.1j, -4.0 - 0.1j]), np.array([7.0, -7.0, 0.25, -30.0])]
    for roots in cases:
        a = np.real(np.poly(roots))
        found = quartic_roots(a[None, :])[0]
        assert vieta_mismatch(a[None, :], found[None, :])[0] < VIETA_TOLERANCE
        assert np.max(_matched_difference(roots, found)) < 1e-11


def test_a_double_root_goes_to_eig_and_is_still_found():
    # M q'' + C q' + K q with the roots -1, -1, -2, -3: Newton's step divides by a zero slope at
    # the double root, and the check sends the row to eig.
    M = np.eye(2)
    C = np.array([[2.0, 0.0], [0.0, 5.0]])
    K = np.array([[1.0, 0.0], [0.0, 6.0]])
    a = matrix_quartic(M, C, K)
    assert not vieta_mismatch(a, quartic_roots(a)) <= VIETA_TOLERANCE
    found = second_order_eigenvalues(M[None], C[None], K[None])[0]
    assert np.max(_matched_difference(np.array([-1.0, -1.0, -2.0, -3.0]), found)) < 1e-7


def test_quartic_of_a_general_mass_matrix():
    rng = np.random.default_rng(3)
    M = rng.normal(size=(200, 2, 2)) + 3.0 * np.eye(2)
    C, K = rng.normal(size=(200, 2, 2)), rng.normal(size=(200, 2, 2))
    zero = np.zeros_like(K)
    expected = np.linalg.eigvals(second_order_model(M, zero, K, zero, damping=C).state_matrix(0.0))
    found = second_order_eigenvalues(M, C, K)
    assert np.max(_matched_difference(expected, found)) < 1e-10
    a = matrix_quartic(M, C, K)
    assert np.allclose(a, np.real([np.poly(row) for row in expected]), rtol=1e-9, atol=1e-9)


def test_models_with_more_states_have_no_second_order_matrices():
    bicycle = load_bicycle("benchmark")
    tyres = dataclasses.replace(bicycle, extensions=dataclasses.replace(
        bicycle.extensions, tyre_compliance=TyreCompliance(cornering_stiffness=10.0, camber_stiffness=1.0,
                                                           relaxation_length=0.1)))
    assert second_order_matrices(tyres, [3.0]) is None
    controlled = load_bicycle("sbw2024")
    lagging = dataclasses.replace(controlled, controller=dataclasses.replace(controlled.controller, lag=0.05))
    assert lagging.controller.has_dynamics()
    assert second_order_matrices(lagging, [3.0]) is None
    assert second_order_matrices(controlled, [3.0]) is not None
    assert isinstance(controlled.controller, Controller)


@pytest.mark.parametrize("name", BICYCLES)
def test_nearest_modes_of_every_cause_agree_with_eig(name):
    base = load_bicycle(name)
    rng = np.random.default_rng(4)
    speeds = np.linspace(2.0, 8.0, 25)
    signals = [("steer_angle", "roll_rate")] * len(speeds)
    for cause in candidate_causes(base):
        lower, upper = cause.limits
        for _ in range(3):
            bicycle = cause.apply(base, lower + (upper - lower) * rng.uniform(size=len(lower)))
            try:
                expected, expected_shapes = nearest_modes_by_eig(bicycle, speeds, np.full(len(speeds), 1.0 + 4.0j),
                                                            signals)
            except np.linalg.LinAlgError:
                continue  # a singular trial model: both routes refuse it
            targets = expected + 0.3 * rng.normal(size=len(speeds))
            expected, expected_shapes = nearest_modes_by_eig(bicycle, speeds, targets, signals)
            found, shapes = nearest_modes(bicycle, speeds, targets, signals)
            assert np.max(np.abs(found - expected) / np.abs(expected)) < 1e-9, cause.name
            assert np.max(np.abs(shapes - expected_shapes) / np.abs(expected_shapes)) < 1e-9, cause.name


def test_a_singular_mass_matrix_is_refused_as_eig_refuses_it():
    M = np.array([[[1.0, 2.0], [2.0, 4.0]]])
    C, K = np.eye(2)[None], np.eye(2)[None]
    with pytest.raises(np.linalg.LinAlgError):
        np.linalg.solve(M, K)
    with pytest.raises(np.linalg.LinAlgError):
        second_order_eigenvalues(M, C, K)
