"""The tyre-compliance model (derivation/tyre.py, whipple.model.tyre).

References: the Whipple model's eigenvalues (generated code, itself checked against Meijaard
et al. 2007 Table 2) as the stiff-tyre limit; Bulsink et al. (2015) and Doria et al. (2019)
for the qualitative effect of realistic tyres (weave less stable); tyre values from
shared spec tyre-model.md (C_alpha 11.5 /rad, C_gamma 0.57 /rad, sigma 0.15 m).
"""

from __future__ import annotations

import numpy as np
import pytest

from whipple.model.assembly import build_linear_model, linear_model
from whipple.model.casadi_model import casadi_state_function
from whipple.model.parameters import Extensions, TyreCompliance, load_bicycle

SPEEDS = np.array([2.0, 4.0, 6.0])


def _slow_eigenvalues(model, speeds, limit=200.0):
    values = np.linalg.eigvals(model.state_matrix(speeds))
    return [np.sort_complex(row[np.abs(row) < limit]) for row in values]


@pytest.mark.parametrize("name", ["benchmark", "kooijman2008"])
def test_stiff_tyres_recover_whipple_eigenvalues(name):
    bicycle = load_bicycle(name)
    whipple = [np.sort_complex(r) for r in np.linalg.eigvals(linear_model(bicycle).state_matrix(SPEEDS))]
    errors = []
    for stiffness, relaxation in [(1e3, 1e-3), (1e5, 1e-5)]:
        stiff = bicycle.with_extensions(tyre_compliance=TyreCompliance(stiffness, 0.0, relaxation))
        slow = _slow_eigenvalues(linear_model(stiff), SPEEDS)
        errors.append(max(np.max(np.abs(s - w)) for s, w in zip(slow, whipple, strict=True)))
    # Converges towards the Whipple eigenvalues as the tyres stiffen.
    assert errors[1] < 1e-3
    assert errors[1] < errors[0] / 10


def test_realistic_tyres_make_the_weave_less_damped_and_add_no_unstable_mode():
    bicycle = load_bicycle("benchmark")
    tyres = bicycle.with_extensions(tyre_compliance=TyreCompliance(11.5, 0.57, 0.15))
    speeds = np.linspace(5.0, 8.0, 7)  # above the weave speed: weave is the oscillatory slow pair
    base = np.linalg.eigvals(linear_model(bicycle).state_matrix(speeds))
    compliant = np.linalg.eigvals(linear_model(tyres).state_matrix(speeds))
    for b, c in zip(base, compliant, strict=True):
        weave_base = b[np.argmax(b.imag)]
        slow = c[np.abs(c) < 30]
        weave_tyre = slow[np.argmax(slow.imag)]
        assert weave_tyre.real > weave_base.real
        fast = c[np.abs(c) >= 30]
        assert np.all(fast.real < 0)


def test_casadi_and_numpy_tyre_models_agree():
    bicycle = load_bicycle("kooijman2008").with_extensions(
        tyre_compliance=TyreCompliance(12.0, 0.8, 0.2, 0.03), steer_damping=0.1)
    function, p0 = casadi_state_function(bicycle, ("cornering_stiffness", "c"))
    numeric = linear_model(bicycle).state_matrix([3.5])[0]
    np.testing.assert_allclose(np.array(function(3.5, p0)), numeric, rtol=1e-10, atol=1e-10)


def test_tyre_values_can_be_batched_as_parameters():
    bicycle = load_bicycle("benchmark")
    stiffness = np.array([8.0, 11.5, 16.0])
    model = build_linear_model({**bicycle.parameters, "cornering_stiffness": stiffness,
                                "camber_stiffness": 0.57, "relaxation_length": 0.15},
                               Extensions())
    assert model.A.shape[:1] == (3,)
    assert model.n_states == 8
