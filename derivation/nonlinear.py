"""The nonlinear Whipple bicycle: Kane's equations in six unconstrained speeds, with the front
wheel's contact constraints kept apart, so that they are solved numerically.

The bicycle is the one of :mod:`whipple.py <whipple.derivation.whipple>` (same frames, points,
bodies and loads). Its configuration is the rear contact's position (x, y) on the ground and the
six angles yaw, roll, pitch (of the rear frame), steer, and the rear and front wheel angles
(each relative to the frame carrying the wheel). The speeds are the angles' rates, u = q'.

The rear wheel's rolling is built into the velocities (its material contact point is at rest),
so every velocity is linear in u and the rear contact's path follows from u by integration.
For this unconstrained six-speed system Kane's equations read

    M(q) u' = F(q, u, T),   M_rs = sum over bodies of m v_r . v_s + w_r . I . w_s,

with v_r, w_r the partial velocities and F the generalized active forces (gravity, the roll
and steer torques T) minus the velocity-dependent part of the generalized inertia forces. The
front wheel rolls without slipping on the ground: the three components of its material contact
point's velocity vanish, C(q) u = 0. The vertical one is the time derivative of the holonomic
constraint h(roll, pitch, steer) = 0 (the front contact's height), which fixes the pitch.
Along a motion d/dt (C u) = 0, i.e. C u' = b with b = -(dC/dt) u. The contact force f on the
front wheel (yaw-frame components) enters through the partial velocities of the contact point,
which are the rows of C, so that

    M u' = F + C^T f,   C u' = b.

Nothing here is inverted or simplified: the pieces are emitted as they are (with common
subexpressions shared) and the library solves the small linear systems numerically, choosing
roll, steer and rear wheel rates as independent speeds.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sm
from sympy.physics.mechanics import ReferenceFrame
from sympy.physics.vector import Vector

from .symbols import pitch, roll, spin_front, spin_rear, steer, yaw
from .whipple import BicycleSystem, Body

# Plain names of the configuration angles, in the order of the speeds u.
ANGLE_NAMES = {yaw: "yaw", roll: "roll", pitch: "pitch", steer: "steer",
               spin_rear: "rear_wheel", spin_front: "front_wheel"}
# Names of the applied torques, in the order of BicycleSystem.inputs.
INPUT_NAMES = ("roll_torque", "steer_torque")


@dataclass(frozen=True)
class Variables:
    """Plain symbols for the dynamic symbols of a system, and the map between them."""

    angles: tuple[sm.Symbol, ...]
    rates: tuple[sm.Symbol, ...]
    inputs: tuple[sm.Symbol, ...]
    table: dict

    def plain(self, expr: sm.Expr) -> sm.Expr:
        return expr.xreplace(self.table)

    def components(self, vector: Vector, frame: ReferenceFrame) -> sm.Matrix:
        """Measure numbers of ``vector`` along ``frame``'s axes, in the plain symbols."""
        return sm.Matrix([self.plain(vector.dot(axis)) for axis in (frame.x, frame.y, frame.z)])

    def time_derivative(self, expr: sm.Expr) -> sm.Expr:
        """d/dt of an expression in the angles and rates, with the rates held (u' = 0)."""
        return sum((expr.diff(q) * u for q, u in zip(self.angles, self.rates, strict=True) if expr.has(q)),
                   sm.S.Zero)


@dataclass(frozen=True)
class NonlinearEquations:
    """The pieces of ``M u' = F + C^T f, C u' = b`` and related quantities, in plain symbols.

    u are the rates of (yaw, roll, pitch, steer, rear wheel, front wheel). ``contact_height``
    is h, whose zero fixes the pitch, with its gradient along (roll, pitch, steer).
    ``rear_contact_velocity`` is (x', y') of the rear contact point on the ground.
    """

    variables: Variables
    mass_matrix: sm.Matrix
    forcing: sm.Matrix
    constraint_matrix: sm.Matrix
    constraint_bias: sm.Matrix
    contact_height: sm.Expr
    contact_height_gradient: sm.Matrix
    kinetic_energy: sm.Expr
    potential_energy: sm.Expr
    rear_contact_velocity: sm.Matrix


def plain_variables(system: BicycleSystem) -> Variables:
    """Plain symbols ``roll``, ``roll_rate``, ... for the system's angles and their rates."""
    t = sm.Symbol("t")
    table: dict = {}
    angles, rates = [], []
    for q in system.coordinates:
        name = ANGLE_NAMES[q]
        rate = sm.Symbol(f"{name}_rate", real=True)
        angle = sm.Symbol(name, real=True)
        # Rates first, so that xreplace replaces q' before q.
        table[q.diff(t)] = rate
        angles.append(angle)
        rates.append(rate)
    table.update({q: angle for q, angle in zip(system.coordinates, angles, strict=True)})
    inputs = tuple(sm.Symbol(name, real=True) for name in INPUT_NAMES)
    table.update(dict(zip(system.inputs, inputs, strict=True)))
    return Variables(tuple(angles), tuple(rates), inputs, table)


def inertia_frame(body: Body, candidates: tuple[ReferenceFrame, ...], variables: Variables) -> ReferenceFrame:
    """The first frame in which the body's central inertia is constant (its own, or its carrier's)."""
    for frame in candidates:
        if not variables.plain(body.central_inertia.to_matrix(frame)).has(*variables.angles):
            return frame
    raise AssertionError(f"no frame with a constant inertia for {body.name}")


def generalized_inertia(system: BicycleSystem, variables: Variables) -> tuple[sm.Matrix, sm.Matrix]:
    """Mass matrix M and the velocity-dependent inertia forces -F* (so that F* = -(M u' + rest)).

    Translation is resolved in the yaw frame A (gravity lies along A.z), rotation in a frame in
    which the body's central inertia is constant; in a frame E turning at Omega,
    d/dt (components) + Omega x (components) gives the inertial rate of change.
    """
    N, A = system.inertial, system.yaw_frame
    u = sm.Matrix(variables.rates)
    n = len(u)
    mass_matrix, inertia_forces = sm.zeros(n, n), sm.zeros(n, 1)
    yaw_rate = sm.Matrix([0, 0, variables.rates[0]])
    carriers = (system.rear_frame, system.front_frame)
    for body in system.bodies:
        velocity = variables.components(body.mass_centre.vel(N), A)
        partial = velocity.jacobian(u)
        acceleration_rest = velocity.applyfunc(variables.time_derivative) + yaw_rate.cross(velocity)
        mass_matrix += body.mass * partial.T * partial
        inertia_forces += body.mass * partial.T * acceleration_rest

        E = inertia_frame(body, (body.frame, *carriers), variables)
        omega = variables.components(body.frame.ang_vel_in(N), E)
        partial_omega = omega.jacobian(u)
        inertia = body.central_inertia.to_matrix(E)
        frame_rate = variables.components(E.ang_vel_in(N), E)
        momentum_rate_rest = (inertia * omega.applyfunc(variables.time_derivative)
                              + frame_rate.cross(inertia * omega))
        mass_matrix += partial_omega.T * inertia * partial_omega
        inertia_forces += partial_omega.T * momentum_rate_rest
    return mass_matrix, inertia_forces


def generalized_active_forces(system: BicycleSystem, variables: Variables) -> sm.Matrix:
    """Generalized active forces of the loads (gravity, roll torque, steer torque)."""
    N, A = system.inertial, system.yaw_frame
    u = sm.Matrix(variables.rates)
    forces = sm.zeros(len(u), 1)
    for load in system.loads:
        motion = load.point.vel(N) if load.point is not None else load.frame.ang_vel_in(N)
        forces += variables.components(motion, A).jacobian(u).T * variables.components(load.vector, A)
    return forces


def front_contact_constraints(system: BicycleSystem, variables: Variables) -> tuple[sm.Matrix, sm.Matrix]:
    """C and b of ``C u = 0`` and ``C u' = b``: the front contact point's velocity vanishes.

    Its yaw-frame components do not depend on the yaw, so their time derivative along the
    motion is the partial derivative in the other angles times their rates.
    """
    velocity = variables.components(system.points["front_contact"].vel(system.inertial), system.yaw_frame)
    constraint_matrix = velocity.jacobian(sm.Matrix(variables.rates))
    bias = -velocity.applyfunc(variables.time_derivative)
    return constraint_matrix, bias


def energies(system: BicycleSystem, variables: Variables, gravity: sm.Symbol) -> tuple[sm.Expr, sm.Expr]:
    """Kinetic energy, and the potential energy of gravity (zero with the mass centres on the ground)."""
    N, A = system.inertial, system.yaw_frame
    rear_contact = system.points["rear_contact"]
    kinetic, potential = sm.S.Zero, sm.S.Zero
    for body in system.bodies:
        velocity = body.mass_centre.vel(N)
        omega = body.frame.ang_vel_in(N)
        kinetic += body.mass * velocity.dot(velocity) / 2 + omega.dot(body.central_inertia.dot(omega)) / 2
        # z points down: the height is -z.
        potential -= body.mass * gravity * body.mass_centre.pos_from(rear_contact).dot(A.z)
    return variables.plain(kinetic), variables.plain(potential)


def rear_contact_velocity(system: BicycleSystem, variables: Variables) -> sm.Matrix:
    """(x', y') of the rear contact point on the ground: the hub's velocity plus that of the
    hub-to-contact vector, which turns with the roll frame."""
    N = system.inertial
    roll_frame = system.frames["roll"]
    hub = system.points["rear_hub"]
    to_contact = system.points["rear_contact"].pos_from(hub)
    velocity = hub.vel(N) + roll_frame.ang_vel_in(N).cross(to_contact)
    # Small expressions in which the roll and yaw rate cancel: simplify shows it.
    return sm.Matrix([sm.simplify(variables.plain(velocity.dot(axis))) for axis in (N.x, N.y)])


def derive_nonlinear_equations(system: BicycleSystem, gravity: sm.Symbol) -> NonlinearEquations:
    """All pieces of the nonlinear equations of the Whipple-type ``system`` (knife-edge wheels).

    ``gravity`` is the symbol of g in the system's gravity loads (for the potential energy).
    """
    variables = plain_variables(system)
    mass_matrix, inertia_forces = generalized_inertia(system, variables)
    forcing = generalized_active_forces(system, variables) - inertia_forces
    constraint_matrix, bias = front_contact_constraints(system, variables)
    height = variables.plain(system.front_contact_position.dot(system.yaw_frame.z))
    # The holonomic constraint depends on roll, pitch and steer only.
    roll_, pitch_, steer_ = (variables.angles[k] for k in (1, 2, 3))
    gradient = sm.Matrix([height.diff(q) for q in (roll_, pitch_, steer_)])
    kinetic, potential = energies(system, variables, gravity)
    return NonlinearEquations(variables, mass_matrix, forcing, constraint_matrix, bias, height, gradient,
                              kinetic, potential, rear_contact_velocity(system, variables))
