"""The tyre-compliance model: lateral tyre forces with relaxation instead of knife edges.

The equations are derived in derivation/tyre.py and emitted to ``whipple.generated.tyre_*``
in descriptor form ``E x' = (A0 + v A1 + ...) x + B f``; this module turns them into a
:class:`~whipple.model.linear.LinearModel` with states

    roll [rad], steer [rad], roll rate [rad/s], steer rate [rad/s], lateral speed of the rear
    contact [m/s], yaw rate [rad/s], rear and front lateral tyre force [N].

As the cornering stiffness grows and the relaxation length shrinks, the eigenvalues tend to
the Whipple model's (tested).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import casadi
import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import ParameterError
from whipple.generated import tyre_casadi, tyre_numpy
from whipple.model.linear import WHIPPLE_INPUT_UNITS, WHIPPLE_INPUTS, LinearModel, polynomial_casadi
from whipple.model.parameters import Extensions

if TYPE_CHECKING:
    from whipple.model.parameters import Bicycle, Controller

TYRE_PARAMETERS: tuple[str, ...] = tuple(tyre_numpy.PARAMETERS)
TYRE_STATES = ("roll", "steer", "roll_rate", "steer_rate", "lateral_speed", "yaw_rate",
               "rear_lateral_force", "front_lateral_force")
TYRE_STATE_UNITS = ("rad", "rad", "rad/s", "rad/s", "m/s", "rad/s", "N", "N")
_POWERS = tuple(name for name in tyre_numpy.OUTPUTS if name.startswith("A"))


def _values(parameters: Mapping[str, ArrayLike], extensions: Extensions | None) -> dict[str, ArrayLike]:
    values: dict[str, ArrayLike] = dict((extensions or Extensions()).model_values())
    values.update(parameters)
    missing = [name for name in TYRE_PARAMETERS if name not in values]
    if missing:
        raise ParameterError(f"tyre model needs {', '.join(missing)}")
    return values


def tyre_linear_model(
    parameters: Mapping[str, ArrayLike],
    extensions: Extensions | None = None,
    controller: Controller | None = None,
    description: str = "",
) -> LinearModel:
    """The first-order tyre-compliance model for one or many parameter sets.

    Parameters
    ----------
    parameters : mapping of str to array_like
        Benchmark parameters; tyre and other extension values may also be given here by the
        names of ``TYRE_PARAMETERS`` (they override ``extensions``).
    extensions : Extensions, optional
        Must carry ``tyre_compliance`` unless the tyre values are in ``parameters``.
    controller : Controller, optional
        State feedback on roll, steer and their rates, gains polynomial in the speed.
    """
    values = _values(parameters, extensions)
    arrays = np.broadcast_arrays(*(np.asarray(values[name], dtype=float) for name in TYRE_PARAMETERS))
    outputs = dict(zip(tyre_numpy.OUTPUTS, tyre_numpy.matrices(*arrays), strict=True))
    E = outputs["E"]
    gains = controller.feedback_coefficients() if controller is not None else []
    degree = max(len(_POWERS), len(gains))
    n = E.shape[-1]
    batch = E.shape[:-2]
    coefficients = np.zeros(batch + (degree, n, n))
    for power, name in enumerate(_POWERS):
        coefficients[..., power, :, :] = outputs[name]
    for power, gain in enumerate(gains):
        coefficients[..., power, :, :4] += outputs["B"] @ gain
    A = np.linalg.solve(E[..., None, :, :], coefficients)
    B = np.linalg.solve(E, outputs["B"])[..., None, :, :]
    return LinearModel(A=A, B=B, state_names=TYRE_STATES, state_units=TYRE_STATE_UNITS,
                       input_names=WHIPPLE_INPUTS, input_units=WHIPPLE_INPUT_UNITS, description=description)


def tyre_casadi_state_function(bicycle: Bicycle, keys: Sequence[str] = ()) -> tuple[casadi.Function, NDArray]:
    """``A(v, p)`` of the tyre model as a CasADi function, symbolic in the named parameters."""
    values = _values({k: x for k, x in bicycle.parameters.items() if k in TYRE_PARAMETERS}, bicycle.extensions)
    unknown = [key for key in keys if key not in TYRE_PARAMETERS]
    if unknown:
        raise ParameterError(f"cannot vary {', '.join(unknown)}: not a tyre-model parameter")
    p = casadi.SX.sym("p", len(keys))
    entries = [p[list(keys).index(name)] if name in keys else casadi.SX(float(values[name]))  # type: ignore[arg-type]
               for name in TYRE_PARAMETERS]
    outputs = dict(zip(tyre_casadi.OUTPUTS, tyre_casadi.matrices(casadi.vertcat(*entries)), strict=True))
    v = casadi.SX.sym("v")
    right = casadi.SX.zeros(outputs["E"].shape)
    for power, name in enumerate(_POWERS):
        right = right + v**power * outputs[name]
    gains = bicycle.controller.feedback_coefficients()
    feedback = polynomial_casadi(np.array(gains).reshape(len(gains), 2, 4), v)
    right[:, :4] = right[:, :4] + outputs["B"] @ feedback
    A = casadi.solve(outputs["E"], right)
    p0 = np.array([float(values[name]) for name in keys])  # type: ignore[arg-type]
    return casadi.Function("A", [v, p], [A], ["v", "p"], ["A"]), p0
