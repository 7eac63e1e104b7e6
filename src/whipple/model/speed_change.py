"""What a changing forward speed adds to the linear equations: the acceleration stiffness.

The linear Whipple equations, ``M q'' + v C1 q' + (g K0 + v^2 K2) q = f``, hold at constant
speed. When the speed changes (a bicycle coasting on the ground), the time derivatives of the
terms that grow with the speed add one more, ``v' Ka q``: the generalized momenta hold terms
``v P q`` (the frames' yaw rate ``v delta cos(lambda) / w`` and the wheels' spin angular
momentum turned by the steer), whose derivative holds ``v' P q``. For the benchmark bicycle
``Ka = [[0, 33.87], [0, 3.34]] kg m`` (the roll row is C1's roll-steer entry, all of which
comes from such momenta; the steer row is not C1's): a deceleration of 0.05 m/s^2 moves its
weave eigenvalue at 5 m/s from -0.775+4.465i to -0.750+4.457i 1/s.

``Ka`` is taken from the nonlinear equations (:func:`whipple.model.nonlinear.casadi_reduced_equations`):
with the rear wheel's acceleration prescribed, ``mass[:2, :2] a + mass[:2, 2] a_rear = force + tau``,
and at the upright ``mass[:2, 2]`` vanishes; its derivative with respect to roll and steer
times ``a_rear = -v' / rR`` is the term, ``Ka = -d(mass[:2, 2])/dq / rR`` (independent of the
speed). Payloads (point masses) and point wheels are folded into their frames first; other extensions (steer
inertias, tyre compliance, linear terms) and the controller add no term of their own here:
their part is left out (the extended models do not describe a changing speed).
"""

from __future__ import annotations

from functools import cache, lru_cache

import casadi
import numpy as np
from numpy.typing import NDArray

from whipple.errors import InputError
from whipple.model.bodies import Body, combine, fold_point_wheels, frame_body
from whipple.model.nonlinear import (
    PARAMETERS,
    STATES,
    casadi_reduced_equations,
    parameter_vector,
    upright_state,
    with_planar_estimates,
)
from whipple.model.parameters import Bicycle


def acceleration_stiffness(bicycle: Bicycle) -> NDArray[np.float64]:
    """Return ``Ka`` [kg m], shape (2, 2): roll and steer torque per rad of roll and steer per m/s^2.

    ``M q'' + v C1 q' + (g K0 + v^2 K2) q + v' Ka q = f`` with ``q = (roll, steer)`` and ``v'``
    the forward acceleration [m/s^2] (negative while slowing down).

    Raises
    ------
    InputError
        If the nonlinear equations cannot be evaluated upright for the bicycle.
    """
    parameters = _folded_parameters(bicycle)
    stiffness = _stiffness_of(tuple(sorted(parameters.items())))
    if not np.all(np.isfinite(stiffness)):
        raise InputError("the nonlinear equations give no acceleration terms for this bicycle (no upright "
                         "contact configuration): simulate it with acceleration_terms=False",
                         bicycle.source or bicycle.name or None)
    return stiffness.copy()


@lru_cache(maxsize=4096)
def _stiffness_of(parameters: tuple[tuple[str, float], ...]) -> NDArray[np.float64]:
    """``Ka`` [kg m] of the folded parameters: a diagnosis evaluates the same bicycles many times."""
    values = dict(parameters)
    state = upright_state(values, 1.0)
    derivative = np.asarray(_coupling_jacobian()(parameter_vector(values), state), dtype=float)
    return -derivative / float(values["rR"])


def _folded_parameters(bicycle: Bicycle) -> dict[str, float]:
    """Return the bicycle's parameters for the nonlinear model, its payloads folded into their frames."""
    parameters, _ = with_planar_estimates(bicycle.parameters)
    parameters = fold_point_wheels(parameters)  # a point wheel: massless, of unit radius, as in the linear model
    for frame, payload in (("B", bicycle.extensions.payload), ("H", bicycle.extensions.front_payload)):
        if payload is None:
            continue
        joined = combine(frame_body(parameters, frame), Body(payload.mass, payload.x, payload.z, 0.0, 0.0, 0.0, 0.0))
        parameters.update({f"m{frame}": joined.mass, f"x{frame}": joined.x, f"z{frame}": joined.z,
                           f"I{frame}xx": joined.xx, f"I{frame}yy": joined.yy, f"I{frame}zz": joined.zz,
                           f"I{frame}xz": joined.xz})
    return {key: float(value) for key, value in parameters.items()}


@cache
def _coupling_jacobian() -> casadi.Function:
    """(p, state) -> d mass[:2, 2] / d(roll, steer), shape (2, 2) [kg m^2 / rad]."""
    p = casadi.MX.sym("p", len(PARAMETERS))
    angles = casadi.MX.sym("angles", 2)  # roll, steer
    rest = casadi.MX.sym("rest", len(STATES))
    state = casadi.vertcat(rest[:3], angles, rest[5:])
    _, mass, _, _ = casadi_reduced_equations()(p, state)
    jacobian = casadi.jacobian(mass[:2, 2], angles)
    function = casadi.Function("coupling_jacobian", [p, angles, rest], [jacobian])
    return casadi.Function("coupling_jacobian_at", [p, rest], [function(p, rest[3:5], rest)])
