"""Symbols of the derivation: the benchmark parameters and the model's variables.

Parameter names follow Meijaard et al. (2007), Table 1, as in the bicycle parameter file.
Every symbol carries a description with its unit, from ``whipple.model.parameter_table``.
"""

from __future__ import annotations

import sympy as sm
from sympy.physics.mechanics import dynamicsymbols

from whipple.model.parameter_table import BY_NAME, names

# Descriptions with units come from the package's one parameter table. IByy and IHyy are left
# out of the models' parameters: they do not enter the linear model (the frames do not pitch to
# first order), which the derivation confirms by construction.
PITCH_INERTIAS = ("IByy", "IHyy")
BENCHMARK_PARAMETERS = {name: BY_NAME[name].described for name in names("benchmark") if name not in PITCH_INERTIAS}
# The pitch inertias, which enter the nonlinear model only.
PITCH_INERTIA_PARAMETERS = {name: BY_NAME[name].described for name in PITCH_INERTIAS}
# Extensions of the Whipple model that keep its two degrees of freedom.
EXTENSION_PARAMETERS = {name: BY_NAME[name].described for name in names("extension")}
# Parameters of the tyre-compliance extension (loads are computed from the mass distribution).
TYRE_PARAMETERS = {name: BY_NAME[name].described for name in names("tyre")}

# Variables of the nonlinear model. Angles follow the benchmark axes (x forward, y right,
# z down): yaw about z, roll about the yawed x, pitch about the rolled y (zero with the rear
# frame in its reference orientation), steer about the steer axis (down), wheel angles about
# the wheel axles relative to the frame that carries the wheel.
NONLINEAR_VARIABLES = {
    "yaw": "yaw angle of the rear frame [rad]",
    "roll": "roll angle of the rear frame [rad]",
    "pitch": "pitch angle of the rear frame [rad]",
    "steer": "steer angle of the front frame relative to the rear frame [rad]",
    "rear_wheel": "rear wheel angle relative to the rear frame [rad]",
    "front_wheel": "front wheel angle relative to the front frame [rad]",
    "yaw_rate": "yaw rate [rad/s]",
    "roll_rate": "roll rate [rad/s]",
    "pitch_rate": "pitch rate [rad/s]",
    "steer_rate": "steer rate [rad/s]",
    "rear_wheel_rate": "rear wheel rate relative to the rear frame [rad/s]",
    "front_wheel_rate": "front wheel rate relative to the front frame [rad/s]",
    "roll_torque": "torque on the rear frame about the roll axis [N m]",
    "steer_torque": "torque of the rear frame on the front frame about the steer axis [N m]",
}

ALL_DESCRIPTIONS = {**BENCHMARK_PARAMETERS, **PITCH_INERTIA_PARAMETERS, **EXTENSION_PARAMETERS,
                    **TYRE_PARAMETERS, **NONLINEAR_VARIABLES}


def parameter_symbols(names: tuple[str, ...] | list[str]) -> dict[str, sm.Symbol]:
    """Real symbols for the named parameters, keyed by name."""
    return {name: sm.Symbol(name, real=True) for name in names}


# Forward speed of the nominal motion [m/s].
v = sm.Symbol("v", real=True)

# Generalized coordinates [rad]: yaw of the rear frame, roll, pitch of the rear frame (fixed
# by the front wheel's ground contact), steer, and the spin angles of the two wheels.
yaw, roll, pitch, steer, spin_rear, spin_front = dynamicsymbols(
    "psi phi theta delta theta_R theta_F"
)

# Lateral velocity of the rear wheel's contact point [m/s], along the yaw frame's y axis: a
# generalized speed of the tyre-compliance model (it has no coordinate of its own).
lateral_speed = dynamicsymbols("u_y")
