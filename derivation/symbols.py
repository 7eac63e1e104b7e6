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
# Extensions of the Whipple model that keep its two degrees of freedom.
EXTENSION_PARAMETERS = {name: BY_NAME[name].described for name in names("extension")}
# Parameters of the tyre-compliance extension (loads are computed from the mass distribution).
TYRE_PARAMETERS = {name: BY_NAME[name].described for name in names("tyre")}

ALL_DESCRIPTIONS = {**BENCHMARK_PARAMETERS, **EXTENSION_PARAMETERS, **TYRE_PARAMETERS}


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
