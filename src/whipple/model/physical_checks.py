"""Physical checks of benchmark parameter sets that go beyond signs and finiteness.

Used by :func:`whipple.model.parameter_set.validate`, which collects their findings:

- **Magnitudes.** A value beyond what any bicycle-like vehicle has (:data:`LIMITS`) is refused:
  it is a typing or unit error, and products of such values (``mB = 1e300``) overflow in the
  equations. A value beyond what bicycles usually have (:data:`PLAUSIBLE`) is a warning.
- **Inertia of each body.** The moments that enter the linear equations (the principal moments
  in the xz plane, and a wheel's spin moment) must not be negative: zero is a point mass, a
  legitimate limit. The triangle inequality of principal moments (each at most the sum of the
  other two) holds for every rigid body, but measured inertias break it by a few percent
  within their measurement error; a violation is a warning stating its size, how it compares
  with the stated uncertainties, and whether the largest moment enters the linear equations.
- **Placement.** A frame's mass centre below the ground, or a massless body with inertia, is
  a warning: the equations take them, but no bicycle has them. All four bodies massless is
  refused: without weight there is nothing to balance (the gravity terms vanish).
- **Radii of gyration.** A body's largest radius of gyration about its mass centre,
  sqrt(largest principal moment / mass), cannot exceed its size: the squared distance of a
  point from an axis through the mass centre is the sum of its squared offsets along two
  perpendicular directions, and the mean of each is a variance, at most D^2/4 for a body of
  diameter D (Popoviciu's inequality); so k <= D / sqrt(2). Beyond :data:`LIMITS`' length
  (a 100 m vehicle) that is refused, beyond :data:`PLAUSIBLE`'s (5 m) it is a warning: a light
  body with a large inertia (``mB = 1e-3`` with ``IBxx = 9.2``: 96 m) is a typing error.
- **Mass matrix.** Where a body has no inertia in the xz plane (point masses), the bicycle as
  a whole may still have none to roll or to steer; then M is singular and the model
  meaningless.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from whipple.generated import whipple_numpy
from whipple.model.bodies import fold_point_wheels

#: Largest magnitude accepted, by unit: no bicycle-like vehicle comes near (a 100 t vehicle,
#: 100 m long); beyond these a value is a typing or unit error.
LIMITS = {"kg": 1e5, "m": 100.0, "kg m^2": 1e6, "m/s^2": 1e3}
#: Largest magnitude of a bicycle with rider and load, by unit; beyond it a warning.
PLAUSIBLE = {"kg": 500.0, "m": 5.0, "kg m^2": 500.0, "m/s^2": 30.0}
#: Each body's mass key and inertia keys: xx, yy, zz, xz (wheels: zz = xx, no product of inertia).
BODIES: tuple[tuple[str, str, str, str, str, str | None], ...] = (
    ("rear wheel", "mR", "IRxx", "IRyy", "IRxx", None),
    ("rear frame", "mB", "IBxx", "IByy", "IBzz", "IBxz"),
    ("front frame", "mH", "IHxx", "IHyy", "IHzz", "IHxz"),
    ("front wheel", "mF", "IFxx", "IFyy", "IFxx", None),
)
#: Fastest forward speed [m/s] any command analyses, simulates or reads from a run: about 3000
#: times the speed of sound, where v^2 K2 already swamps everything else in A(v).
MAX_SPEED = 1e6
#: Shortest wheelbase [m] accepted: a toy bicycle has 0.2 m; below this a unit or typing error,
#: and the equations, which divide by w, overflow (w = 1e-300).
MIN_WHEELBASE = 1e-3
#: Gravity below this [m/s^2] is a warning (the Moon has 1.6).
LOW_GRAVITY = 1.0
#: A triangle-inequality excess up to this many standard deviations is within measurement error.
WITHIN_SIGMAS = 2.0

Array = NDArray[np.float64]


def magnitude_findings(values: Mapping[str, Array], units: Mapping[str, str]
                       ) -> list[tuple[NDArray[np.bool_], str, bool]]:
    """(bad, message, is_warning) for values beyond :data:`LIMITS` or :data:`PLAUSIBLE`."""
    findings = []
    for unit, limit in LIMITS.items():
        names = [name for name in values if units.get(name) == unit]
        # The usual case, all plausible, tested without broadcasting the scalars of a batch
        # (NaN, reported elsewhere, is neither over nor unusual).
        if not any(np.any(np.abs(values[name]) > PLAUSIBLE[unit]) for name in names):
            continue
        size = np.abs(np.stack(np.broadcast_arrays(*(values[name] for name in names))))
        over, unusual = size > limit, (size > PLAUSIBLE[unit]) & (size <= limit)
        for k, name in enumerate(names):
            value = values[name]
            shown = f"{name} = {float(value):.6g} {unit}" if value.ndim == 0 else name
            findings.append((over[k], f"{shown} is beyond {limit:g} {unit}: not a bicycle (a unit or "
                                      "typing error?)", False))
            findings.append((unusual[k], f"{shown} is unusually large for a bicycle (above "
                                         f"{PLAUSIBLE[unit]:g} {unit})", True))
    if "w" in values:
        w = values["w"]
        shown = f"w = {float(w):.6g} m" if w.ndim == 0 else "w"
        findings.append(((w > 0) & (w < MIN_WHEELBASE), f"{shown} is below {MIN_WHEELBASE:g} m: not a bicycle (a unit "
                                                        "or typing error?)", False))
    if "g" in values:
        g = values["g"]
        shown = f"g = {float(g):.6g} m/s^2" if g.ndim == 0 else "g"
        findings.append(((g > 0) & (g < LOW_GRAVITY),
                         f"{shown} is unusually small (below {LOW_GRAVITY:g} m/s^2)", True))
    return findings


#: The frames' mass-centre heights (z points down, so a positive z is below the ground).
_HEIGHTS = {"zB": "rear frame", "zH": "front frame"}


def placement_findings(values: Mapping[str, Array]) -> list[tuple[NDArray[np.bool_], str, bool]]:
    """(bad, message, is_warning) for what no rigid bicycle has, but the equations still take.

    A frame's mass centre below the ground, and a massless body with inertia, are warnings: the
    linear equations are defined for them (and a fitted or teaching set may have them), but they
    are almost always a sign error or a value in the wrong field. A bicycle whose four masses are
    all zero is refused.
    """
    findings = []
    for name, frame in _HEIGHTS.items():
        if name in values:
            height = values[name]
            shown = f"{name} = {float(height):.6g} m" if height.ndim == 0 else name
            findings.append((height > 0, f"{shown} puts the {frame}'s mass centre below the ground "
                                         "(z points down: a sign error?)", True))
    for _, mass, xx, yy, zz, xz in BODIES:
        present = [key for key in dict.fromkeys((xx, yy, zz, xz)) if key is not None and key in values]
        if mass in values and present:
            inertia = np.any(np.stack(np.broadcast_arrays(*(values[key] for key in present))) != 0, axis=0)
            findings.append(((values[mass] == 0) & inertia, f"{mass} = 0 with nonzero inertia "
                             f"({', '.join(present)}): a body without mass has none", True))
    masses = [body[1] for body in BODIES]
    if all(mass in values for mass in masses):
        total = sum(values[mass] for mass in masses)
        findings.append((np.asarray(total == 0), f"{' + '.join(masses)} = 0 kg: a bicycle without mass has no "
                         "weight to balance", False))
    return findings


def gyration_findings(values: Mapping[str, Array]) -> list[tuple[NDArray[np.bool_], str, bool]]:
    """(bad, message, is_warning) for bodies whose radius of gyration no part of their size has.

    See the module notes: a body of diameter D has radii of gyration of at most D / sqrt(2)
    about its mass centre; D is bounded by the lengths of :data:`LIMITS` (refused) and
    :data:`PLAUSIBLE` (a warning).
    """
    findings = []
    for label, mass, xx, yy, zz, xz in BODIES:
        keys = [key for key in (mass, xx, yy, zz) if key in values]
        if len(keys) < 4:
            continue
        product = values[xz] if xz is not None and xz in values else np.zeros(())
        largest = principal_moments(values[xx], values[yy], values[zz], product).max(axis=0)
        m = values[mass]
        with np.errstate(divide="ignore", invalid="ignore"):
            radius = np.sqrt(np.where(m > 0, largest / np.where(m > 0, m, 1.0), 0.0))
        for limit, warning in ((LIMITS["m"], False), (PLAUSIBLE["m"], True)):
            bound = limit / math.sqrt(2)
            bad = radius > bound
            if warning:
                bad = bad & (radius <= LIMITS["m"] / math.sqrt(2))
            shown = (f"a radius of gyration of {float(radius):.3g} m (largest moment {float(largest):.6g} kg m^2 "
                     f"with {mass} = {float(m):.6g} kg)" if radius.ndim == 0 else "a radius of gyration")
            findings.append((bad, f"{label}: {shown} above {bound:.3g} m, which only a body over {limit:g} m "
                                  + ("across has: not a bicycle (a unit or typing error?)" if not warning
                                     else "across has: unusual for a bicycle"), warning))
    return findings


def uncertainty_findings(uncertainty: Mapping[str, float], units: Mapping[str, str]) -> list[tuple[bool, str]]:
    """(bad, message) for standard deviations of unknown parameters, negative, or beyond :data:`LIMITS`.

    An angle's standard deviation may not exceed pi; beyond the limits the propagated
    uncertainty of a critical speed would overflow.
    """
    findings = []
    for name, sigma in uncertainty.items():
        unit = units.get(name)
        findings.append((unit is None, f"uncertainty of unknown parameter {name!r}"))
        findings.append((not sigma >= 0 or math.isinf(sigma), f"uncertainty of {name} = {sigma:.6g} must be finite "
                                                               "and >= 0"))
        limit = math.pi if unit == "rad" else LIMITS.get(unit or "")
        if limit is not None and math.isfinite(sigma) and sigma > limit:
            findings.append((True, f"uncertainty of {name} = {sigma:.6g} {unit} is beyond {limit:.4g} {unit}: "
                                   "not a bicycle's (a unit or typing error?)"))
    return findings


def principal_moments(xx: Array, yy: Array, zz: Array, xz: Array) -> Array:
    """Principal moments [kg m^2], shape (3, ...): the two in the xz plane (larger first), then yy."""
    mean, radius = (xx + zz) / 2, np.hypot((xx - zz) / 2, xz)
    return np.stack(np.broadcast_arrays(mean + radius, mean - radius, yy))


def triangle_excess(xx: Array, yy: Array, zz: Array, xz: Array) -> Array:
    """How far the largest principal moment exceeds the sum of the other two [kg m^2]."""
    moments = principal_moments(xx, yy, zz, xz)
    return 2 * moments.max(axis=0) - moments.sum(axis=0)


def excess_std(values: Mapping[str, float], keys: tuple[str, str, str, str],
               uncertainty: Mapping[str, float]) -> float | None:
    """Return the standard deviation [kg m^2] of the triangle excess from independent uncertainties.

    Each parameter is moved by one standard deviation either way (a secant, robust at the
    kink where the largest moment changes); None when no key has an uncertainty.
    """
    sigmas = {key: uncertainty.get(key, 0.0) for key in keys}
    if not any(sigmas.values()):
        return None

    def excess(changed: Mapping[str, float]) -> float:
        point = [np.asarray(changed[key], dtype=float) for key in keys]
        return float(triangle_excess(*point))

    total = 0.0
    for key, sigma in sigmas.items():
        if sigma:
            up, down = dict(values), dict(values)
            up[key] += sigma
            down[key] -= sigma
            total += ((excess(up) - excess(down)) / 2) ** 2
    return math.sqrt(total)


def triangle_message(text: str, excess: float, moments: Array, std: float | None, remedy: str) -> str:
    """One line describing a triangle-inequality violation of one body (see the module notes).

    `remedy` says which moment could absorb the violation and whether it enters the equations.
    """
    share = excess / float(moments.sum())
    shown = ", ".join(f"{m:.6g}" for m in moments)
    if std is None:
        error = "no uncertainty stated"
    else:
        sigmas = excess / std if std > 0 else math.inf
        verdict = ("within measurement error" if sigmas <= WITHIN_SIGMAS
                   else "more than the stated uncertainties explain")
        error = f"{sigmas:.1f} standard deviations of the stated uncertainties ({std:.2g} kg m^2): {verdict}"
    return (f"{text} by {excess:.3g} kg m^2 ({share:.2%} of their sum; principal moments {shown}); "
            f"{error}; {remedy}")


def triangle_remedy(yy: str, yy_is_largest: bool, excess: float, wheel: bool) -> str:
    """Which moment would satisfy the inequality, and whether it matters to the linear model."""
    if wheel:
        return "both of a wheel's moments enter the linear equations"
    change = "smaller" if yy_is_largest else "larger"
    return f"{yy} {excess:.3g} kg m^2 {change} would satisfy it, and {yy} does not enter the linear equations"


def singular_mass_matrix(parameters: Mapping[str, Array]) -> NDArray[np.bool_]:
    """Where the mass matrix M of the linear model is not positive definite.

    Parameters
    ----------
    parameters : mapping of str to ndarray
        The benchmark parameters the generated code needs (arrays that broadcast).
    """
    folded = fold_point_wheels(parameters)
    M = whipple_numpy.matrices(*(folded[name] for name in whipple_numpy.PARAMETERS))[0]
    m00, m11 = M[..., 0, 0], M[..., 1, 1]
    det = m00 * m11 - M[..., 0, 1] * M[..., 1, 0]
    with np.errstate(invalid="ignore"):
        return ~((m00 > 0) & (m11 > 0) & (det > 1e-12 * np.abs(m00 * m11)))


def tyre_point_wheel_problem(point: Sequence[str]) -> str:
    """Return the problem of point wheels (``rR``, ``rF`` of radius zero) under the tyre model."""
    return f"tyre compliance needs wheels of positive radius ({', '.join(point)} = 0)"
