"""The spectrum at each root of a stability condition: verification, direction, mode.

Used by :mod:`whipple.stability.critical`. A root of the Hopf or real condition
(:mod:`whipple.stability.polyroots`) is a change of stability only if an eigenvalue is on the
imaginary axis there: the Hopf condition also vanishes where two real eigenvalues of opposite
sign have a zero sum. At each root this module finds the eigenvalues, keeps the genuine
crossings, reads the direction and names the mode (:mod:`whipple.stability.crossing_modes`):

* **second-order models** (4 states ``[q, q']``: Whipple, damping, controllers), for simple
  roots, in closed form from the characteristic coefficients ``a_k`` at the root: at a Hopf
  root the quartic factors as ``(s^2 + w^2)(s^2 + a_1 s + a_2 - w^2)`` with ``w^2 = a_3 / a_1``
  (``w^2 < 0``: opposite real eigenvalues, dropped); at a real root ``s = 0`` and the cubic
  ``s^3 + a_1 s^2 + a_2 s + a_3`` gives the others; each eigenvector is ``[q, s q]`` with q in
  the null space of ``s^2 I + s C(v) + K(v)``;
* **other models** and touch candidates: ``numpy.linalg.eig`` of A at the root, after a few
  secant steps on the crossing eigenvalue's real part for companion-matrix roots (high-degree
  polynomials in the monomial basis lose digits; the eigenvalues do not).

The direction is the sign of ``Re d lambda / dv = -Re (dp/dv) / (dp/ds)`` at the crossing
eigenvalue (p the characteristic polynomial); where that is not clear-cut (a touch, a double
eigenvalue) the eigenvalues just either side of the root decide, as the old grid solver did.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from whipple.stability import modes
from whipple.stability.crossing_modes import crossing_modes
from whipple.stability.cubic import cubic_roots
from whipple.stability.polynomial import (
    characteristic_at,
    det_2x2,
    is_second_order,
    mixed_2x2,
    state_matrices_at,
)

#: Largest |real part| [1/s, relative to 1 + |lambda|] of an eigenvalue accepted as touching
#: the imaginary axis at a tangential root.
TOUCH_TOLERANCE = 1e-9
#: Largest |real part| [1/s, relative to 1 + |lambda|] of the crossing eigenvalue at a simple
#: root (the roots are exact to rounding; this only rejects spurious candidates).
AXIS_TOLERANCE = 1e-6
#: Roots [m/s, relative to 1 + |v|] closer than this are one (double) root.
DOUBLE_ROOT_GAP = 1e-7
#: Secant steps on the crossing eigenvalue after a companion-matrix root, and how far
#: [m/s, relative to 1 + |v|] they may move it.
REFINE_STEPS = 4
REFINE_WINDOW = 1e-4
#: Offset [m/s, relative to 1 + |v|] either side of a root where a doubtful direction is read.
SIDE_STEP = 1e-6
#: Smallest |Re d lambda/dv| relative to |d lambda/dv| read as a crossing (else: look either side).
CLEAR_SLOPE = 1e-8


def _eigenvalues_at(coefficients: NDArray[np.float64], model: NDArray[np.intp],
                    speed: NDArray[np.float64]) -> NDArray[np.complex128]:
    if speed.size == 0:
        return np.zeros((0, coefficients.shape[-1]), dtype=complex)
    return np.asarray(np.linalg.eigvals(state_matrices_at(coefficients, model, speed)),
                      dtype=complex)


def _nearest(values: NDArray[np.complex128], target: NDArray[np.complex128]) -> NDArray[np.intp]:
    return np.argmin(np.abs(values - target[:, None]), axis=-1)


def _crossing_value(kind: str, lam: NDArray[np.complex128], target: NDArray[np.complex128]
                    ) -> NDArray[np.complex128]:
    rows = np.arange(lam.shape[0])
    return lam[rows, _nearest(lam, target)]


def _refine(kind: str, model: NDArray[np.intp], speed: NDArray[np.float64],
            near: NDArray[np.bool_], method: NDArray[np.str_],
            coefficients: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.str_]]:
    """Secant steps on the real part of the crossing eigenvalue itself.

    High-degree condition polynomials (controllers, the tyre model) lose digits when expanded
    in the monomial basis; the eigenvalues of A(v) do not. Simple roots found by companion
    matrices are therefore finished on ``Re lambda(v)``, each step kept only if it reduces
    ``|Re lambda|`` and stays within :data:`REFINE_WINDOW` of the polynomial root.
    """
    todo = np.nonzero(~near & np.char.startswith(method, "companion"))[0]
    if todo.size == 0:
        return speed, method
    speed = speed.copy()
    sub_model, start = model[todo], speed[todo]
    lam = _eigenvalues_at(coefficients, sub_model, start)
    target = (lam[np.arange(todo.size), np.argmin(np.abs(lam.real), axis=-1)])
    x0, g0 = start, target.real
    x1 = start + 1e-7 * (1.0 + np.abs(start))
    value1 = _crossing_value(kind, _eigenvalues_at(coefficients, sub_model, x1), target)
    g1 = value1.real
    best, best_g = x0.copy(), np.abs(g0)
    window = REFINE_WINDOW * (1.0 + np.abs(start))
    for _ in range(REFINE_STEPS):
        with np.errstate(divide="ignore", invalid="ignore"):
            x2 = x1 - g1 * (x1 - x0) / (g1 - g0)
        x2 = np.where(np.isfinite(x2) & (np.abs(x2 - start) <= window), x2, x1)
        value2 = _crossing_value(kind, _eigenvalues_at(coefficients, sub_model, x2), value1)
        g2 = value2.real
        better = np.abs(g2) < best_g
        best, best_g = np.where(better, x2, best), np.where(better, np.abs(g2), best_g)
        x0, g0, x1, g1, value1 = x1, g1, x2, g2, value2
    moved = best != start
    speed[todo] = best
    method = method.astype("<U27")
    method[todo[moved]] = np.char.add(method[todo[moved]], "+secant")
    return speed, method


def _null_shares(coefficients: NDArray[np.float64], speed: NDArray[np.float64],
                 eigenvalues: NDArray[np.complex128]) -> NDArray[np.float64]:
    """``|roll| / (|roll| + |steer|)`` of each eigenvector of a second-order model at its root."""
    A = state_matrices_at(coefficients, np.arange(speed.size), speed)
    K, C = -A[:, None, 2:, :2], -A[:, None, 2:, 2:]
    s = eigenvalues[:, :, None, None]
    return null_roll_share(s * s * np.eye(2) + s * C + K)


def null_roll_share(B: NDArray[np.complex128] | NDArray[np.float64]) -> NDArray[np.float64]:
    """``|roll| / (|roll| + |steer|)`` of the null vector q of singular 2 x 2 matrices B (..., 2, 2).

    q is orthogonal to the larger row of B (0.5 where B vanishes).
    """
    first = np.abs(B[..., 0, 0]) + np.abs(B[..., 0, 1]) >= np.abs(B[..., 1, 0]) + np.abs(B[..., 1, 1])
    row = np.where(first[..., None], B[..., 0, :], B[..., 1, :])
    roll, steer = np.abs(row[..., 1]), np.abs(row[..., 0])
    with np.errstate(invalid="ignore", divide="ignore"):
        share = roll / (roll + steer)
    return np.where(np.isfinite(share), share, 0.5)


def _closed_form(kind: str, a: NDArray[np.float64]
                 ) -> tuple[NDArray[np.complex128], NDArray[np.bool_]]:
    """Eigenvalues at simple roots of a 4-state model from ``a_k`` (R, 5); crossing one first."""
    count = a.shape[0]
    lam = np.zeros((count, 4), dtype=complex)
    if kind == "hopf":
        with np.errstate(divide="ignore", invalid="ignore"):
            w2 = a[:, 3] / a[:, 1]
        # a_1 = a_3 = 0 (v = 0 for the Whipple model): s^4 + a_2 s^2 + a_4, so s^2 solves a
        # quadratic; a pair is on the axis where a root s^2 = -w^2 is real and negative.
        even = a[:, 1] == 0
        if np.any(even):
            disc = a[even, 2] ** 2 - 4.0 * a[even, 4]
            lower = np.where(disc >= 0, 0.5 * (-a[even, 2] - np.sqrt(np.abs(disc))), np.nan)
            upper = np.where(disc >= 0, 0.5 * (-a[even, 2] + np.sqrt(np.abs(disc))), np.nan)
            # The lowest-frequency pair on the axis: the negative root nearest zero.
            w2[even] = np.where(upper < 0, -upper, np.where(lower < 0, -lower, np.nan))
        genuine = np.isfinite(w2) & (w2 > 0)
        w = np.sqrt(np.where(genuine, w2, 0.0))
        genuine &= w > modes.REAL_TOLERANCE * (1.0 + w)
        lam[:, 0], lam[:, 1] = 1j * w, -1j * w
        b, c = a[:, 1], a[:, 2] - np.where(genuine, w2, 0.0)
        root = np.sqrt((b * b - 4.0 * c).astype(complex))
        lam[:, 2], lam[:, 3] = 0.5 * (-b + root), 0.5 * (-b - root)
        return lam, genuine
    lam[:, 1:] = cubic_roots(a[:, 1], a[:, 2], a[:, 3])
    return lam, np.ones(count, dtype=bool)


def _by_eig(kind: str, coefficients: NDArray[np.float64], speed: NDArray[np.float64],
            near: NDArray[np.bool_]) -> tuple[NDArray[np.complex128], NDArray[np.float64],
                                              NDArray[np.intp], NDArray[np.bool_]]:
    """Eigenvalues, roll shares, crossing index and genuineness from ``numpy.linalg.eig``."""
    n = coefficients.shape[-1]
    if speed.size == 0:
        return (np.zeros((0, n), dtype=complex), np.zeros((0, n)), np.zeros(0, dtype=np.intp),
                np.zeros(0, dtype=bool))
    lam, vectors = np.linalg.eig(state_matrices_at(coefficients, np.arange(speed.size), speed))
    lam, vectors = np.asarray(lam, dtype=complex), np.asarray(vectors, dtype=complex)
    amplitude = np.abs(vectors[:, :2, :])
    with np.errstate(invalid="ignore", divide="ignore"):
        share = amplitude[:, 0] / (amplitude[:, 0] + amplitude[:, 1])
    share = np.where(np.isfinite(share), share, 0.5)
    rows = np.arange(speed.size)
    if kind == "hopf":
        # The pair on the axis: of the complex-conjugate pairs, the one with the smallest
        # real part (two real eigenvalues of opposite sign also sum to zero, and at v = 0 the
        # Whipple model may have both at once).
        size = 1.0 + np.abs(lam)
        upper = lam.imag > modes.REAL_TOLERANCE * size
        branch = np.argmin(np.where(upper, np.abs(lam.real), np.inf), axis=-1)
        value = lam[rows, branch]
        genuine = upper[rows, branch]
        on_axis = np.abs(value.real)
    else:
        branch = np.argmin(np.abs(lam), axis=-1)
        value = lam[rows, branch]
        genuine = np.abs(value.imag) <= modes.REAL_TOLERANCE * (1.0 + np.abs(value))
        on_axis = np.abs(value)
    tolerance = np.where(near, TOUCH_TOLERANCE, AXIS_TOLERANCE) * (1.0 + np.abs(value))
    return lam, share, branch, genuine & (on_axis <= tolerance)


def verify_roots(kind: str, coefficients: NDArray[np.float64], model: NDArray[np.intp],
                 speed: NDArray[np.float64], near: NDArray[np.bool_], method: NDArray[np.str_]
                 ) -> dict[str, NDArray]:
    """Keep the roots where an eigenvalue is on the imaginary axis; name its mode.

    Parameters
    ----------
    kind : {'hopf', 'real'}
        The condition whose roots these are.
    coefficients : ndarray, shape (B, T, n, n)
        Polynomial coefficients of the state matrices of the models [1/s per (m/s)^k].
    model, speed, near, method : ndarray, shape (R,)
        The roots (:class:`whipple.stability.polyroots.PolynomialRoots`), speeds in m/s.

    Returns
    -------
    dict
        Flat arrays ``model``, ``speed`` [m/s], ``value`` (the eigenvalue on the axis [1/s],
        positive imaginary part for hopf), ``kind``, ``method``, ``mode``.
    """
    n = coefficients.shape[-1]
    # One root per speed: a double root may come out of the solver twice, split by rounding.
    same = np.zeros(speed.shape, dtype=bool)
    same[1:] = ((model[1:] == model[:-1])
                & (np.abs(np.diff(speed)) <= DOUBLE_ROOT_GAP * (1.0 + np.abs(speed[1:]))))
    model, speed, near, method = model[~same], speed[~same], near[~same], method[~same]
    speed, method = _refine(kind, model, speed, near, method, coefficients)
    lam = np.zeros((speed.size, n), dtype=complex)
    share = np.zeros((speed.size, n))
    branch = np.zeros(speed.size, dtype=np.intp)
    genuine = np.zeros(speed.size, dtype=bool)
    closed = np.zeros(speed.size, dtype=bool)
    if is_second_order(coefficients):
        closed = ~near
        if np.any(closed):
            from_char = characteristic_at_roots(coefficients, model[closed], speed[closed])
            if kind == "hopf":
                # a_1 = 0 (e.g. at v = 0) leaves w^2 = a_3 / a_1 undefined: use eig there.
                defined = (from_char[:, 1] != 0) | (from_char[:, 3] == 0)
                closed[np.nonzero(closed)[0][~defined]] = False
                from_char = from_char[defined]
            lam[closed], genuine[closed] = _closed_form(kind, from_char)
            if kind == "real":  # Hopf labels need no eigenvectors
                share[closed] = _null_shares(coefficients[model[closed]], speed[closed],
                                             lam[closed])
    rest = ~closed
    lam[rest], share[rest], branch[rest], genuine[rest] = _by_eig(
        kind, coefficients[model[rest]], speed[rest], near[rest])
    keep = np.nonzero(genuine)[0]
    labels = crossing_modes(kind, coefficients, model[keep], speed[keep], lam[keep],
                            share[keep], branch[keep])
    return {"model": model[keep], "speed": speed[keep],
            "value": lam[keep, branch[keep]], "kind": np.full(keep.shape, kind),
            "method": method[keep].astype("<U27"), "mode": labels}


def characteristic_at_roots(coefficients: NDArray[np.float64], model: NDArray[np.intp],
                            speed: NDArray[np.float64]) -> NDArray[np.float64]:
    """``[1, a_1 .. a_4]`` of second-order models at their roots, from ``det(s^2 I + s C + K)``."""
    A = state_matrices_at(coefficients, model, speed)
    K, C = -A[:, 2:, :2], -A[:, 2:, 2:]
    return np.stack([np.ones(speed.size), C[:, 0, 0] + C[:, 1, 1],
                     K[:, 0, 0] + K[:, 1, 1] + det_2x2(C), mixed_2x2(C, K), det_2x2(K)], axis=-1)


def merge(parts: list[dict[str, NDArray]]) -> dict[str, NDArray]:
    """Concatenate flat crossing arrays and sort them by (model, speed)."""
    merged = {key: np.concatenate([part[key] for part in parts]) for key in parts[0]}
    order = np.lexsort((merged["speed"], merged["model"]))
    return {key: array[order] for key, array in merged.items()}


def merge_touches(found: dict[str, NDArray]) -> dict[str, NDArray]:
    """One tangential root where rounding split it in two neighbouring touches of one kind."""
    model, speed, kind, direction = found["model"], found["speed"], found["kind"], found["direction"]
    twin = np.zeros(speed.shape, dtype=bool)
    twin[1:] = ((model[1:] == model[:-1]) & (kind[1:] == kind[:-1]) & (direction[1:] == "touch")
                & (direction[:-1] == "touch")
                & (np.diff(speed) <= REFINE_WINDOW * (1.0 + np.abs(speed[1:]))))
    if not np.any(twin):
        return found
    first = np.nonzero(twin)[0] - 1
    found = {key: array.copy() for key, array in found.items()}
    found["speed"][first] = 0.5 * (speed[first] + speed[first + 1])
    return {key: array[~twin] for key, array in found.items()}


def directions(found: dict[str, NDArray], coefficients: NDArray[np.float64],
               characteristic: NDArray[np.float64]) -> NDArray[np.str_]:
    """Direction of each crossing: sign of ``Re d lambda / dv`` (see the module docstring).

    Parameters
    ----------
    found : dict
        Flat arrays ``model``, ``speed`` [m/s], ``value`` [1/s] sorted by (model, speed).
    coefficients : ndarray, shape (B, T, n, n)
        Polynomial coefficients of the state matrices.
    characteristic : ndarray, shape (B, n + 1, L)
        The characteristic coefficients as polynomials in v.

    Returns
    -------
    ndarray of str
        ``destabilising``, ``stabilising`` or ``touch``.
    """
    model, speed, value = found["model"], found["speed"], found["value"]
    if speed.size == 0:
        return np.zeros(0, dtype="<U13")
    n = characteristic.shape[1] - 1
    own = characteristic[model]
    a = characteristic_at(own, speed)
    slope_poly = own[:, :, 1:] * np.arange(1, own.shape[-1])
    da = characteristic_at(slope_poly, speed) if own.shape[-1] > 1 else np.zeros_like(a)
    powers = value[:, None] ** np.arange(n, -1, -1)
    dp_dv = np.sum(da * powers, axis=-1)
    dp_ds = np.sum(a[:, :-1] * np.arange(n, 0, -1) * value[:, None] ** np.arange(n - 1, -1, -1),
                   axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        rate = -dp_dv / dp_ds
    clear = np.isfinite(rate) & (np.abs(rate.real) > CLEAR_SLOPE * np.abs(rate))
    # Two roots this close may be one double root split by rounding: look either side.
    same = model[1:] == model[:-1]
    close = same & (np.diff(speed) <= REFINE_WINDOW * (1.0 + np.abs(speed[1:])))
    clear[1:] &= ~close
    clear[:-1] &= ~close
    result = np.where(rate.real > 0, "destabilising", "stabilising").astype("<U13")
    doubt = np.nonzero(~clear)[0]
    if doubt.size:
        result[doubt] = _side_directions(found, coefficients, doubt)
    return result


def _side_directions(found: dict[str, NDArray], coefficients: NDArray[np.float64],
                     subset: NDArray[np.intp]) -> NDArray[np.str_]:
    """Sign of the crossing eigenvalue's real part just below and above the roots `subset`."""
    model, speed, value = found["model"], found["speed"], found["value"]
    same = np.concatenate([[False], model[1:] == model[:-1]])
    gap_below = np.where(same, np.diff(speed, prepend=-np.inf), np.inf)
    gap_above = np.concatenate([gap_below[1:], [np.inf]])
    gap = np.minimum(gap_below, gap_above)
    gap = np.where(gap > 0, gap, np.inf)
    delta = np.minimum(SIDE_STEP * (1.0 + np.abs(speed)), 0.25 * gap)[subset]
    model, speed, value = model[subset], speed[subset], value[subset]
    both = _eigenvalues_at(coefficients, np.concatenate([model, model]),
                           np.concatenate([speed - delta, speed + delta]))
    below, above = both[:speed.size], both[speed.size:]
    rows = np.arange(speed.size)
    re_below = below[rows, _nearest(below, value)].real
    re_above = above[rows, _nearest(above, value)].real
    return np.select([(re_below < 0) & (re_above > 0), (re_below > 0) & (re_above < 0)],
                     ["destabilising", "stabilising"], default="touch")


