"""From a bicycle (parameters, extensions, controller) to its linear model.

The matrices come from the generated NumPy code (``whipple.generated``), which ``whipple
regenerate`` derives from first principles in derivation/. This module only assembles them,
broadcasting over many parameter sets: it adds the controller's feedback and converts to
first-order form (:mod:`whipple.model.first_order`). The same models as exact CasADi
expressions are in :mod:`whipple.model.casadi_model`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import ParameterError
from whipple.generated import whipple_extended_numpy, whipple_numpy
from whipple.model.actuator import with_actuator
from whipple.model.bodies import fold_point_wheels
from whipple.model.linear import LinearModel, second_order_model
from whipple.model.linear_terms import TERM_MATRICES
from whipple.model.parameters import Bicycle, Controller, Extensions
from whipple.model.tyre import tyre_linear_model

__all__ = ["MODEL_PARAMETERS", "EXTENDED_PARAMETERS", "Matrices", "whipple_matrices", "extension_values",
           "extended_matrices", "EXTENSION_EFFECTS", "model_matrices", "whipple_form_matrices", "build_linear_model",
           "second_order_matrices", "linear_model"]

_NO_EXTENSIONS = Extensions()

#: Parameters of the base model, in the order of the generated code.
MODEL_PARAMETERS: tuple[str, ...] = tuple(whipple_numpy.PARAMETERS)
#: Parameters of the extended model: the base ones plus payloads, steer inertias and damping.
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
    """Return the parameters `names` as arrays, with point wheels (radius 0) folded into their frames.

    The generated code divides by the wheel radii; a point wheel's limit is evaluated exactly
    by :func:`whipple.model.bodies.fold_point_wheels`.
    """
    missing = [name for name in names if name not in parameters]
    if missing:
        raise ParameterError(f"missing parameters: {', '.join(missing)}")
    folded = fold_point_wheels(parameters)
    return [np.asarray(folded[name], dtype=float) for name in names]


def whipple_matrices(parameters: Mapping[str, ArrayLike]) -> Matrices:
    """Return the Whipple model's matrices for one or many parameter sets.

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


def extension_values(extensions: Extensions | None) -> dict[str, float]:
    """Return the extended model's extension values (zero when absent), by parameter name."""
    values = (extensions if extensions is not None else _NO_EXTENSIONS).model_values()
    return {name: value for name, value in values.items() if name in EXTENDED_PARAMETERS}


def extended_matrices(
    parameters: Mapping[str, ArrayLike], extensions: Extensions | None = None
) -> Matrices:
    """Matrices including the payloads, steer inertias and steer damping extensions.

    Extension values may also be given (as arrays) in ``parameters`` under the names of
    ``EXTENDED_PARAMETERS`` (``payload_mass`` [kg], ``payload_x`` [m], ``payload_z`` [m], the
    same prefixed ``front_`` for the front payload, ``steer_inertia`` and
    ``reflected_steer_inertia`` [kg m^2], ``steer_damping`` [N m s/rad]); those override
    ``extensions``.

    Parameters
    ----------
    parameters : mapping of str to array_like
        Benchmark parameters by name (SI units), and optionally extension values (above).
    extensions : Extensions, optional
        The payloads, steer inertias and steer damping (default none).

    Returns
    -------
    Matrices
        M [kg m^2], C1 [kg m], K0 with gravity [N m/rad], K2 [kg] and D [N m s/rad], each of shape
        (..., 2, 2); q = [roll, steer].
    """
    merged: dict[str, ArrayLike] = dict(extension_values(extensions))
    merged.update(parameters)
    M, C1, D, K0, K2 = _evaluate(whipple_extended_numpy.matrices,
                                 _gather(merged, EXTENDED_PARAMETERS))
    return _with_terms(Matrices(M, C1, K0, K2, D), extensions)


def _with_terms(matrices: Matrices, extensions: Extensions | None) -> Matrices:
    """Add the extensions' linear terms (:mod:`whipple.model.linear_terms`) to the matrices."""
    terms = extensions.linear_terms if extensions is not None else None
    if terms is None:
        return matrices
    return matrices._replace(**{name: getattr(matrices, name) + terms.matrix(name) for name in TERM_MATRICES})


#: Extension values that change the matrices on their own (a payload's position matters only
#: with its mass): when all are zero the extended model is the Whipple model.
EXTENSION_EFFECTS = ("payload_mass", "front_payload_mass", "steer_inertia",
                     "reflected_steer_inertia", "steer_damping")


def model_matrices(parameters: Mapping[str, ArrayLike], extensions: Extensions | None = None
                   ) -> Matrices:
    """Return the model's matrices, from the plain Whipple code when no extension enters them.

    :func:`extended_matrices` when an extension has an effect (:data:`EXTENSION_EFFECTS`),
    else :func:`whipple_matrices` (the same matrices to rounding, at a quarter of the cost).
    """
    values: dict[str, ArrayLike] = dict(extension_values(extensions))
    values.update({name: parameters[name] for name in EXTENSION_EFFECTS if name in parameters})
    if any(np.any(np.asarray(values.get(name, 0.0)) != 0) for name in EXTENSION_EFFECTS):
        return extended_matrices(parameters, extensions)
    return _with_terms(whipple_matrices(parameters), extensions)


def _has_tyre_states(parameters: Mapping[str, ArrayLike], extensions: Extensions | None) -> bool:
    """Whether the model has tyre states (:mod:`whipple.model.tyre`), from extensions or parameters."""
    return (extensions is not None and extensions.tyre_compliance is not None) or "cornering_stiffness" in parameters


def whipple_form_matrices(parameters: Mapping[str, ArrayLike], extensions: Extensions | None = None,
                          controller: Controller | None = None) -> Matrices | None:
    """Return the matrices of a model of the Whipple form; None for a model of another form.

    The Whipple form is ``M q'' + v C1 q' + (K0 + v^2 K2) q = 0``: the Whipple model with
    payloads and steer inertias, but no steer damping, tyre states or controller. For such
    models the matrices are all the stability analysis needs
    (:func:`whipple.stability.critical.whipple_speed_table`).
    """
    if (controller is not None and not controller.is_empty()) or _has_tyre_states(parameters, extensions):
        return None
    matrices = model_matrices(parameters, extensions)
    return None if np.any(matrices.D) else matrices


def build_linear_model(
    parameters: Mapping[str, ArrayLike],
    extensions: Extensions | None = None,
    controller: Controller | None = None,
    description: str = "",
) -> LinearModel:
    """Return the first-order model of one or many parameter sets (arrays broadcast).

    Parameters
    ----------
    parameters : mapping of str to array_like
        Benchmark parameters (and optionally extension values, see `extended_matrices`).
    extensions : Extensions, optional
        Effects beyond the Whipple model; ``speed_scale`` does not enter the model (it relates
        measured to true speed). Tyre compliance is handled by ``whipple.model.tyre``.
    controller : Controller, optional
        State feedback whose gains are polynomials in the speed; with a delay or lag the
        model gains actuator states (:mod:`whipple.model.actuator`).
    description : str
        A name for the model, carried along (e.g. the bicycle's).

    Returns
    -------
    LinearModel
        States roll, steer, roll rate and steer rate (and actuator or tyre states where needed);
        inputs roll and steer torque [N m].
    """
    if controller is not None and controller.has_dynamics():
        return with_actuator(build_linear_model(parameters, extensions, None, description), controller)
    if _has_tyre_states(parameters, extensions):
        return tyre_linear_model(parameters, extensions, controller, description)
    matrices = model_matrices(parameters, extensions)
    feedback = controller.feedback_coefficients() if controller is not None else None
    return second_order_model(matrices.M, matrices.C1, matrices.K0, matrices.K2,
                              damping=matrices.D, feedback=feedback, description=description)


def second_order_matrices(bicycle: Bicycle, speeds: ArrayLike
                          ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None:
    """Return M, C(v) and K(v) of ``M q'' + C(v) q' + K(v) q = 0``, or None for a model with more states.

    The bicycle's linear model (:func:`linear_model`) when it has the states ``[q, q']`` only:
    no tyre states and no controller dynamics (a state-feedback controller enters C and K).

    Parameters
    ----------
    bicycle : Bicycle
        One bicycle.
    speeds : array_like
        True forward speeds [m/s], shape S.

    Returns
    -------
    tuple of ndarray or None
        M [kg m^2] (2, 2); ``C = v C1 + D - F_rate(v)`` [N m s/rad] and
        ``K = K0 + v^2 K2 - F_angle(v)`` [N m/rad], each S + (2, 2).
    """
    controller, extensions = bicycle.controller, bicycle.extensions
    if (controller is not None and controller.has_dynamics()) or _has_tyre_states(bicycle.parameters, extensions):
        return None
    matrices = model_matrices(bicycle.parameters, extensions)
    v = np.asarray(speeds, dtype=float)[..., None, None]
    C = v * matrices.C1 + matrices.D
    K = matrices.K0 + v * v * matrices.K2
    # The feedback f = sum_k v^k F_k x moves to the left-hand side.
    for power, gain in enumerate(controller.feedback_coefficients() if controller is not None else []):
        C = C - v**power * gain[:, 2:]
        K = K - v**power * gain[:, :2]
    return matrices.M, C, K


def linear_model(bicycle: Bicycle) -> LinearModel:
    """Return the linear model of a bicycle, with its extensions and controller.

    Parameters
    ----------
    bicycle : Bicycle
        The bicycle (its parameters, extensions such as tyre compliance, and controller).

    Returns
    -------
    LinearModel
        The first-order model ``x' = A(v) x + B u``: states roll [rad], steer [rad], roll rate and
        steer rate [rad/s] (and actuator or tyre states where the bicycle has them).
    """
    return build_linear_model(bicycle.parameters, bicycle.extensions, bicycle.controller,
                              description=bicycle.name)
