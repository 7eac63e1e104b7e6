"""The test oracle (Meijaard et al. 2007, Appendix A) against published numbers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from meijaard_oracle import meijaard_matrices, meijaard_matrices_scalar, random_physical_parameters

from whipple.model.parameters import PARAMETER_NAMES, validate

NAMES = ("M", "C1", "K0", "K2")


def _published(reference, g_in_k0):
    matrices = {name: np.array(reference["matrices"][name]) for name in NAMES}
    if not g_in_k0:
        matrices["K0"] = matrices["K0"] * reference["parameters"]["g"]
    return matrices


def test_benchmark_matrices(meijaard2007):
    # Meijaard et al. (2007), Appendix A / section 4, 14-15 significant digits; the published
    # K0 excludes g, so it is multiplied by g = 9.81 here.
    published = _published(meijaard2007, g_in_k0=False)
    for name, computed in zip(NAMES, meijaard_matrices(meijaard2007["parameters"]), strict=True):
        np.testing.assert_allclose(computed, published[name], rtol=0, atol=1e-12, err_msg=name)


def test_kooijman2008_matrices(kooijman2008):
    # Kooijman & Schwab (2009), eq. (2), printed to 5 decimals with K0 including g.
    published = _published(kooijman2008, g_in_k0=True)
    for name, computed in zip(NAMES, meijaard_matrices(kooijman2008["parameters"]), strict=True):
        np.testing.assert_allclose(
            computed, published[name], rtol=0, atol=0.5e-5 + 1e-12, err_msg=name
        )


def test_benchmark_eigenvalues(meijaard2007):
    # Meijaard et al. (2007), Table 2: eigenvalues at 0-10 m/s; the published digits differ
    # from exact arithmetic by up to about 1e-13 (reference file note).
    M, C1, K0, K2 = meijaard_matrices(meijaard2007["parameters"])
    for key, pairs in meijaard2007["eigenvalues"].items():
        v = float(key[1:])
        stiffness = np.linalg.solve(M, K0 + v**2 * K2)
        damping = np.linalg.solve(M, v * C1)
        A = np.block([[np.zeros((2, 2)), np.eye(2)], [-stiffness, -damping]])
        computed = np.sort_complex(np.linalg.eigvals(A))
        published = np.sort_complex(np.array([complex(re, im) for re, im in pairs]))
        np.testing.assert_allclose(computed, published, rtol=0, atol=1e-12, err_msg=key)


def test_scalar_and_vectorised_oracles_agree(meijaard2007):
    rng = np.random.default_rng(20070501)
    batch = random_physical_parameters(rng, 50)
    vectorised = meijaard_matrices(batch)
    for i in range(50):
        one = meijaard_matrices_scalar({k: float(v[i]) for k, v in batch.items()})
        for name, a, b in zip(NAMES, one, vectorised, strict=True):
            # Same formulas, different evaluation order (x**2 against x*x).
            np.testing.assert_allclose(a, b[i], rtol=1e-13, atol=1e-13, err_msg=name)
    for a, b in zip(
        meijaard_matrices_scalar(meijaard2007["parameters"]),
        meijaard_matrices(meijaard2007["parameters"]),
        strict=True,
    ):
        assert a.shape == b.shape == (2, 2)
        np.testing.assert_allclose(a, b, rtol=1e-15, atol=1e-15)


def test_oracle_broadcasts(meijaard2007):
    parameters = dict(meijaard2007["parameters"])
    parameters["c"] = np.linspace(-0.02, 0.1, 12).reshape(3, 4)
    parameters["g"] = np.array([9.78, 9.81, 9.83, 9.81])  # broadcasts against c's last axis
    matrices = meijaard_matrices(parameters)
    for matrix in matrices:
        assert matrix.shape == (3, 4, 2, 2)
    single = dict(parameters, c=float(parameters["c"][2, 1]), g=float(parameters["g"][1]))
    for a, b in zip(matrices, meijaard_matrices(single), strict=True):
        np.testing.assert_allclose(a[2, 1], b, rtol=1e-15, atol=1e-15)


def test_random_parameter_sets_are_physical_and_varied():
    parameters = random_physical_parameters(np.random.default_rng(7), 1000)
    assert set(parameters) == set(PARAMETER_NAMES)
    assert all(value.shape == (1000,) for value in parameters.values())
    report = validate(parameters)
    assert report.ok, report.problems
    assert not report.warnings
    assert (parameters["c"] < 0).any() and (parameters["c"] > 0.15).any()
    assert np.abs(parameters["lam"]).max() <= 0.6
    assert (parameters["lam"] < 0).any()
    again = random_physical_parameters(np.random.default_rng(7), 1000)
    assert all(np.array_equal(parameters[k], again[k]) for k in PARAMETER_NAMES)


def test_structure_of_the_matrices_for_random_bicycles():
    # Properties of the benchmark equations (Meijaard et al. 2007, section 4): M is a mass
    # matrix, so symmetric positive definite for a physical bicycle; K0 is symmetric; C1 and K2
    # have no roll-angle or roll-rate term in the roll equation.
    M, C1, K0, K2 = meijaard_matrices(random_physical_parameters(np.random.default_rng(3), 1000))
    np.testing.assert_array_equal(M, np.swapaxes(M, -1, -2))
    np.testing.assert_array_equal(K0, np.swapaxes(K0, -1, -2))
    assert np.linalg.eigvalsh(M).min() > 0
    assert not C1[:, 0, 0].any() and not K2[:, :, 0].any()


@pytest.mark.parametrize("folder", ["src", "derivation", "generated"])
def test_oracle_is_never_imported_by_the_package(folder):
    root = Path(__file__).resolve().parent.parent / folder
    for path in root.rglob("*.py"):
        assert "meijaard_oracle" not in path.read_text(encoding="utf-8"), path
