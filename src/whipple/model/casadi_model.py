"""The linear models as exact CasADi expressions: symbolic in the speed and in chosen parameters.

Root finding and first-order uncertainty need A(v, p) exactly and differentiably. The matrices
come from the generated CasADi code (``whipple.generated.*_casadi``) and go through the same
first-order assembly as the NumPy models (:mod:`whipple.model.first_order`), with CasADi's
operations.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import casadi
import numpy as np
from numpy.typing import NDArray

from whipple.errors import ParameterError
from whipple.generated import tyre_casadi, whipple_casadi, whipple_extended_casadi
from whipple.model.actuator import actuator_realisation, used_rows
from whipple.model.assembly import EXTENDED_PARAMETERS, extension_values
from whipple.model.bodies import fold_point_wheels, folded_parameters
from whipple.model.first_order import (
    ArrayOps,
    actuator_coefficients,
    descriptor_coefficients,
    second_order_coefficients,
)
from whipple.model.linear import LinearModel
from whipple.model.linear_terms import added_feedback
from whipple.model.parameters import Bicycle
from whipple.model.tyre import TYRE_PARAMETERS, tyre_values

#: CasADi SX matrices (one model; no batch).
CASADI_OPS = ArrayOps(
    join_columns=lambda blocks: casadi.horzcat(*blocks),
    join_rows=lambda blocks: casadi.vertcat(*blocks),
    split_columns=lambda matrix, width: casadi.horzsplit(matrix, width),
    solve=casadi.solve,
    zeros=lambda like, rows, columns: casadi.SX.zeros(rows, columns),
    identity=lambda like, size: casadi.SX.eye(size),
)


def polynomial(coefficients: Sequence[Any] | NDArray[np.float64], speed: casadi.SX) -> casadi.SX:
    """``sum_k speed^k C_k`` as a CasADi expression (Horner's rule).

    Parameters
    ----------
    coefficients : sequence of matrices, or array of shape (K + 1, r, c)
        Coefficients, constant term first (NumPy arrays or CasADi matrices).
    speed : casadi.SX
        The forward speed v [m/s].
    """
    total = casadi.SX(casadi.DM(coefficients[-1]) if isinstance(coefficients[-1], np.ndarray) else coefficients[-1])
    for coefficient in reversed(list(coefficients)[:-1]):
        term = casadi.DM(coefficient) if isinstance(coefficient, np.ndarray) else coefficient
        total = total * speed + term
    return total


def casadi_state_matrix(model: LinearModel) -> casadi.Function:
    """``A(v)`` of a single (unbatched) model as a CasADi function, exact in v [m/s].

    Raises
    ------
    ValueError
        If the model holds a batch of parameter sets.
    """
    if model.batch_shape:
        raise ValueError("casadi_state_matrix needs a single model, not a batch")
    speed = casadi.SX.sym("v")
    return casadi.Function("A", [speed], [polynomial(model.A, speed)], ["v"], ["A"])


def casadi_matrices(p: casadi.SX | NDArray[np.float64]) -> tuple[casadi.SX, ...]:
    """Return M, C1, K0, K2 of the base model as CasADi expressions of a parameter vector p.

    p holds the parameters in the order of ``whipple.model.assembly.MODEL_PARAMETERS``.
    """
    return tuple(whipple_casadi.matrices(p))


def _symbolic(values: Mapping[str, Any], names: Sequence[str], keys: Sequence[str]
              ) -> tuple[casadi.SX, casadi.SX, NDArray[np.float64]]:
    """Return the parameter vector in the order of `names`, symbolic in `keys`; the symbols; their values."""
    unknown = [key for key in keys if key not in names]
    if unknown:
        raise ParameterError(f"cannot vary {', '.join(unknown)}: not a parameter of the model")
    p = casadi.SX.sym("p", len(keys))
    entries = [p[list(keys).index(name)] if name in keys else casadi.SX(float(values[name])) for name in names]
    return casadi.vertcat(*entries), p, np.array([float(values[name]) for name in keys])


def casadi_state_function(bicycle: Bicycle, keys: Sequence[str] = ()
                          ) -> tuple[casadi.Function, NDArray[np.float64]]:
    """``A(v, p)`` of a bicycle's model as a CasADi function, symbolic in the parameters ``keys``.

    Parameters
    ----------
    bicycle : Bicycle
        Supplies the values of every parameter not in ``keys``, the extensions and controller.
    keys : sequence of str
        Names from ``EXTENDED_PARAMETERS`` (or, with tyre compliance, ``TYRE_PARAMETERS``) to
        keep symbolic (e.g. the keys of the bicycle's uncertainty table).

    Returns
    -------
    function : casadi.Function
        ``A = function(v, p)``, with v the speed [m/s] and p the values of ``keys``.
    p0 : ndarray
        The bicycle's values of ``keys``.
    """
    controller = bicycle.controller
    dynamic = controller.has_dynamics()
    # With actuator dynamics the loop is closed afterwards, through the actuator's states.
    feedback = [] if dynamic else controller.feedback_coefficients()
    if bicycle.extensions.linear_terms is not None:
        # The added terms belong to the plant: they act with or without actuator dynamics.
        feedback = added_feedback(feedback, bicycle.extensions.linear_terms.feedback_coefficients())
    gains = [casadi.DM(gain) for gain in feedback]
    if bicycle.extensions.tyre_compliance is not None:
        values = tyre_values({k: x for k, x in bicycle.parameters.items() if k in TYRE_PARAMETERS},
                             bicycle.extensions)
        vector, p, p0 = _symbolic(values, TYRE_PARAMETERS, keys)
        outputs = dict(zip(tyre_casadi.OUTPUTS, tyre_casadi.matrices(vector), strict=True))
        powers = [outputs[name] for name in tyre_casadi.OUTPUTS if name.startswith("A")]
        coefficients, inputs = descriptor_coefficients(outputs["E"], powers, outputs["B"], gains, CASADI_OPS)
    else:
        values = dict(extension_values(bicycle.extensions))
        values.update({k: x for k, x in bicycle.parameters.items() if k in EXTENDED_PARAMETERS})
        folded = [key for key in keys if key in folded_parameters(bicycle.parameters)]
        if folded:
            raise ParameterError(f"cannot vary {', '.join(folded)}: a point wheel (radius 0) is folded "
                                 "into its frame", bicycle.source or None)
        # Point wheels: the same exact limit as the NumPy model (whipple.model.bodies).
        values = {key: float(value) for key, value in fold_point_wheels(values).items()}
        vector, p, p0 = _symbolic(values, EXTENDED_PARAMETERS, keys)
        M, C1, D, K0, K2 = whipple_extended_casadi.matrices(vector)
        coefficients, inputs = second_order_coefficients(M, C1, D, K0, K2, gains, CASADI_OPS)
    if dynamic and used_rows(controller):
        actuator = actuator_realisation(controller.delay, controller.lag)
        coefficients, _ = actuator_coefficients(coefficients, inputs, controller.feedback_coefficients(),
                                                used_rows(controller),
                                                (actuator.a, actuator.b, actuator.c, actuator.d), CASADI_OPS)
    v = casadi.SX.sym("v")
    return casadi.Function("A", [v, p], [polynomial(coefficients, v)], ["v", "p"], ["A"]), p0
