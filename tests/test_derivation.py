"""The derived and generated equations against independent references.

Sources of reference values:
- published matrices: Meijaard et al. (2007) section 4 / Table 1 and Kooijman & Schwab (2009)
  equation (2), shipped in whipple/data/reference (see its README);
- the Meijaard et al. (2007) Appendix A closed form, implemented independently in
  tests/meijaard_oracle.py (never used by the package);
- closed-form equivalences: a payload point mass is the same as a heavier rear frame (parallel
  axis theorem); extra steer inertia is the same as a front frame inertia plus J s s^T.
"""

from __future__ import annotations

import numpy as np
import pytest
import whipple.generated
import whipple.generated.tyre_numpy
import whipple.generated.whipple_extended_numpy
import whipple.generated.whipple_numpy
from meijaard_oracle import meijaard_matrices, random_physical_parameters
from whipple.derivation.regenerate import differences, generate

from whipple.model.assembly import (
    EXTENDED_PARAMETERS,
    MODEL_PARAMETERS,
    extended_matrices,
    whipple_matrices,
)
from whipple.model.casadi_model import casadi_matrices
from whipple.model.verification import reference_sets, verify

NAMES = ("M", "C1", "K0", "K2")


@pytest.mark.parametrize("reference", reference_sets(), ids=lambda r: r.name)
def test_published_matrices_through_casadi(reference):
    result = verify(reference)
    worst = max(entry.error for entry in result.entries)
    assert result.passed, f"largest error {worst:.2e} > tolerance {reference.tolerance:.1e}"


def test_benchmark_to_1e_12_absolute():
    benchmark = next(r for r in reference_sets() if r.name == "benchmark")
    vector = np.array([benchmark.parameters[name] for name in MODEL_PARAMETERS])
    for name, value in zip(NAMES, casadi_matrices(vector), strict=True):
        np.testing.assert_allclose(np.array(value), benchmark.matrices[name], rtol=0, atol=1e-12)


def _normwise_relative(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    # Relative to each matrix's largest entry: some entries vanish identically (C1[0,0]) or
    # nearly cancel, where an entrywise relative error is meaningless.
    scale = np.max(np.abs(b), axis=(-2, -1))
    return np.max(np.abs(a - b), axis=(-2, -1)) / scale


def test_generated_equals_closed_form_at_1000_random_bicycles():
    parameters = random_physical_parameters(np.random.default_rng(20071955), 1000)
    generated = whipple_matrices(parameters)
    oracle = meijaard_matrices(parameters)
    for name, expected in zip(NAMES, oracle, strict=True):
        error = _normwise_relative(getattr(generated, name), expected)
        assert error.shape == (1000,)
        assert np.max(error) < 1e-12, f"{name}: worst normwise relative error {np.max(error):.2e}"


def test_numpy_and_casadi_agree_on_random_bicycles():
    parameters = random_physical_parameters(np.random.default_rng(7), 50)
    numeric = whipple_matrices(parameters)
    for index in range(50):
        vector = np.array([parameters[name][index] for name in MODEL_PARAMETERS])
        for name, value in zip(NAMES, casadi_matrices(vector), strict=True):
            np.testing.assert_allclose(np.array(value), getattr(numeric, name)[index],
                                       rtol=1e-13, atol=1e-13)


def test_broadcasting_over_parameter_arrays():
    benchmark = next(r for r in reference_sets() if r.name == "benchmark").parameters
    parameters = dict(benchmark)
    parameters["c"] = np.linspace(0.0, 0.1, 7)[:, None]
    parameters["mB"] = np.array([80.0, 85.0, 90.0])
    matrices = whipple_matrices(parameters)
    assert matrices.M.shape == (7, 3, 2, 2)
    single = whipple_matrices({**benchmark, "c": parameters["c"][4, 0], "mB": 90.0})
    np.testing.assert_array_equal(matrices.K0[4, 2], single.K0)


def test_one_parameter_set_gives_exactly_its_row_of_a_batch():
    # One set is evaluated as NumPy scalars (the diagnosis' fits evaluate thousands, one at a
    # time); a batch as arrays. The arithmetic is the same, so the results must be bit for bit.
    parameters = random_physical_parameters(np.random.default_rng(11), 40)
    rng = np.random.default_rng(12)
    extensions = {"payload_mass": rng.uniform(0, 20, 40), "payload_x": rng.uniform(-0.3, 1.0, 40),
                  "payload_z": rng.uniform(-1.5, -0.3, 40), "steer_inertia": rng.uniform(0, 0.2, 40),
                  "steer_damping": rng.uniform(0, 2, 40), "front_payload_mass": rng.uniform(0, 8, 40),
                  "front_payload_x": rng.uniform(0.8, 1.4, 40), "front_payload_z": rng.uniform(-1.5, -0.5, 40),
                  "reflected_steer_inertia": rng.uniform(0, 0.3, 40),
                  "cornering_stiffness": rng.uniform(5, 50, 40), "camber_stiffness": rng.uniform(0.3, 1.5, 40),
                  "relaxation_length": rng.uniform(0.01, 0.3, 40), "pneumatic_trail": rng.uniform(0, 0.03, 40)}
    table = {**parameters, **extensions}
    modules = (whipple.generated.whipple_numpy, whipple.generated.whipple_extended_numpy,
               whipple.generated.tyre_numpy)
    for module in modules:
        batch = module.matrices(*(table[name] for name in module.PARAMETERS))
        for index in (0, 17, 39):
            single = module.matrices(*(float(table[name][index]) for name in module.PARAMETERS))
            for name, one, many in zip(module.OUTPUTS, single, batch, strict=True):
                assert one.shape == many.shape[1:]
                np.testing.assert_array_equal(one, many[index], err_msg=f"{module.__name__} {name}")


# Slow (the whole derivation; CI runs `whipple regenerate --check` itself): run with `pytest -m slow`.
@pytest.mark.slow
def test_generated_folder_is_reproduced_by_a_fresh_derivation():
    folder = whipple.generated.__file__.rsplit("/", 1)[0]
    from pathlib import Path

    assert differences(generate(), Path(folder)) == []


def _benchmark() -> dict[str, float]:
    return dict(next(r for r in reference_sets() if r.name == "benchmark").parameters)


def test_payload_equals_heavier_rear_frame():
    p = _benchmark()
    mass, x, z = 6.0, 0.05, -0.75
    extended = extended_matrices({**p, "payload_mass": mass, "payload_x": x, "payload_z": z})
    total = p["mB"] + mass
    xB = (p["mB"] * p["xB"] + mass * x) / total
    zB = (p["mB"] * p["zB"] + mass * z) / total
    combined = dict(p, mB=total, xB=xB, zB=zB)
    # Parallel axis theorem for the tensor entries (Ixz = -sum m x z about the mass centre).
    combined["IBxx"] = p["IBxx"] + p["mB"] * (p["zB"] - zB) ** 2 + mass * (z - zB) ** 2
    combined["IBzz"] = p["IBzz"] + p["mB"] * (p["xB"] - xB) ** 2 + mass * (x - xB) ** 2
    combined["IBxz"] = (p["IBxz"] - p["mB"] * (p["xB"] - xB) * (p["zB"] - zB)
                        - mass * (x - xB) * (z - zB))
    expected = whipple_matrices(combined)
    for name in NAMES:
        np.testing.assert_allclose(getattr(extended, name), getattr(expected, name),
                                   rtol=1e-12, atol=1e-12)


def test_steer_inertia_equals_front_frame_inertia_about_steer_axis():
    p = _benchmark()
    J = 0.02
    s, c = np.sin(p["lam"]), np.cos(p["lam"])
    extended = extended_matrices({**p, "steer_inertia": J})
    expected = whipple_matrices(dict(p, IHxx=p["IHxx"] + J * s * s, IHzz=p["IHzz"] + J * c * c,
                                     IHxz=p["IHxz"] + J * s * c))
    for name in NAMES:
        np.testing.assert_allclose(getattr(extended, name), getattr(expected, name),
                                   rtol=1e-12, atol=1e-12)


def test_steer_damping_acts_on_steer_rate_only():
    extended = extended_matrices({**_benchmark(), "steer_damping": 0.3})
    np.testing.assert_allclose(extended.D, [[0.0, 0.0], [0.0, 0.3]], atol=1e-15)


def test_extended_model_without_extensions_is_the_base_model():
    p = _benchmark()
    base, extended = whipple_matrices(p), extended_matrices(p)
    for name in NAMES:
        np.testing.assert_allclose(getattr(extended, name), getattr(base, name), rtol=1e-13, atol=1e-13)
    assert set(MODEL_PARAMETERS) < set(EXTENDED_PARAMETERS)
    # The pitch inertias cannot enter: the frames do not pitch to first order.
    assert "IByy" not in MODEL_PARAMETERS and "IHyy" not in MODEL_PARAMETERS


def test_table2_eigenvalues_from_the_derived_model():
    """Meijaard et al. (2007) Table 2: eigenvalues at 0..10 m/s, from the derived matrices."""
    import tomllib
    from importlib import resources

    from whipple.model.linear import second_order_model

    text = resources.files("whipple.data").joinpath("reference", "meijaard2007-benchmark.toml").read_text()
    table = tomllib.loads(text)["eigenvalues"]
    matrices = whipple_matrices(_benchmark())
    model = second_order_model(matrices.M, matrices.C1, matrices.K0, matrices.K2)
    for key, published in table.items():
        speed = float(key[1:])
        computed = np.sort_complex(np.linalg.eigvals(model.state_matrix([speed])[0]))
        expected = np.sort_complex(np.array([complex(re, im) for re, im in published]))
        np.testing.assert_allclose(computed, expected, rtol=0, atol=1e-12, err_msg=f"v = {speed} m/s")
