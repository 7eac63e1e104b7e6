"""Tyre compliance: linear lateral tyre forces with relaxation instead of knife-edge wheels.

Assumptions (see docs/tyre-compliance.md):

- Each wheel keeps its longitudinal rolling and normal contact conditions; the lateral
  no-slip condition is removed, so the rear contact's lateral speed and the yaw rate become
  degrees of freedom.
- Slip angle alpha = -(lateral velocity of the wheel's material contact point) / v, the
  lateral direction being perpendicular to the wheel's heading in the ground plane. Camber
  gamma is the lean of the wheel plane from vertical: asin(axle . vertical).
- Steady-state lateral force Fy_ss = Fz (C_alpha alpha + C_gamma gamma), Fz the static load
  on the wheel from moment balance of the whole bicycle. Each wheel's force relaxes towards it
  over the relaxation length sigma: (sigma / v) dFy/dt + Fy = Fy_ss. The force acts at the
  contact point along the lateral direction.
- Self-aligning moment: the slip part of the force, Fy - Fz C_gamma gamma, acts a pneumatic
  trail behind the contact (camber thrust has no pneumatic trail).

With relaxation the equations stay polynomial in v: dFy/dt = -(Fz C_alpha / sigma) v_lat +
(v / sigma)(Fz C_gamma gamma - Fy).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sm

from .linearize import DerivationError, kane_linearize
from .symbols import lateral_speed, roll, spin_rear, steer, v, yaw
from .whipple import BicycleSystem, Load


@dataclass(frozen=True)
class DescriptorEquations:
    """``E x' = sum_k v^k A_k x + B f`` with polynomial coefficients in the speed v.

    x = [roll, steer, roll rate, steer rate, lateral speed, yaw rate, rear lateral force,
    front lateral force]; f = [roll torque, steer torque].
    """

    E: sm.Matrix
    A: tuple[sm.Matrix, ...]
    B: sm.Matrix
    states: tuple[str, ...]


TYRE_STATES = ("roll", "steer", "roll_rate", "steer_rate", "lateral_speed", "yaw_rate",
               "rear_lateral_force", "front_lateral_force")


def static_loads(system: BicycleSystem, g: sm.Symbol, wheelbase: sm.Symbol) -> tuple[sm.Expr, sm.Expr]:
    """Static normal loads on the rear and front wheels [N], by moment balance."""
    A = system.yaw_frame
    rear_contact = system.points["rear_contact"]
    upright = {q: 0 for q in system.coordinates}
    weight = sum((body.mass * g for body in system.bodies), sm.S.Zero)
    moment = sum((body.mass * g * body.mass_centre.pos_from(rear_contact).dot(A.x).xreplace(upright)
                  for body in system.bodies), sm.S.Zero)
    front = sm.simplify(moment / wheelbase)
    return sm.simplify(weight - front), front


def add_tyre_forces(system: BicycleSystem, p: dict[str, sm.Symbol]) -> tuple[sm.Symbol, sm.Symbol]:
    """Apply the lateral tyre force (state) of each wheel at its contact, with pneumatic trail."""
    A = system.yaw_frame
    forces = sm.symbols("F_rear F_front", real=True)
    loads = static_loads(system, p["g"], p["w"])
    wheels = (("rear", system.frames["rear_wheel"], system.rear_frame),
              ("front", system.frames["front_wheel"], system.front_frame))
    for force, load, (name, wheel, carrier) in zip(forces, loads, wheels, strict=True):
        heading = system.headings[name]
        lateral = A.z.cross(heading)
        contact = system.points[f"{name}_contact"]
        camber = sm.asin(carrier.y.dot(A.z))
        system.loads.append(Load(force * lateral, point=contact))
        slip_force = force - load * p["camber_stiffness"] * camber
        # The slip force acting a pneumatic trail behind the contact: its moment about it.
        torque = (-p["pneumatic_trail"] * heading).cross(slip_force * lateral)
        system.loads.append(Load(torque, frame=wheel))
    return forces


def derive_tyre_equations(system: BicycleSystem, p: dict[str, sm.Symbol]) -> DescriptorEquations:
    """Linear equations of the bicycle with tyre compliance, in descriptor form."""
    forces = add_tyre_forces(system, p)
    A = system.yaw_frame
    equation_speeds = (roll.diff(), steer.diff(), lateral_speed, yaw.diff())
    result = kane_linearize(system, {spin_rear.diff(): -v / p["rR"]}, equation_speeds,
                            system.inputs + forces)
    variables = result.perturbation
    q = list(variables.coordinates)
    u = list(variables.speeds)
    a = list(variables.accelerations)
    state = q + u + list(forces)
    rates = [variables.kinematics[q[0]], variables.kinematics[q[1]]]

    # Relaxation equations of the tyre forces.
    relaxation = []
    for force, load, name, carrier in zip(forces, static_loads(system, p["g"], p["w"]),
                                          ("rear", "front"), (system.rear_frame, system.front_frame),
                                          strict=True):
        lateral = A.z.cross(system.headings[name])
        zeroth, slip_speed = result.expand(system.points[f"{name}_contact"].vel(system.inertial).dot(lateral))
        zeroth_camber, camber = result.expand(sm.asin(carrier.y.dot(A.z)))
        if zeroth != 0 or zeroth_camber != 0:
            raise DerivationError(f"{name} wheel slips or leans in the nominal motion")
        sigma = p["relaxation_length"]
        relaxation.append(-(load * p["cornering_stiffness"] / sigma) * slip_speed
                          + (v / sigma) * (load * p["camber_stiffness"] * camber - force))

    n = len(state)
    E = sm.eye(n)
    E[2:6, 2:6] = sm.Matrix(4, 4, lambda i, j: result.equations[i].diff(a[j]))
    right = ([rates[0], rates[1]]
             + [-(result.equations[i] - sum((result.equations[i].diff(x) * x for x in a), sm.S.Zero))
                for i in range(4)]
             + relaxation)
    right = [sm.expand(r) for r in right]
    # E x' = right(x, f): acceleration coefficients moved left, so right has none.
    degree = max(sm.degree(r, v) for r in right if r != 0)
    jacobian = [[right[i].diff(x) for x in state] for i in range(n)]
    A_coefficients = [sm.Matrix([[entry.coeff(v, k) if k else entry.xreplace({v: 0}) for entry in row]
                                 for row in jacobian]) for k in range(degree + 1)]
    B = sm.Matrix(n, len(system.inputs), lambda i, j: right[i].diff(system.inputs[j]))
    for k, matrix in enumerate(A_coefficients):
        if any(entry.has(v) for entry in matrix):
            raise DerivationError(f"coefficient of v^{k} still depends on v")
    # Acceleration coefficients carry the sign of Kane's inertia forces: make E's block the
    # (positive definite) mass matrix and flip its rows of the right-hand side accordingly.
    E[2:6, 2:6] = -E[2:6, 2:6]
    for k in range(len(A_coefficients)):
        A_coefficients[k][2:6, :] = -A_coefficients[k][2:6, :]
    B[2:6, :] = -B[2:6, :]
    return DescriptorEquations(E=E, A=tuple(A_coefficients), B=B, states=TYRE_STATES)
