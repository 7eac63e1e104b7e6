"""Kane's method, linearized about upright straight-ahead rolling at constant speed v.

Only first-order terms in the small lateral motion are needed, so nothing is ever expanded
beyond them: every quantity is built exactly (cheap, with sympy.physics.vector) and then
replaced by its first-order Taylor polynomial about the nominal motion. The nonholonomic
constraints are solved the same way: the dependent speeds' coefficient matrix is inverted only
at the nominal configuration (a 3x3 constant matrix), and its first-order correction follows
from differentiating ``C(q) T(q) = -D(q)``. This is what makes the derivation take seconds
where a full symbolic linearization takes minutes.

Orders of magnitude, with eps the size of the lateral perturbation:

- roll, steer, their rates and accelerations, and the yaw rate are O(eps);
- the rear frame pitch is O(eps^2) (lateral symmetry), and so are its rates and the change of
  forward speed: they are set to zero, which the derivation checks (the front contact stays on
  the ground to first order; the solved pitch rate has no first-order part);
- accelerations of mass centres and rates of change of angular momenta vanish in the nominal
  motion, so in Kane's generalized inertia forces only the zeroth-order partial velocities
  are needed; the loads (gravity) are O(1), so their partial velocities are needed to first
  order (this is where the pitch enters: through the partial velocities, never the angle).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sm
from sympy.physics.vector import Vector

from .symbols import pitch, roll, spin_front, spin_rear, steer, v, yaw
from .whipple import BicycleSystem

# Plain symbols for the perturbation variables in the final equations.
q_roll, q_steer = sm.symbols("q_roll q_steer", real=True)
u_roll, u_steer = sm.symbols("u_roll u_steer", real=True)
a_roll, a_steer = sm.symbols("a_roll a_steer", real=True)
COORDINATES = (q_roll, q_steer)
RATES = (u_roll, u_steer)
ACCELERATIONS = (a_roll, a_steer)


class DerivationError(AssertionError):
    """A check of the derivation's own assumptions failed."""


@dataclass(frozen=True)
class LinearEquations:
    """``M q'' + (v C1 + D) q' + (K0 + v^2 K2) q = B f`` with q = [roll, steer].

    Entries are SymPy expressions in the parameters; ``inputs`` are the symbols of f.
    """

    M: sm.Matrix
    C1: sm.Matrix
    D: sm.Matrix
    K0: sm.Matrix
    K2: sm.Matrix
    B: sm.Matrix
    inputs: tuple[sm.Symbol, ...]


def _plain(expr: sm.Expr, table: dict) -> sm.Expr:
    return expr.xreplace(table)


class _Expansion:
    """First-order Taylor expansion about the nominal motion.

    ``nominal`` maps each plain variable to its value in the nominal motion and ``first``
    to its first-order part (an expression in the final perturbation variables). The first-order
    part of f is the directional derivative d/de f(nominal + e * first) at e = 0: one
    differentiation per expression instead of one per variable.
    """

    _eps = sm.Symbol("epsilon_perturbation")

    def __init__(self, nominal: dict, first: dict):
        self.nominal = nominal
        self.first = first
        self._ray = {x: nominal.get(x, x) + self._eps * first.get(x, 0)
                     for x in set(nominal) | set(first)}

    def zeroth(self, expr: sm.Expr) -> sm.Expr:
        return expr.xreplace(self.nominal)

    def first_order(self, expr: sm.Expr) -> sm.Expr:
        return expr.xreplace(self._ray).diff(self._eps).xreplace({self._eps: 0})


def _time_derivative(expr: sm.Expr) -> sm.Expr:
    """d/dt of an expression linear in the perturbation variables (coefficients constant)."""
    chain = {q_roll: u_roll, q_steer: u_steer, u_roll: a_roll, u_steer: a_steer}
    return sum((expr.diff(x) * dx for x, dx in chain.items()), sm.S.Zero)


def linearize(system: BicycleSystem, rear_radius: sm.Symbol) -> LinearEquations:
    """Linearized equations of the lateral motion of ``system`` at forward speed v."""
    A = system.yaw_frame
    N = system.inertial

    # Dynamic symbols -> plain symbols, highest derivatives first so that xreplace is exact.
    coordinates = (yaw, roll, pitch, steer, spin_rear, spin_front)
    plain_q = sm.symbols("yaw_ roll_ pitch_ steer_ spinR_ spinF_", real=True)
    plain_u = sm.symbols("d_yaw d_roll d_pitch d_steer d_spinR d_spinF", real=True)
    plain_a = sm.symbols("dd_yaw dd_roll dd_pitch dd_steer dd_spinR dd_spinF", real=True)
    table = {}
    for q, pq, pu, pa in zip(coordinates, plain_q, plain_u, plain_a, strict=True):
        table[q.diff().diff()] = pa
        table[q.diff()] = pu
        table[q] = pq
    yaw_q, roll_q, pitch_q, steer_q, spinR_q, spinF_q = plain_q
    yaw_u, roll_u, pitch_u, steer_u, spinR_u, spinF_u = plain_u
    yaw_a, roll_a, pitch_a, steer_a, spinR_a, spinF_a = plain_a

    def components(vector: Vector) -> list[sm.Expr]:
        return [_plain(vector.dot(axis), table) for axis in (A.x, A.y, A.z)]

    independent = (roll_u, steer_u, spinR_u)
    dependent = (yaw_u, pitch_u, spinF_u)
    configuration_nominal = {yaw_q: 0, roll_q: 0, pitch_q: 0, steer_q: 0, spinR_q: 0, spinF_q: 0}
    configuration_first = {roll_q: q_roll, steer_q: q_steer}
    speeds_zero = {s: 0 for s in plain_u}

    # --- Holonomic constraint: the front contact stays on the ground. At first order its
    # height must not depend on roll or steer, which is what lets the pitch be dropped.
    height = _plain(system.front_contact_position.dot(A.z), table)
    configuration = _Expansion(configuration_nominal, configuration_first)
    if sm.simplify(configuration.zeroth(height)) != 0 or sm.simplify(configuration.first_order(height)) != 0:
        raise DerivationError("front contact leaves the ground at first order")

    # --- Nonholonomic constraints: C(q) u_dep + D(q) u_ind = 0 from the front contact velocity.
    constraint = components(system.front_contact_velocity)
    C = sm.Matrix([[sm.diff(row, s) for s in dependent] for row in constraint])
    D = sm.Matrix([[sm.diff(row, s) for s in independent] for row in constraint])
    C0 = C.xreplace(configuration_nominal).applyfunc(sm.simplify)
    D0 = D.xreplace(configuration_nominal).applyfunc(sm.simplify)
    # First-order parts in the plain coordinates, so that T stays a function of them.
    in_plain = _Expansion(configuration_nominal, {roll_q: roll_q, steer_q: steer_q})
    C1 = C.applyfunc(in_plain.first_order)
    D1 = D.applyfunc(in_plain.first_order)
    C0_inv = C0.inv().applyfunc(sm.simplify)
    T0 = (-C0_inv * D0).applyfunc(sm.simplify)
    T1 = (-C0_inv * (D1 + C1 * T0)).applyfunc(sm.expand)
    # Dependent speeds to first order with u_ind = (u_roll, u_steer, -v/rR).
    nominal_spin = -v / rear_radius
    dep_nominal = [sm.simplify(T0[i, 2] * nominal_spin) for i in range(3)]
    to_final = {roll_q: q_roll, steer_q: q_steer}
    dep_first = [sm.expand(T0[i, 0] * u_roll + T0[i, 1] * u_steer
                           + T1[i, 2].xreplace(to_final) * nominal_spin) for i in range(3)]
    if dep_nominal[0] != 0 or dep_nominal[1] != 0:
        raise DerivationError("nominal motion has a yaw or pitch rate")
    if sm.simplify(dep_first[1]) != 0:
        raise DerivationError("pitch rate has a first-order part")
    # Coefficients of the independent speeds in the dependent ones, to first order in q.
    transfer = T0 + T1

    # --- The nominal motion and first-order parts of every variable.
    nominal = dict(configuration_nominal)
    nominal.update(speeds_zero)
    nominal.update({spinR_u: nominal_spin, spinF_u: dep_nominal[2], yaw_u: 0, pitch_u: 0})
    nominal.update({s: 0 for s in plain_a})
    first = {roll_q: q_roll, steer_q: q_steer, roll_u: u_roll, steer_u: u_steer,
             roll_a: a_roll, steer_a: a_steer,
             yaw_u: dep_first[0], spinF_u: dep_first[2],
             yaw_a: _time_derivative(dep_first[0]), spinF_a: _time_derivative(dep_first[2])}
    # The applied torques are perturbations too.
    nominal.update({f: 0 for f in system.inputs})
    first.update({f: f for f in system.inputs})
    expansion = _Expansion(nominal, first)

    def partial(vector_components: list[sm.Expr], r: int) -> list[sm.Expr]:
        """Nonholonomic partial velocity w.r.t. independent speed r (exact up to T's order)."""
        return [sm.diff(c, independent[r])
                + sum((sm.diff(c, dependent[d]) * transfer[d, r] for d in range(3)), sm.S.Zero)
                for c in vector_components]

    # Per body: first-order inertia terms, and the exact speeds' components for the partials.
    inertial_terms = []
    for body in system.bodies:
        velocity = components(body.mass_centre.vel(N))
        omega = components(body.frame.ang_vel_in(N))
        acceleration = [expansion.first_order(a) for a in components(body.mass_centre.vel(N).dt(N))]
        momentum_rate = [expansion.first_order(h) for h in
                         components((body.central_inertia & body.frame.ang_vel_in(N)).dt(N))]
        inertial_terms.append((body.mass, velocity, omega, acceleration, momentum_rate))

    equations = []
    for r in range(2):
        generalized = sm.S.Zero
        for mass, velocity, omega, acceleration, momentum_rate in inertial_terms:
            v_r = [expansion.zeroth(c) for c in partial(velocity, r)]
            w_r = [expansion.zeroth(c) for c in partial(omega, r)]
            generalized -= mass * sum((a * x for a, x in zip(acceleration, v_r, strict=True)), sm.S.Zero)
            generalized -= sum((h * x for h, x in zip(momentum_rate, w_r, strict=True)), sm.S.Zero)
        for load in system.loads:
            if load.point is not None:
                motion = components(load.point.vel(N))
            else:
                motion = components(load.frame.ang_vel_in(N))
            work = sum((f * m for f, m in zip(components(load.vector), partial(motion, r), strict=True)),
                       sm.S.Zero)
            if sm.simplify(expansion.zeroth(work)) != 0:
                raise DerivationError("a load does work in the nominal motion")
            generalized += expansion.first_order(work)
        equations.append(sm.expand(generalized))

    return _coefficient_matrices(equations, system.inputs)


def _coefficient_matrices(equations: list[sm.Expr], inputs: tuple[sm.Symbol, ...]) -> LinearEquations:
    """Split ``0 = B f - (M q'' + (v C1 + D) q' + (K0 + v^2 K2) q)`` into its matrices."""

    def coefficient(expr: sm.Expr, variable: sm.Symbol) -> sm.Expr:
        return sm.expand(expr.diff(variable))

    M = sm.Matrix(2, 2, lambda i, j: -coefficient(equations[i], ACCELERATIONS[j]))
    rate = sm.Matrix(2, 2, lambda i, j: -coefficient(equations[i], RATES[j]))
    stiffness = sm.Matrix(2, 2, lambda i, j: -coefficient(equations[i], COORDINATES[j]))
    B = sm.Matrix(2, len(inputs), lambda i, j: coefficient(equations[i], inputs[j]))
    D = rate.xreplace({v: 0})
    C1 = ((rate - D) / v).applyfunc(sm.expand)
    K0 = stiffness.xreplace({v: 0})
    K2 = ((stiffness - K0) / v**2).applyfunc(sm.expand)
    for name, matrix in (("C1", C1), ("K2", K2), ("M", M), ("B", B)):
        if any(entry.has(v) for entry in matrix):
            raise DerivationError(f"{name} depends on the speed: not of the benchmark form")
    return LinearEquations(M=M, C1=C1, D=D, K0=K0, K2=K2, B=B, inputs=inputs)
