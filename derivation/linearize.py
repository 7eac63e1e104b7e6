"""Kane's method, linearized about upright straight-ahead rolling at constant speed v.

Only first-order terms in the small lateral motion are needed, so nothing is ever expanded
beyond them: every quantity is built exactly (cheap, with sympy.physics.vector) and then
replaced by its first-order Taylor polynomial about the nominal motion. The nonholonomic
constraints are solved the same way: the dependent speeds' coefficient matrix is inverted only
at the nominal configuration (a constant matrix), and its first-order correction follows from
differentiating ``C(q) T(q) = -D(q)``. This is what makes the derivation take seconds where a
full symbolic linearization takes minutes.

Orders of magnitude, with eps the size of the lateral perturbation:

- roll, steer, their rates and accelerations, lateral and yaw rates, applied torques and tyre
  forces are O(eps);
- the rear frame pitch is O(eps^2) (lateral symmetry), and so are its rates and the change of
  forward speed: they are set to zero, which the derivation checks (the front contact stays on
  the ground to first order; the solved pitch rate has no first-order part);
- accelerations of mass centres and rates of change of angular momenta vanish in the nominal
  motion, so in Kane's generalized inertia forces only the zeroth-order partial velocities
  are needed; gravity is O(1), so its partial velocities are needed to first order (this is
  where the pitch enters: through the partial velocities, never the angle).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sm
from sympy.physics.vector import Vector

from .symbols import pitch, roll, spin_rear, steer, v
from .whipple import BicycleSystem


class DerivationError(AssertionError):
    """A check of the derivation's own assumptions failed."""


@dataclass(frozen=True)
class Perturbation:
    """The final perturbation variables of the linear equations.

    ``coordinates`` are the small configuration variables (roll, steer), ``speeds`` the
    independent speeds whose Kane equations are formed (their accelerations are
    ``accelerations``), ``kinematics`` maps each coordinate to its rate.
    """

    coordinates: tuple[sm.Symbol, ...]
    speeds: tuple[sm.Symbol, ...]
    accelerations: tuple[sm.Symbol, ...]
    kinematics: dict[sm.Symbol, sm.Symbol]


@dataclass(frozen=True)
class KaneLinearization:
    """First-order Kane equations ``0 = sum of generalized forces`` and related quantities.

    ``equations[r]`` is linear in the perturbation variables and in ``first_order_symbols``;
    ``expand`` gives the first-order part of any further quantity of the system (e.g. a slip
    velocity) in the same variables.
    """

    equations: list[sm.Expr]
    perturbation: Perturbation
    expand: object = field(repr=False)


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


def kane_linearize(
    system: BicycleSystem,
    nominal_speeds: dict[sm.Expr, sm.Expr],
    equation_speeds: tuple[sm.Expr, ...],
    first_order_symbols: tuple[sm.Symbol, ...],
) -> KaneLinearization:
    """Linearized Kane equations of ``system`` for the speeds in ``equation_speeds``.

    Parameters
    ----------
    system : BicycleSystem
        Bodies, loads, the speeds (independent and dependent, as dynamic symbols) and the
        constraints (scalar velocity expressions that vanish).
    nominal_speeds : dict
        Independent speeds whose nominal value is not zero (the rear wheel spin, -v/rR).
    equation_speeds : tuple
        Independent speeds whose Kane equations are formed; the others (the rear wheel spin)
        decouple from the lateral motion at first order.
    first_order_symbols : tuple
        Symbols that are O(eps) and kept as they are (applied torques, tyre forces).
    """
    A = system.yaw_frame
    N = system.inertial
    t = sm.Symbol("t")

    # Dynamic symbols -> plain symbols, highest derivatives first so that xreplace is exact.
    # ``rate_of`` maps each plain speed to the plain symbol of its time derivative.
    table: dict = {}
    plain_q: dict = {}
    rate_of: dict = {}
    for q in system.coordinates:
        name = str(q.func)
        plain_q[q] = sm.Symbol(f"{name}_", real=True)
        table[q.diff(t, 2)] = sm.Symbol(f"dd_{name}", real=True)
        table[q.diff(t)] = sm.Symbol(f"d_{name}", real=True)
        rate_of[table[q.diff(t)]] = table[q.diff(t, 2)]
    for u in system.generalized_speeds:
        name = str(u.func)
        table[u.diff(t)] = sm.Symbol(f"d_{name}", real=True)
        table[u] = sm.Symbol(f"{name}_", real=True)
        rate_of[table[u]] = table[u.diff(t)]
    table.update(plain_q)

    def plain(expr: sm.Expr) -> sm.Expr:
        return expr.xreplace(table)

    def components(vector: Vector) -> list[sm.Expr]:
        return [plain(vector.dot(axis)) for axis in (A.x, A.y, A.z)]

    independent = [plain(s) for s in system.independent_speeds]
    dependent = [plain(s) for s in system.dependent_speeds]
    in_equations = [independent.index(plain(s)) for s in equation_speeds]

    # Final perturbation variables: q_<coordinate>, u_<speed>, a_<speed>.
    q_final = {plain_q[roll]: sm.Symbol("q_roll", real=True), plain_q[steer]: sm.Symbol("q_steer", real=True)}
    u_final, a_final = {}, {}
    for i in in_equations:
        name = str(independent[i]).removeprefix("d_").removesuffix("_")
        u_final[independent[i]] = sm.Symbol(f"u_{name}", real=True)
        a_final[independent[i]] = sm.Symbol(f"a_{name}", real=True)
    perturbation = Perturbation(
        coordinates=tuple(q_final.values()), speeds=tuple(u_final.values()),
        accelerations=tuple(a_final.values()),
        kinematics={q_final[plain_q[roll]]: u_final[plain(roll.diff(t))],
                    q_final[plain_q[steer]]: u_final[plain(steer.diff(t))]})

    def time_derivative(expr: sm.Expr) -> sm.Expr:
        """d/dt of an expression linear in the final variables (constant coefficients)."""
        chain = dict(perturbation.kinematics)
        chain.update({u: a_final[key] for key, u in u_final.items()})
        return sum((expr.diff(x) * dx for x, dx in chain.items()), sm.S.Zero)

    configuration_nominal = {p: 0 for p in plain_q.values()}
    configuration = _Expansion(configuration_nominal, dict(q_final))

    # --- Holonomic constraint: the front contact stays on the ground. At first order its
    # height must not depend on roll or steer, which is what lets the pitch be dropped.
    height = plain(system.front_contact_position.dot(A.z))
    if sm.simplify(configuration.zeroth(height)) != 0 or sm.simplify(configuration.first_order(height)) != 0:
        raise DerivationError("front contact leaves the ground at first order")

    # --- Nonholonomic constraints: C(q) u_dep + D(q) u_ind = 0.
    constraints = [plain(c) for c in system.constraints]
    C = sm.Matrix([[sm.diff(row, s) for s in dependent] for row in constraints])
    D = sm.Matrix([[sm.diff(row, s) for s in independent] for row in constraints])
    # First-order parts in the plain coordinates, so that T stays a function of them.
    in_plain = _Expansion(configuration_nominal, {p: p for p in plain_q.values()})
    C0 = C.xreplace(configuration_nominal).applyfunc(sm.simplify)
    D0 = D.xreplace(configuration_nominal).applyfunc(sm.simplify)
    C1 = C.applyfunc(in_plain.first_order)
    D1 = D.applyfunc(in_plain.first_order)
    C0_inv = C0.inv().applyfunc(sm.simplify)
    T0 = (-C0_inv * D0).applyfunc(sm.simplify)
    T1 = (-C0_inv * (D1 + C1 * T0)).applyfunc(sm.expand)
    transfer = T0 + T1  # dependent speeds per independent speed, to first order in q

    nominal_independent = sm.Matrix([nominal_speeds.get(s, 0) for s in system.independent_speeds])
    first_independent = sm.Matrix([u_final.get(s, 0) for s in independent])
    to_final = {p: q_final.get(p, 0) for p in plain_q.values()}
    dependent_nominal = [sm.simplify(x) for x in T0 * nominal_independent]
    dependent_first = [sm.expand(x) for x in T0 * first_independent + T1.xreplace(to_final) * nominal_independent]
    pitch_rate = dependent.index(plain(pitch.diff(t)))
    if dependent_nominal[pitch_rate] != 0 or sm.simplify(dependent_first[pitch_rate]) != 0:
        raise DerivationError("pitch rate has a zeroth- or first-order part")

    # --- The nominal motion and the first-order part of every plain variable.
    nominal: dict = dict(configuration_nominal)
    first: dict = dict(q_final)
    for s, value, final in zip(independent, nominal_independent, first_independent, strict=True):
        nominal[s] = value
        first[s] = final
    for s, value, part in zip(dependent, dependent_nominal, dependent_first, strict=True):
        nominal[s] = value
        first[s] = part
    for speed, acceleration in rate_of.items():
        # Steady nominal motion: accelerations vanish; first-order parts by the chain rule.
        nominal[acceleration] = 0
        first[acceleration] = time_derivative(first.get(speed, 0))
    for symbol in first_order_symbols:
        nominal[symbol] = 0
        first[symbol] = symbol
    expansion = _Expansion(nominal, first)

    def partial(vector_components: list[sm.Expr], r: int) -> list[sm.Expr]:
        """Nonholonomic partial velocity w.r.t. independent speed r (exact up to T's order)."""
        return [sm.diff(c, independent[r])
                + sum((sm.diff(c, dependent[d]) * transfer[d, r] for d in range(len(dependent))), sm.S.Zero)
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
    for r in in_equations:
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
            force = components(load.vector)
            work = sum((f * m for f, m in zip(force, partial(motion, r), strict=True)), sm.S.Zero)
            if sm.simplify(expansion.zeroth(work)) != 0:
                raise DerivationError("a load does work in the nominal motion")
            generalized += expansion.first_order(work)
        equations.append(sm.expand(generalized))

    def expand_quantity(expr: sm.Expr) -> tuple[sm.Expr, sm.Expr]:
        """Zeroth and first-order parts of a quantity given in dynamic symbols."""
        plain_expr = plain(expr)
        return sm.simplify(expansion.zeroth(plain_expr)), sm.expand(expansion.first_order(plain_expr))

    return KaneLinearization(equations, perturbation, expand_quantity)


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


def linearize(system: BicycleSystem, rear_radius: sm.Symbol) -> LinearEquations:
    """Linearized equations of the Whipple-type ``system`` (knife-edge wheels) at speed v."""
    result = kane_linearize(system, {spin_rear.diff(): -v / rear_radius},
                            (roll.diff(), steer.diff()), system.inputs)
    return _coefficient_matrices(result, system.inputs)


def _coefficient_matrices(result: KaneLinearization, inputs: tuple[sm.Symbol, ...]) -> LinearEquations:
    """Split ``0 = B f - (M q'' + (v C1 + D) q' + (K0 + v^2 K2) q)`` into its matrices."""
    equations = result.equations
    variables = result.perturbation

    def coefficient(expr: sm.Expr, variable: sm.Symbol) -> sm.Expr:
        return sm.expand(expr.diff(variable))

    M = sm.Matrix(2, 2, lambda i, j: -coefficient(equations[i], variables.accelerations[j]))
    rate = sm.Matrix(2, 2, lambda i, j: -coefficient(equations[i], variables.speeds[j]))
    stiffness = sm.Matrix(2, 2, lambda i, j: -coefficient(equations[i], variables.coordinates[j]))
    B = sm.Matrix(2, len(inputs), lambda i, j: coefficient(equations[i], inputs[j]))
    D = rate.xreplace({v: 0})
    C1 = ((rate - D) / v).applyfunc(sm.expand)
    K0 = stiffness.xreplace({v: 0})
    K2 = ((stiffness - K0) / v**2).applyfunc(sm.expand)
    for name, matrix in (("C1", C1), ("K2", K2), ("M", M), ("B", B)):
        if any(entry.has(v) for entry in matrix):
            raise DerivationError(f"{name} depends on the speed: not of the benchmark form")
    return LinearEquations(M=M, C1=C1, D=D, K0=K0, K2=K2, B=B, inputs=inputs)
