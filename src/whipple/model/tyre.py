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

from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike

from whipple.errors import ParameterError
from whipple.generated import tyre_numpy
from whipple.model.actuator import with_actuator
from whipple.model.first_order import descriptor_coefficients
from whipple.model.linear import WHIPPLE_INPUT_UNITS, WHIPPLE_INPUTS, LinearModel
from whipple.model.linear_terms import added_feedback
from whipple.model.parameters import Controller, Extensions

TYRE_PARAMETERS: tuple[str, ...] = tuple(tyre_numpy.PARAMETERS)
TYRE_STATES = ("roll", "steer", "roll_rate", "steer_rate", "lateral_speed", "yaw_rate",
               "rear_lateral_force", "front_lateral_force")
TYRE_STATE_UNITS = ("rad", "rad", "rad/s", "rad/s", "m/s", "rad/s", "N", "N")
_POWERS = tuple(name for name in tyre_numpy.OUTPUTS if name.startswith("A"))


def tyre_values(parameters: Mapping[str, ArrayLike], extensions: Extensions | None) -> dict[str, ArrayLike]:
    """Return the tyre model's parameter values: `parameters` over the extensions' values.

    Raises
    ------
    ParameterError
        If a tyre-model parameter has no value.
    """
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
    """Return the first-order tyre-compliance model for one or many parameter sets.

    Parameters
    ----------
    parameters : mapping of str to array_like
        Benchmark parameters; tyre and other extension values may also be given here by the
        names of ``TYRE_PARAMETERS`` (they override ``extensions``).
    extensions : Extensions, optional
        Must carry ``tyre_compliance`` unless the tyre values are in ``parameters``.
    controller : Controller, optional
        State feedback on roll, steer and their rates, gains polynomial in the speed (with
        actuator states for a delay or lag, :mod:`whipple.model.actuator`).
    """
    if controller is not None and controller.has_dynamics():
        return with_actuator(tyre_linear_model(parameters, extensions, None, description), controller)
    values = tyre_values(parameters, extensions)
    arrays = np.broadcast_arrays(*(np.asarray(values[name], dtype=float) for name in TYRE_PARAMETERS))
    outputs = dict(zip(tyre_numpy.OUTPUTS, tyre_numpy.matrices(*arrays), strict=True))
    gains = controller.feedback_coefficients() if controller is not None else []
    if extensions is not None and extensions.linear_terms is not None:
        gains = added_feedback(gains, extensions.linear_terms.feedback_coefficients())
    coefficients, inputs = descriptor_coefficients(outputs["E"], [outputs[name] for name in _POWERS],
                                                   outputs["B"], gains)
    A, B = np.stack(coefficients, axis=-3), inputs[..., None, :, :]
    return LinearModel(A=A, B=B, state_names=TYRE_STATES, state_units=TYRE_STATE_UNITS,
                       input_names=WHIPPLE_INPUTS, input_units=WHIPPLE_INPUT_UNITS, description=description)
