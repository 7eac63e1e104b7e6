"""Symbols of the derivation: the benchmark parameters and the model's variables.

Parameter names follow Meijaard et al. (2007), Table 1, as in the bicycle parameter file.
Every symbol carries a description with its unit.
"""

from __future__ import annotations

import sympy as sm
from sympy.physics.mechanics import dynamicsymbols

# name: description [unit]. IByy and IHyy are absent: they do not enter the linear model
# (the frames do not pitch to first order), which the derivation confirms by construction.
BENCHMARK_PARAMETERS = {
    "w": "wheelbase [m]",
    "c": "trail [m]",
    "lam": "steer axis tilt from vertical [rad]",
    "g": "gravitational acceleration [m/s^2]",
    "rR": "rear wheel radius [m]",
    "mR": "rear wheel mass [kg]",
    "IRxx": "rear wheel moment of inertia about a diameter [kg m^2]",
    "IRyy": "rear wheel moment of inertia about its axle [kg m^2]",
    "xB": "rear frame mass centre, forward of the rear contact [m]",
    "zB": "rear frame mass centre, vertical (z down) [m]",
    "mB": "rear frame mass [kg]",
    "IBxx": "rear frame moment of inertia about x [kg m^2]",
    "IBzz": "rear frame moment of inertia about z [kg m^2]",
    "IBxz": "rear frame product of inertia xz [kg m^2]",
    "xH": "front frame mass centre, forward of the rear contact [m]",
    "zH": "front frame mass centre, vertical (z down) [m]",
    "mH": "front frame mass [kg]",
    "IHxx": "front frame moment of inertia about x [kg m^2]",
    "IHzz": "front frame moment of inertia about z [kg m^2]",
    "IHxz": "front frame product of inertia xz [kg m^2]",
    "rF": "front wheel radius [m]",
    "mF": "front wheel mass [kg]",
    "IFxx": "front wheel moment of inertia about a diameter [kg m^2]",
    "IFyy": "front wheel moment of inertia about its axle [kg m^2]",
}

# The pitch inertias, which enter the nonlinear model only.
PITCH_INERTIA_PARAMETERS = {
    "IByy": "rear frame moment of inertia about y [kg m^2]",
    "IHyy": "front frame moment of inertia about y [kg m^2]",
}

# Extensions of the Whipple model that keep its two degrees of freedom.
EXTENSION_PARAMETERS = {
    "payload_mass": "point mass rigidly attached to the rear frame [kg]",
    "payload_x": "payload position, forward of the rear contact [m]",
    "payload_z": "payload position, vertical (z down) [m]",
    "steer_inertia": "extra moment of inertia of the front frame about the steer axis [kg m^2]",
    "steer_damping": "viscous damping torque about the steer axis per steer rate [N m s/rad]",
}

# Parameters of the tyre-compliance extension (loads are computed from the mass distribution).
TYRE_PARAMETERS = {
    "cornering_stiffness": "lateral force per static wheel load per rad of slip angle [1/rad]",
    "camber_stiffness": "lateral force per static wheel load per rad of camber [1/rad]",
    "relaxation_length": "distance rolled for the lateral force to build up [m]",
    "pneumatic_trail": "self-aligning moment arm of the lateral slip force [m]",
}

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
