"""The catalogue of derived models: what ``whipple regenerate`` emits.

- ``whipple``: the benchmark Whipple bicycle in its 24 parameters that enter the linear model.
- ``whipple_extended``: the same with payload point masses on the rear and on the front frame,
  extra (rigid) steer inertia, reflected steer inertia of a geared rotor and viscous steer
  damping, derived by adding those bodies and loads to the system
  (not by editing matrices), so that the extensions pass through the same mechanics.
- ``tyre``: the extended bicycle with lateral tyre compliance (see ``tyre.py``), whose state
  adds the lateral speed, the yaw rate and the two tyre forces.
- ``whipple_nonlinear``: the pieces of the nonlinear equations of the benchmark Whipple bicycle
  (see ``nonlinear.py``), as functions of the parameters and the state, for numerical solution.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import sympy as sm

from .linearize import LinearEquations, linearize
from .nonlinear import derive_nonlinear_equations
from .symbols import (
    BENCHMARK_PARAMETERS,
    EXTENSION_PARAMETERS,
    PITCH_INERTIA_PARAMETERS,
    PITCH_INERTIAS,
    TYRE_PARAMETERS,
    parameter_symbols,
)
from .tidy import tidy
from .tyre import derive_tyre_equations
from .whipple import (
    BicycleSystem,
    add_front_payload,
    add_payload,
    add_reflected_steer_inertia,
    add_steer_damping,
    add_steer_inertia,
    build_bicycle,
)

# IByy and IHyy are carried through the dynamics and must drop out (checked below).
_PITCH_INERTIAS = PITCH_INERTIAS


@dataclass(frozen=True)
class DerivedModel:
    """A model's name, description, parameter order, and its matrices by output name."""

    name: str
    description: str
    parameters: tuple[str, ...]
    matrices: dict[str, sm.Matrix]
    equation: str

    @property
    def outputs(self) -> tuple[str, ...]:
        return tuple(self.matrices)


@dataclass(frozen=True)
class DerivedFunction:
    """One emitted function: its arguments beyond the parameters, and its outputs.

    Each output is ``(expression, description)``; the expression is a scalar, a column vector
    (emitted as an array with one trailing axis) or a matrix (two trailing axes).
    """

    name: str
    summary: str
    variables: tuple[str, ...]
    outputs: dict[str, tuple[sm.Expr | sm.Matrix, str]]


@dataclass(frozen=True)
class DerivedFunctions:
    """A model emitted as several functions of the parameters and of state variables."""

    name: str
    description: str
    parameters: tuple[str, ...]
    functions: tuple[DerivedFunction, ...]
    equation: str


_BENCHMARK_FORM = "M q'' + (v C1 + D) q' + (K0 + v**2 K2) q = f, q = [roll, steer], f = [roll torque, steer torque]"


def _tidy_equations(equations: LinearEquations, lam: sm.Symbol) -> LinearEquations:
    def clean(matrix: sm.Matrix) -> sm.Matrix:
        return matrix.applyfunc(lambda entry: tidy(entry, lam))

    return LinearEquations(
        M=clean(equations.M), C1=clean(equations.C1), D=clean(equations.D),
        K0=clean(equations.K0), K2=clean(equations.K2), B=clean(equations.B),
        inputs=equations.inputs,
    )


def _check_free_symbols(equations: LinearEquations, allowed: tuple[str, ...], name: str) -> None:
    used = set()
    for matrix in (equations.M, equations.C1, equations.D, equations.K0, equations.K2):
        used |= {str(symbol) for symbol in matrix.free_symbols}
    unexpected = used - set(allowed)
    if unexpected:
        raise AssertionError(f"model {name} depends on unexpected symbols {sorted(unexpected)}")


def derive_whipple() -> DerivedModel:
    """The benchmark Whipple bicycle."""
    p = parameter_symbols(list(BENCHMARK_PARAMETERS) + list(_PITCH_INERTIAS))
    equations = _tidy_equations(linearize(build_bicycle(p), p["rR"]), p["lam"])
    names = tuple(BENCHMARK_PARAMETERS)
    _check_free_symbols(equations, names, "whipple")
    if equations.B != sm.eye(2):
        raise AssertionError("the benchmark inputs are not dual to roll and steer")
    return DerivedModel("whipple", "Whipple bicycle, Meijaard et al. (2007) parameters", names,
                        {"M": equations.M, "C1": equations.C1, "K0": equations.K0, "K2": equations.K2},
                        _BENCHMARK_FORM + "; K0 includes gravity")


def _add_extensions(system: BicycleSystem, p: dict[str, sm.Symbol]) -> None:
    """Every extension that keeps the two degrees of freedom, as bodies and loads."""
    add_payload(system, p)
    add_front_payload(system, p)
    add_steer_inertia(system, p)
    add_reflected_steer_inertia(system, p)
    add_steer_damping(system, p["steer_damping"])


def _check_reflected_inertia(equations: LinearEquations, p: dict[str, sm.Symbol]) -> None:
    """The reflected steer inertia must enter M[steer, steer] alone, with coefficient one."""
    J = p["reflected_steer_inertia"]
    for name in ("M", "C1", "D", "K0", "K2"):
        matrix = getattr(equations, name)
        change = (matrix - matrix.xreplace({J: 0})).applyfunc(sm.simplify)
        expected = sm.Matrix([[0, 0], [0, J]]) if name == "M" else sm.zeros(2, 2)
        if change != expected:
            raise AssertionError(f"the reflected steer inertia changes {name} by {change}")


def derive_whipple_extended() -> DerivedModel:
    """The Whipple bicycle with payloads, steer inertias and steer damping."""
    p = parameter_symbols(list(BENCHMARK_PARAMETERS) + list(_PITCH_INERTIAS)
                          + list(EXTENSION_PARAMETERS))
    system = build_bicycle(p)
    _add_extensions(system, p)
    equations = _tidy_equations(linearize(system, p["rR"]), p["lam"])
    names = tuple(BENCHMARK_PARAMETERS) + tuple(EXTENSION_PARAMETERS)
    _check_free_symbols(equations, names, "whipple_extended")
    _check_reflected_inertia(equations, p)
    return DerivedModel(
        "whipple_extended",
        "Whipple bicycle with rear- and front-frame payload point masses, extra steer inertia, "
        "reflected steer inertia and steer damping",
        names, {"M": equations.M, "C1": equations.C1, "D": equations.D, "K0": equations.K0, "K2": equations.K2},
        _BENCHMARK_FORM + "; K0 includes gravity")


def derive_tyre() -> DerivedModel:
    """The bicycle with lateral tyre compliance (and the other extensions), descriptor form."""
    p = parameter_symbols(list(BENCHMARK_PARAMETERS) + list(_PITCH_INERTIAS)
                          + list(EXTENSION_PARAMETERS) + list(TYRE_PARAMETERS))
    system = build_bicycle(p, lateral_slip=True)
    _add_extensions(system, p)
    equations = derive_tyre_equations(system, p)
    names = tuple(BENCHMARK_PARAMETERS) + tuple(EXTENSION_PARAMETERS) + tuple(TYRE_PARAMETERS)
    matrices = {"E": equations.E}
    matrices.update({f"A{k}": matrix for k, matrix in enumerate(equations.A)})
    matrices["B"] = equations.B
    matrices = {key: matrix.applyfunc(lambda entry: tidy(entry, p["lam"])) for key, matrix in matrices.items()}
    model = DerivedModel(
        "tyre", "Bicycle with linear lateral tyre forces and relaxation (tyre compliance)", names, matrices,
        "E x' = (A0 + v A1 + ...) x + B f, x = [" + ", ".join(equations.states) + "], "
        "f = [roll torque, steer torque]")
    used = set().union(*(matrix.free_symbols for matrix in matrices.values()))
    unexpected = {str(s) for s in used} - set(names)
    if unexpected:
        raise AssertionError(f"model tyre depends on unexpected symbols {sorted(unexpected)}")
    return model


# The benchmark's 26 parameters in the order of its Table 1: IByy after IBxx, IHyy after IHxx.
_TABLE_ORDER = tuple(name for base in BENCHMARK_PARAMETERS
                     for name in ((base, base[:2] + "yy") if base in ("IBxx", "IHxx") else (base,)))
if set(_TABLE_ORDER) != set(BENCHMARK_PARAMETERS) | set(PITCH_INERTIA_PARAMETERS):
    raise AssertionError("the nonlinear model's parameters are not the benchmark's 26")
_ANGLES = ("roll", "pitch", "steer")
_RATES = ("yaw_rate", "roll_rate", "pitch_rate", "steer_rate", "rear_wheel_rate", "front_wheel_rate")

_NONLINEAR_FORM = (
    "M u' = F + C^T f, C u' = b (the front contact's velocity C u vanishes; f is the contact force "
    "on the front wheel, yaw-frame components [N]), u = [" + ", ".join(_RATES) + "]; the pitch solves "
    "h(roll, pitch, steer) = 0; the rear contact moves at (x', y') = rear_contact_velocity"
)


def derive_whipple_nonlinear() -> DerivedFunctions:
    """The nonlinear Whipple bicycle: mass matrix, forcing, constraints, energies."""
    p = parameter_symbols(_TABLE_ORDER)
    equations = derive_nonlinear_equations(build_bicycle(p), p["g"])
    functions = (
        DerivedFunction("contact_height", "The holonomic constraint h = 0 that fixes the pitch.", _ANGLES, {
            "height": (equations.contact_height,
                       "z of the front contact relative to the rear contact [m], z down (0 on the ground)"),
            "height_gradient": (equations.contact_height_gradient,
                                "dh/d(roll, pitch, steer) [m/rad]"),
        }),
        DerivedFunction("constraints", "The front contact's velocity C u (yaw-frame components).", _ANGLES, {
            "C": (equations.constraint_matrix, "velocity of the front contact per rate in u [m/rad]"),
        }),
        DerivedFunction("dynamics", "Kane's equations of the unconstrained speeds, and the constraint bias.",
                        _ANGLES + _RATES + ("roll_torque", "steer_torque"), {
            "M": (equations.mass_matrix, "mass matrix [kg m^2]"),
            "F": (equations.forcing, "generalized active minus velocity-dependent inertia forces [N m]"),
            "b": (equations.constraint_bias, "C u' = b along the motion [m/s^2]"),
        }),
        DerivedFunction("energy", "Kinetic and potential energy.", _ANGLES + _RATES, {
            "kinetic": (equations.kinetic_energy, "kinetic energy [J]"),
            "potential": (equations.potential_energy,
                          "potential energy of gravity, zero with the mass centres at ground level [J]"),
        }),
        DerivedFunction("rear_contact_velocity", "Velocity of the rear contact point along the ground.",
                        ("yaw", "pitch_rate", "rear_wheel_rate"), {
            "velocity": (equations.rear_contact_velocity, "(x', y') in the ground frame [m/s]"),
        }),
    )
    for function in functions:
        allowed = set(_TABLE_ORDER) | set(function.variables)
        for expression, _ in function.outputs.values():
            unexpected = {str(s) for s in expression.free_symbols} - allowed
            if unexpected:
                raise AssertionError(f"{function.name} depends on unexpected symbols {sorted(unexpected)}")
    return DerivedFunctions("whipple_nonlinear", "Whipple bicycle, nonlinear equations, Meijaard et al. (2007) "
                            "parameters", _TABLE_ORDER, functions, _NONLINEAR_FORM)


MODELS: dict[str, Callable[[], DerivedModel | DerivedFunctions]] = {
    "whipple": derive_whipple,
    "whipple_extended": derive_whipple_extended,
    "tyre": derive_tyre,
    "whipple_nonlinear": derive_whipple_nonlinear,
}
