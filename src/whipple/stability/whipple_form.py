"""Weave and capsize speeds of models of the Whipple form in closed form, for sweeps.

A model of the *Whipple form* has 4 states ``[q, q']`` and
``q'' = -(K0 + v^2 K2) q - v C1 q`` (the mass matrix folded into ``K0, K2, C1``): the Whipple
model and its payload and inertia extensions, without speed-independent damping or a
controller. Its characteristic polynomial ``s^4 + a1 s^3 + a2 s^2 + a3 s + a4`` has, with
``u = v^2`` and ``m(X, Y) = det(X + Y) - det X - det Y``::

    a1 = v c,                   c  = tr C1
    a2 = k0 + u e2,             k0 = tr K0,        e2 = tr K2 + det C1
    a3 = v (d1 + u d3),         d1 = m(C1, K0),    d3 = m(C1, K2)
    a4 = f0 + u f2 + u^2 f4,    f0 = det K0,       f2 = m(K0, K2),  f4 = det K2

so the Hopf condition ``a1 a2 a3 - a3^2 - a1^2 a4`` is ``u`` times a quadratic in u and the real
condition ``a4`` is a quadratic in u. Both are solved by the cancellation-free quadratic
formula; a Hopf root is a crossing where ``w^2 = a3 / a1 > 0`` (else two real eigenvalues of
opposite sign), and stability between the roots is the Routh-Hurwitz test at the midpoints, as
in :mod:`whipple.stability.critical`, whose general solver this reproduces for these models
without the per-root eigen-analysis, directions and mode labels.

A sweep needs those only where the main stable range (the longest) does not settle the weave
and capsize speeds: :func:`whipple_form_table` reports which models it settled, and the
general solver does the rest: models whose main range does not start at a Hopf crossing (or end
at a real one) while such a crossing lies in the interval (its label would decide), near-double
roots (a possible touch), coincident roots, and degenerate conditions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from whipple.model.first_order import NUMPY_OPS
from whipple.stability import modes
from whipple.stability.cubic import cubic_roots
from whipple.stability.polynomial import det_2x2, hurwitz_stable, is_second_order, mixed_2x2
from whipple.stability.root_spectrum import null_roll_share

#: Roots of a condition closer than this (relative, through the discriminant: ``|disc| <=
#: DOUBLE_ROOT * b^2``, roots within about 1e-4 of each other) may be one double root, i.e. a
#: touch: left to the general solver, which decides touches on the eigenvalues.
DOUBLE_ROOT = 1e-8
#: Crossings of the two conditions closer than this [m/s, relative to 1 + v] are left to the
#: general solver (one speed, two kinds).
COINCIDENT = 1e-4
#: ``|w^2|`` [1/s^2] at a Hopf root below which the pair is too close to the real axis for the
#: closed-form test (the general solver's threshold is ``w ~ 1e-6`` 1/s).
WEAK_PAIR = 1e-8
#: Hurwitz minors outside these magnitudes may have lost their sign to underflow or overflow.
_TINY, _HUGE = 1e-250, 1e250


@dataclass(frozen=True)
class WhippleFormTable:
    """Speeds of the models the closed form settled (see the module docstring).

    Attributes
    ----------
    settled : ndarray of bool, shape (N,)
        Models whose speeds below are final; the others need the general solver.
    weave_speed, capsize_speed : ndarray, shape (N,)
        As :class:`whipple.stability.critical.CriticalSpeedTable` [m/s]; NaN for none (and
        for unsettled models).
    range_model : ndarray of int, shape (R,)
        Model of each stable range (settled models only), ascending.
    range_low, range_high : ndarray, shape (R,)
        Ends [m/s] of each stable range, by increasing speed within a model.
    """

    settled: NDArray[np.bool_]
    weave_speed: NDArray[np.float64]
    capsize_speed: NDArray[np.float64]
    range_model: NDArray[np.intp]
    range_low: NDArray[np.float64]
    range_high: NDArray[np.float64]


def is_whipple_form(coefficients: NDArray[np.float64]) -> bool:
    """Return True if every model of A's coefficients (N, T, 4, 4) has the Whipple form."""
    if coefficients.ndim != 4 or coefficients.shape[1] > 3 or not is_second_order(coefficients):
        return False
    lower = coefficients[:, :, 2:, :]
    # No damping at v^0 or v^2, no stiffness at v^1.
    return bool(not np.any(lower[:, 0, :, 2:]) and not np.any(lower[:, 1:2, :, :2])
                and not np.any(lower[:, 2:3, :, 2:]))


def _quadratic_roots(p0: NDArray[np.float64], p1: NDArray[np.float64], p2: NDArray[np.float64]
                     ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Real roots (N, 2) of ``p0 + p1 u + p2 u^2`` (NaN for none) and whether to defer.

    Deferred: a discriminant within DOUBLE_ROOT of zero (a possible double root) or a
    polynomial that vanishes identically.
    """
    disc = p1 * p1 - 4.0 * p2 * p0
    q = -0.5 * (p1 + np.copysign(np.sqrt(np.maximum(disc, 0.0)), p1))
    with np.errstate(divide="ignore", invalid="ignore"):
        roots = np.stack([q / p2, p0 / q], axis=-1)
    roots[disc < 0] = np.nan
    roots[~np.isfinite(roots)] = np.nan
    defer = (np.abs(disc) <= DOUBLE_ROOT * p1 * p1) & (p2 != 0)
    defer |= (p0 == 0) & (p1 == 0) & (p2 == 0)
    return roots, defer


def _speeds(v: NDArray[np.float64], low: float, high: float
            ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Speeds v [m/s] strictly inside (low, high) (NaN otherwise), and which are in [low, high]."""
    with np.errstate(invalid="ignore"):
        within = (v >= low) & (v <= high)
        inside = (v > low) & (v < high)
    return np.where(inside, v, np.nan), within


@dataclass(frozen=True)
class _Invariants:
    """Coefficients of the characteristic polynomial in u = v^2 (module docstring), per model."""

    C1: NDArray[np.float64]
    K0: NDArray[np.float64]
    K2: NDArray[np.float64]
    c: NDArray[np.float64]
    k0: NDArray[np.float64]
    e2: NDArray[np.float64]
    d1: NDArray[np.float64]
    d3: NDArray[np.float64]
    f0: NDArray[np.float64]
    f2: NDArray[np.float64]
    f4: NDArray[np.float64]

    @classmethod
    def of(cls, coefficients: NDArray[np.float64]) -> _Invariants:
        """From A's coefficients (N, T, 4, 4)."""
        count = coefficients.shape[0]
        K0 = -coefficients[:, 0, 2:, :2]
        C1 = -coefficients[:, 1, 2:, 2:] if coefficients.shape[1] > 1 else np.zeros((count, 2, 2))
        K2 = -coefficients[:, 2, 2:, :2] if coefficients.shape[1] > 2 else np.zeros((count, 2, 2))
        return cls.folded(C1, K0, K2)

    @classmethod
    def of_matrices(cls, M: NDArray[np.float64], C1: NDArray[np.float64], K0: NDArray[np.float64],
                    K2: NDArray[np.float64]) -> _Invariants:
        """From the second-order matrices (N, 2, 2), folded by M as the first-order model folds them."""
        folded = NUMPY_OPS.solve(M, np.concatenate([C1, K0, K2], axis=-1))
        return cls.folded(folded[..., :2], folded[..., 2:4], folded[..., 4:])

    @classmethod
    def folded(cls, C1: NDArray[np.float64], K0: NDArray[np.float64], K2: NDArray[np.float64]) -> _Invariants:
        """From ``M^-1 C1, M^-1 K0, M^-1 K2`` (N, 2, 2)."""
        return cls(C1, K0, K2, C1[:, 0, 0] + C1[:, 1, 1], K0[:, 0, 0] + K0[:, 1, 1],
                   K2[:, 0, 0] + K2[:, 1, 1] + det_2x2(C1), mixed_2x2(C1, K0), mixed_2x2(C1, K2), det_2x2(K0),
                   mixed_2x2(K0, K2), det_2x2(K2))

    def select(self, rows: NDArray[np.intp]) -> _Invariants:
        return _Invariants(*(getattr(self, name)[rows] for name in self.__dataclass_fields__))

    def characteristic(self, v: NDArray[np.float64], rows: NDArray[np.intp]
                       ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """``a1, a2, a3, a4`` (P,) of models `rows` at speeds v (P,) [m/s]."""
        u = v * v
        return (v * self.c[rows], self.k0[rows] + u * self.e2[rows], v * (self.d1[rows] + u * self.d3[rows]),
                self.f0[rows] + u * (self.f2[rows] + u * self.f4[rows]))

    def stable_at(self, v: NDArray[np.float64], rows: NDArray[np.intp]) -> NDArray[np.bool_]:
        """Whether models `rows` are asymptotically stable at speeds v (P,) [m/s] (Routh-Hurwitz).

        :func:`~whipple.stability.polynomial.hurwitz_stable`'s test without its rescaling of the
        polynomial, which changes no sign (a power of two) and matters only where a Hurwitz
        minor overflows or underflows: only there is the scaled test used.
        """
        a1, a2, a3, a4 = self.characteristic(v, rows)
        delta2 = a1 * a2 - a3
        delta3 = delta2 * a3 - a1 * a1 * a4
        stable = (a1 > 0) & (a4 > 0) & (delta2 > 0) & (delta3 > 0)
        with np.errstate(invalid="ignore"):
            doubtful = ~((np.abs(delta3) > _TINY) & (np.abs(delta3) < _HUGE) & (np.abs(delta2) > _TINY))
        if np.any(doubtful):
            a = np.stack([np.ones(int(np.count_nonzero(doubtful))), a1[doubtful], a2[doubtful], a3[doubtful],
                          a4[doubtful]], axis=-1)
            stable[doubtful] = hurwitz_stable(a)
        return stable


def _hopf_labels(p: _Invariants, v: NDArray[np.float64], w2: NDArray[np.float64]
                 ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Whether each Hopf crossing (R, 2) is the weave, and whether that is too close to call.

    At the root the quartic is ``(s^2 + w^2)(s^2 + a1 s + a2 - w^2)``; the crossing pair is the
    weave unless the other pair is complex with a lower frequency.
    """
    a1 = v * p.c[:, None]
    rest = p.k0[:, None] + v * v * p.e2[:, None] - w2
    disc = a1 * a1 - 4.0 * rest
    frequency = 0.5 * np.sqrt(np.maximum(-disc, 0.0))
    magnitude = 1.0 + np.sqrt(np.abs(rest))
    other_pair = frequency > modes.REAL_TOLERANCE * magnitude
    w = np.sqrt(np.maximum(w2, 0.0))
    weave = ~other_pair | (frequency >= w * (1.0 - 1e-12))
    doubtful = (np.abs(frequency - modes.REAL_TOLERANCE * magnitude) <= 1e-3 * modes.REAL_TOLERANCE * magnitude) \
        | (np.abs(frequency - w) <= 1e-9 * w)
    return weave, doubtful


def _capsize_labels(p: _Invariants, v: NDArray[np.float64]
                    ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Whether each real crossing (R, 2) is the capsize, and whether the closed form can tell.

    At the root the other eigenvalues solve ``s^3 + a1 s^2 + a2 s + a3``. With a complex pair
    among them (the weave) and one real eigenvalue r, the crossing (s = 0) is the capsize when
    it is the rightmost of the roll-dominated real eigenvalues (of all real ones if neither is
    roll-dominated). Without a pair the general solver follows the branches over speed.
    """
    u = v * v
    a1, a2 = v * p.c[:, None], p.k0[:, None] + u * p.e2[:, None]
    a3 = v * (p.d1[:, None] + u * p.d3[:, None])
    others = cubic_roots(a1.ravel(), a2.ravel(), a3.ravel()).reshape(v.shape + (3,))
    r = others[..., 0].real
    pair_imag = np.abs(others[..., 1].imag)
    magnitude = 1.0 + np.abs(others[..., 1])
    has_pair = pair_imag > modes.REAL_TOLERANCE * magnitude
    K = p.K0[:, None] + u[..., None, None] * p.K2[:, None]
    C = v[..., None, None] * p.C1[:, None]
    share_zero = null_roll_share(K)
    share_r = null_roll_share(r[..., None, None] ** 2 * np.eye(2) + r[..., None, None] * C + K)
    rolling_zero, rolling_r = share_zero >= 0.5, share_r >= 0.5
    zero_candidate = rolling_zero | ~rolling_r
    r_candidate = rolling_r | ~rolling_zero
    capsize = zero_candidate & (~r_candidate | (r < 0))
    doubtful = ~has_pair | (np.abs(pair_imag - modes.REAL_TOLERANCE * magnitude)
                            <= 1e-3 * modes.REAL_TOLERANCE * magnitude)
    doubtful |= (np.abs(share_zero - 0.5) <= 1e-9) | (np.abs(share_r - 0.5) <= 1e-9) | (r == 0)
    return capsize, doubtful


def _crossing_at_rest(p: _Invariants) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Whether the weave crosses the axis at v = 0, and whether the closed form cannot tell.

    v = 0 is the root of the factor u of the Hopf condition.

    At rest the quartic is ``s^4 + k0 s^2 + f0``: a pair is on the axis where a root z of
    ``z^2 + k0 z + f0`` is negative, the lowest-frequency one (the weave) at the negative z
    nearest zero, ``w^2 = -z``. It crosses when ``Re d lambda / dv = (c w^2 - d1) / (2 k0 -
    4 w^2)`` is not zero (the model is odd in v, so the real part changes sign there).
    """
    c, k0, d1 = p.c, p.k0, p.d1
    disc = k0 * k0 - 4.0 * p.f0
    root = np.sqrt(np.maximum(disc, 0.0))
    upper, lower = 0.5 * (-k0 + root), 0.5 * (-k0 - root)
    w2 = np.where(disc >= 0, np.where(upper < 0, -upper, -lower), -1.0)
    w = np.sqrt(np.maximum(w2, 0.0))
    on_axis = (w2 > 0) & (w > modes.REAL_TOLERANCE * (1.0 + w))
    slope, curvature = c * w2 - d1, 2.0 * k0 - 4.0 * w2
    scale = 1e-6 * (np.abs(c) * np.abs(w2) + np.abs(d1))
    doubtful = (np.abs(w - modes.REAL_TOLERANCE * (1.0 + w)) <= 1e-3 * modes.REAL_TOLERANCE) \
        | (np.abs(disc) <= DOUBLE_ROOT * k0 * k0)
    doubtful |= on_axis & ((np.abs(slope) <= scale) | (np.abs(curvature) <= 1e-6 * (np.abs(k0) + w2)))
    return on_axis & ~doubtful, doubtful


def _first(v: NDArray[np.float64], chosen: NDArray[np.bool_]) -> NDArray[np.float64]:
    """Lowest of the chosen speeds (R, 2) per row; NaN where none is chosen."""
    first = np.min(np.where(chosen, v, np.inf), axis=-1)
    return np.where(np.isfinite(first), first, np.nan)


def _first_weave(p: _Invariants, v: NDArray[np.float64], w2: NDArray[np.float64],
                 within: NDArray[np.bool_], low: float) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Return the first weave crossing in the interval [m/s] (NaN for none), and any doubt."""
    weave, doubt = _hopf_labels(p, v, w2)
    first = _first(v, within & weave)
    doubtful = np.any(within & doubt, axis=-1)
    if low == 0.0:
        at_rest, doubt_at_rest = _crossing_at_rest(p)
        first[at_rest] = 0.0
        doubtful |= doubt_at_rest
    return first, doubtful


def _first_capsize(p: _Invariants, v: NDArray[np.float64], within: NDArray[np.bool_], low: float
                   ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Return the first capsize crossing in the interval [m/s] (NaN for none), and any doubt."""
    capsize, doubt = _capsize_labels(p, v)
    doubtful = np.any(within & doubt, axis=-1)
    if low == 0.0:
        doubtful |= p.f0 == 0  # a real root at rest
    return _first(v, within & capsize), doubtful


def whipple_form_table(coefficients: NDArray[np.float64], low: float, high: float
                       ) -> WhippleFormTable:
    """Weave and capsize speeds and stable ranges of models of the Whipple form.

    Parameters
    ----------
    coefficients : ndarray, shape (N, T, 4, 4)
        ``A_k`` of N models of the Whipple form (:func:`is_whipple_form`) [1/s per (m/s)^k].
    low, high : float
        Speed interval [m/s], ``0 <= low < high``.

    Returns
    -------
    WhippleFormTable
    """
    return _table(_Invariants.of(coefficients), low, high)


def whipple_form_table_of_matrices(M: NDArray[np.float64], C1: NDArray[np.float64], K0: NDArray[np.float64],
                                   K2: NDArray[np.float64], low: float, high: float) -> WhippleFormTable:
    """:func:`whipple_form_table` of models ``M q'' + v C1 q' + (K0 + v^2 K2) q = 0``.

    The same numbers (bit for bit) as from the models' first-order coefficients, without
    forming them: a sweep's models need only these invariants.

    Parameters
    ----------
    M, C1, K0, K2 : ndarray, shape (N, 2, 2)
        Mass [kg m^2], velocity damping [kg m], stiffness with gravity [N m/rad] and
        speed-squared stiffness [kg] matrices; M invertible.
    low, high : float
        Speed interval [m/s], ``0 <= low < high``.
    """
    return _table(_Invariants.of_matrices(M, C1, K0, K2), low, high)


def _table(p: _Invariants, low: float, high: float) -> WhippleFormTable:
    """:func:`whipple_form_table` of the models with invariants `p`."""
    count = p.c.shape[0]
    c, k0, e2, d1, d3, f0, f2, f4 = p.c, p.k0, p.e2, p.d1, p.d3, p.f0, p.f2, p.f4
    # The Hopf condition divided by u, and the real condition.
    hopf_u, defer_hopf = _quadratic_roots(c * k0 * d1 - d1 * d1 - c * c * f0,
                                          c * (k0 * d3 + e2 * d1) - 2.0 * d1 * d3 - c * c * f2,
                                          c * e2 * d3 - d3 * d3 - c * c * f4)
    real_u, defer_real = _quadratic_roots(f0, f2, f4)
    with np.errstate(divide="ignore", invalid="ignore"):
        w2 = (d1[:, None] + hopf_u * d3[:, None]) / c[:, None]
        hopf_v, real_v = np.sqrt(hopf_u), np.sqrt(real_u)
    w = np.sqrt(np.maximum(w2, 0.0))
    genuine = (w2 > 0) & (w > modes.REAL_TOLERANCE * (1.0 + w))
    hopf_inside, hopf_within = _speeds(hopf_v, low, high)
    real_inside, real_within = _speeds(real_v, low, high)
    # (A Hopf root u = 0 beside the factor u is a double root at rest.)
    defer = defer_hopf | defer_real | (c == 0) | np.any(hopf_u == 0, axis=-1)
    # A pair barely on or off the axis (w ~ 0): the general solver decides on the eigenvalues.
    defer |= np.any(hopf_within & ~(np.abs(w2) > WEAK_PAIR), axis=-1)
    hopf_within &= genuine
    knots = np.concatenate([np.full((count, 1), float(low)), np.where(genuine, hopf_inside, np.nan),
                            real_inside, np.full((count, 1), float(high))], axis=-1)
    kind = np.zeros(knots.shape, dtype=np.int8)  # 1: Hopf root, 2: real root
    kind[:, 1:3], kind[:, 3:5] = 1, 2
    order = np.argsort(knots, axis=-1)  # NaN last
    knots = np.take_along_axis(knots, order, axis=-1)
    kind = np.take_along_axis(kind, order, axis=-1)
    defer |= np.any(np.diff(knots, axis=-1) <= COINCIDENT * (1.0 + knots[:, 1:]), axis=-1)
    start, end = knots[:, :-1], knots[:, 1:]
    rows, columns = np.nonzero(np.isfinite(end))
    stable = np.zeros(start.shape, dtype=bool)
    stable[rows, columns] = p.stable_at(0.5 * (start[rows, columns] + end[rows, columns]), rows)
    # The main (longest) stable range, the first of equal ones; where a Hopf (real) crossing
    # bounds it from below (above), that is the weave (capsize) speed, else the first
    # crossing labelled so.
    length = np.where(stable, end - start, -np.inf)
    main = np.argmax(length, axis=-1)
    index = np.arange(count)
    has_main = np.isfinite(length[index, main])
    weave_below = has_main & (kind[index, main] == 1)
    capsize_above = has_main & (kind[index, main + 1] == 2)
    weave = np.where(weave_below, start[index, main], np.nan)
    capsize = np.where(capsize_above, end[index, main], np.nan)
    settled = ~defer
    need = np.nonzero(settled & ~weave_below)[0]
    weave[need], doubtful = _first_weave(p.select(need), hopf_v[need], w2[need], hopf_within[need],
                                         low)
    settled[need[doubtful]] = False
    need = np.nonzero(settled & ~capsize_above)[0]
    capsize[need], doubtful = _first_capsize(p.select(need), real_v[need], real_within[need], low)
    settled[need[doubtful]] = False
    weave[~settled], capsize[~settled] = np.nan, np.nan
    range_model, range_column = np.nonzero(stable & settled[:, None])
    return WhippleFormTable(settled, weave, capsize, range_model, start[range_model, range_column],
                            end[range_model, range_column])
