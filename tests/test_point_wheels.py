"""Point wheels (radius zero): the two-mass-skate limit of the Whipple model.

The generated code divides by the wheel radii; a point wheel is evaluated by folding its mass
and inertia into its frame (whipple.model.bodies), which is exact. Checked against the
closed-form matrices of Meijaard et al. (2007) with the gyrostatic coefficients I/r taken as
their limit 0 (tests/meijaard_oracle.py), and against wheels of shrinking radius.
"""

from __future__ import annotations

import numpy as np
import pytest
from meijaard_oracle import meijaard_matrices

from whipple.errors import ParameterError
from whipple.model.assembly import linear_model, whipple_matrices
from whipple.model.casadi_model import casadi_state_function
from whipple.model.parameters import Bicycle, TyreCompliance, check_physical, load_bicycle, validate

#: The two-mass-skate bicycle as BicycleParameters stores it (TmsBenchmark.txt).
TMS = dict(w=1.0, c=0.0, lam=0.0872664626, g=9.81, rR=0.0, mR=0.0, IRxx=0.0, IRyy=0.0, xB=1.2, zB=-0.4,
           mB=10.0, IBxx=0.0, IByy=0.0, IBzz=0.0, IBxz=0.0, xH=1.02, zH=-0.2, mH=1.0, IHxx=0.0, IHyy=0.0,
           IHzz=0.0, IHxz=0.0, rF=0.0, mF=0.0, IFxx=0.0, IFyy=0.0)


def _assert_matrices_close(parameters, expected, tolerance=1e-12):
    computed = whipple_matrices(parameters)
    for name, mine, theirs in zip("M C1 K0 K2".split(), computed[:4], expected, strict=True):
        scale = max(np.max(np.abs(theirs)), 1.0)
        assert np.max(np.abs(mine - theirs)) <= tolerance * scale, name


def test_two_mass_skate_matrices_match_the_closed_form():
    _assert_matrices_close(TMS, meijaard_matrices(TMS))
    # No gyroscopic terms: C1 and K2 come from the masses alone, and are not zero.
    assert np.any(whipple_matrices(TMS).C1 != 0)


@pytest.mark.parametrize("wheel", ["R", "F", "both"])
def test_point_wheels_with_mass_match_the_closed_form(wheel):
    # A skate carrying mass and an inertia about its diameter, on the benchmark bicycle.
    parameters = dict(load_bicycle("benchmark").parameters)
    for letter in ("R", "F") if wheel == "both" else (wheel,):
        parameters |= {f"r{letter}": 0.0, f"I{letter}yy": 0.0, f"I{letter}xx": 0.02}
    assert validate(parameters).ok
    _assert_matrices_close(parameters, meijaard_matrices(parameters))


def test_point_wheels_are_the_limit_of_shrinking_wheels():
    # Wheels of radius r with the mass distribution of a ring (I = m r^2 about the axle):
    # the matrices approach the point-wheel ones linearly in r.
    limit = whipple_matrices(TMS | {"mR": 2.0, "mF": 1.5})
    errors = []
    for r in (1e-2, 1e-3, 1e-4):
        shrunk = TMS | {"mR": 2.0, "mF": 1.5, "rR": r, "rF": r, "IRyy": 2.0 * r**2, "IFyy": 1.5 * r**2,
                        "IRxx": r**2, "IFxx": 0.75 * r**2}
        computed = whipple_matrices(shrunk)
        errors.append(max(np.max(np.abs(a - b)) for a, b in zip(computed[:4], limit[:4], strict=True)))
    # First order in r: the largest term is the wheels' weight moment g (mR + mF) r in K0.
    assert errors[0] == pytest.approx(9.81 * 3.5 * 1e-2, rel=0.05)
    assert errors[1] == pytest.approx(errors[0] / 10, rel=0.05)
    assert errors[2] == pytest.approx(errors[1] / 10, rel=0.05)


def test_the_casadi_model_takes_the_same_limit():
    bicycle = Bicycle(TMS, name="tms")
    function, _ = casadi_state_function(bicycle)
    numpy_model = linear_model(bicycle)
    for speed in (0.5, 3.0):
        assert np.allclose(np.array(function(speed, [])), numpy_model.state_matrix(np.array([speed]))[0],
                           rtol=1e-12, atol=1e-12)
    with pytest.raises(ParameterError, match="cannot vary rR: a point wheel"):
        casadi_state_function(bicycle, ["rR"])


def test_a_point_wheel_cannot_spin_with_inertia():
    with pytest.raises(ParameterError, match=r"rR = 0 \(a point rear wheel\) needs IRyy = 0"):
        check_physical(TMS | {"IRyy": 0.01})


def test_point_masses_without_inertia_to_steer_are_refused():
    # All front mass on the steer axis (which passes through the front contact at zero trail
    # and tilt): steering moves no mass, and M is singular.
    on_axis = TMS | {"lam": 0.0, "xH": 1.0}
    report = validate(on_axis)
    assert any("the mass matrix M is not positive definite" in p for p in report.problems)
    assert validate(TMS).ok


def test_tyre_compliance_needs_wheels_of_positive_radius():
    bicycle = Bicycle(TMS).with_extensions(tyre_compliance=TyreCompliance(11.5, 0.57, 0.1))
    assert "tyre compliance needs wheels of positive radius (rR, rF = 0)" in validate(bicycle).problems
