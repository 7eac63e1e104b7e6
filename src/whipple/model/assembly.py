"""From a bicycle (parameters, extensions, controller) to its linear model.

The matrices come from the generated code (``whipple.generated``), which ``whipple
regenerate`` derives from first principles in derivation/. This module only assembles them:
it adds the controller's feedback and converts to first-order form, numerically (NumPy,
broadcasting over many parameter sets) or symbolically (CasADi, for root finding and
derivatives with respect to parameters).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, NamedTuple

import casadi
import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import ParameterError
from whipple.generated import (
    whipple_casadi,
    whipple_extended_casadi,
    whipple_extended_numpy,
    whipple_numpy,
)
from whipple.model.linear import LinearModel, polynomial_casadi, second_order_model

if TYPE_CHECKING:
    from whipple.model.parameters import Bicycle, Controller

from whipple.model.parameters import Extensions

_NO_EXTENSIONS = Extensions()

#: Parameters of the base model, in the order of the generated code.
MODEL_PARAMETERS: tuple[str, ...] = tuple(whipple_numpy.PARAMETERS)
#: Parameters of the extended model: the base ones plus payload, steer inertia and damping.
EXTENDED_PARAMETERS: tuple[str, ...] = tuple(whipple_extended_numpy.PARAMETERS)


class Matrices(NamedTuple):
    """Coefficient matrices of ``M q'' + (v C1 + D) q' + (K0 + v^2 K2) q = f``.

    Each has shape (..., 2, 2): M [kg m^2], C1 [kg m], D [N m s/rad], K0 with gravity
    [N m/rad], K2 [kg] (per rad); q = [roll, steer].
    """

    M: NDArray[np.float64]
    C1: NDArray[np.float64]
    K0: NDArray[np.float64]
    K2: NDArray[np.float64]
    D: NDArray[np.float64]


# Sets evaluated per call of the generated code: small enough that its ~100 temporaries stay in
# the CPU cache (measured 6x faster than one call on 10^6 sets, see benchmarks/).
_CHUNK = 8192


def _evaluate(function, arrays: list[NDArray[np.float64]]) -> tuple[NDArray[np.float64], ...]:
    """Call generated code on broadcast parameter arrays, in cache-sized chunks."""
    arrays = list(np.broadcast_arrays(*arrays))
    shape = arrays[0].shape
    size = int(np.prod(shape))
    if size <= _CHUNK:
        return tuple(function(*arrays))
    flat = [array.reshape(-1) for array in arrays]
    pieces = [function(*(array[start:start + _CHUNK] for array in flat))
              for start in range(0, size, _CHUNK)]
    return tuple(np.concatenate([piece[k] for piece in pieces]).reshape(shape + (2, 2))
                 for k in range(len(pieces[0])))


def _gather(parameters: Mapping[str, ArrayLike], names: Sequence[str]) -> list[NDArray[np.float64]]:
    missing = [name for name in names if name not in parameters]
    if missing:
        raise ParameterError(f"missing parameters: {', '.join(missing)}")
    return [np.asarray(parameters[name], dtype=float) for name in names]


def whipple_matrices(parameters: Mapping[str, ArrayLike]) -> Matrices:
    """The Whipple model's matrices for one or many parameter sets.

    Parameters
    ----------
    parameters : mapping of str to array_like
        Benchmark parameters by name (SI units, see ``whipple.model.parameters``); arrays broadcast
        against each other. IByy and IHyy may be present and are not used.

    Returns
    -------
    Matrices
        M, C1, K0 (with gravity), K2, and D = 0; shape broadcast_shape + (2, 2).
    """
    M, C1, K0, K2 = _evaluate(whipple_numpy.matrices, _gather(parameters, MODEL_PARAMETERS))
    return Matrices(M, C1, K0, K2, np.zeros_like(M))


def _extension_values(extensions: Extensions | None) -> dict[str, float]:
    values = (extensions if extensions is not None else _NO_EXTENSIONS).model_values()
    return {name: value for name, value in values.items() if name in EXTENDED_PARAMETERS}


def extended_matrices(
    parameters: Mapping[str, ArrayLike], extensions: Extensions | None = None
) -> Matrices:
    """Matrices including the payload, steer inertia and steer damping extensions.

    Extension values may also be given (as arrays) in ``parameters`` under the names of
    ``EXTENDED_PARAMETERS`` (``payload_mass`` [kg], ``payload_x`` [m], ``payload_z`` [m],
    ``steer_inertia`` [kg m^2], ``steer_damping`` [N m s/rad]); those override ``extensions``.
    """
    merged: dict[str, ArrayLike] = dict(_extension_values(extensions))
    merged.update(parameters)
    M, C1, D, K0, K2 = _evaluate(whipple_extended_numpy.matrices,
                                 _gather(merged, EXTENDED_PARAMETERS))
    return Matrices(M, C1, K0, K2, D)


def build_linear_model(
    parameters: Mapping[str, ArrayLike],
    extensions: Extensions | None = None,
    controller: Controller | None = None,
    description: str = "",
) -> LinearModel:
    """The first-order model of one or many parameter sets (arrays broadcast).

    Parameters
    ----------
    parameters : mapping of str to array_like
        Benchmark parameters (and optionally extension values, see `extended_matrices`).
    extensions : Extensions, optional
        Effects beyond the Whipple model; ``speed_scale`` does not enter the model (it relates
        measured to true speed). Tyre compliance is handled by ``whipple.model.tyre``.
    controller : Controller, optional
        State feedback whose gains are polynomials in the speed.
    """
    tyres = extensions is not None and extensions.tyre_compliance is not None
    if tyres or "cornering_stiffness" in parameters:
        from whipple.model.tyre import tyre_linear_model  # the tyre model has its own states

        return tyre_linear_model(parameters, extensions, controller, description)
    matrices = extended_matrices(parameters, extensions)
    feedback = controller.feedback_coefficients() if controller is not None else None
    return second_order_model(matrices.M, matrices.C1, matrices.K0, matrices.K2,
                              damping=matrices.D, feedback=feedback, description=description)


def linear_model(bicycle: Bicycle) -> LinearModel:
    """The linear model of a bicycle, with its extensions and controller."""
    return build_linear_model(bicycle.parameters, bicycle.extensions, bicycle.controller,
                              description=bicycle.name)


def casadi_matrices(p: casadi.SX | NDArray[np.float64]) -> tuple[casadi.SX, ...]:
    """M, C1, K0, K2 of the base model as CasADi expressions of a parameter vector p.

    p holds the parameters in the order of ``MODEL_PARAMETERS``.
    """
    return tuple(whipple_casadi.matrices(p))


def casadi_state_function(
    bicycle: Bicycle, keys: Sequence[str] = ()
) -> tuple[casadi.Function, NDArray[np.float64]]:
    """``A(v, p)`` as a CasADi function, symbolic in the parameters named by ``keys``.

    Parameters
    ----------
    bicycle : Bicycle
        Supplies the values of every parameter not in ``keys``, the extensions and controller.
    keys : sequence of str
        Names from ``EXTENDED_PARAMETERS`` to keep symbolic (e.g. the keys of the bicycle's
        uncertainty table).

    Returns
    -------
    function : casadi.Function
        ``A = function(v, p)``, with v the speed [m/s] and p the values of ``keys``.
    p0 : ndarray
        The bicycle's values of ``keys``.
    """
    if bicycle.extensions.tyre_compliance is not None:
        from whipple.model.tyre import tyre_casadi_state_function

        return tyre_casadi_state_function(bicycle, keys)
    values = dict(_extension_values(bicycle.extensions))
    values.update({k: float(x) for k, x in bicycle.parameters.items() if k in EXTENDED_PARAMETERS})
    unknown = [key for key in keys if key not in EXTENDED_PARAMETERS]
    if unknown:
        raise ParameterError(f"cannot vary {', '.join(unknown)}: not a model parameter")
    p = casadi.SX.sym("p", len(keys))
    entries = [p[keys.index(name)] if name in keys else casadi.SX(values[name])
               for name in EXTENDED_PARAMETERS]
    M, C1, D, K0, K2 = whipple_extended_casadi.matrices(casadi.vertcat(*entries))
    v = casadi.SX.sym("v")
    stiffness = K0 + v**2 * K2
    damping = v * C1 + D
    gains = bicycle.controller.feedback_coefficients()
    feedback = polynomial_casadi(np.array(gains).reshape(len(gains), 2, 4), v)
    lower = casadi.solve(M, casadi.horzcat(-stiffness, -damping) + feedback)
    A = casadi.vertcat(casadi.horzcat(casadi.SX.zeros(2, 2), casadi.SX.eye(2)), lower)
    p0 = np.array([values[name] for name in keys], dtype=float)
    return casadi.Function("A", [v, p], [A], ["v", "p"], ["A"]), p0
