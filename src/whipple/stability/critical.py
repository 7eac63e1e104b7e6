"""Critical speeds and stable speed ranges of linear bicycle models, from exact polynomial conditions.

A model ``x' = A(v) x`` is asymptotically stable at speed v [m/s] when every eigenvalue of
A(v) has a negative real part. Stability changes only where an eigenvalue crosses the
imaginary axis, at a zero of one of two scalar conditions, both exact polynomials in v for every
model of the package (:mod:`whipple.stability.polynomial`):

* the Hopf condition (Hurwitz determinant Delta_(n-1)), where a complex pair crosses: for the
  bicycle the **weave speed**;
* the real condition ``a_n = det(-A(v))``, where a real eigenvalue crosses zero: the **capsize
  speed** (``det(K0 + v^2 K2) = 0`` for the Whipple model).

The method, batched over bicycles, with no speed grid (its cost does not depend on the width of
``[low, high]``):

1. the characteristic coefficients, the Hopf and the real condition as polynomials in v, by
   exact polynomial arithmetic on A's coefficients (:mod:`whipple.stability.polynomial`);
2. all their real roots in ``[low, high]`` (:mod:`whipple.stability.polyroots`): closed form for
   the Whipple model's quadratics in v^2, companion-matrix eigenvalues otherwise, polished by
   Newton's method;
3. each root verified on the spectrum there (:mod:`whipple.stability.root_spectrum`, in closed
   form for 4-state models): a Hopf root where the pair summing to zero is two real
   eigenvalues of opposite sign (not an axis crossing; e.g. at v = 0 for the Whipple model) is
   dropped, as is a candidate whose eigenvalue is not on the axis. The sign of
   ``Re d lambda / dv`` gives the direction; a tangential root (an eigenvalue touching the axis
   without crossing) is reported with direction ``touch`` and splits a stable range, since
   stability is not asymptotic at that single speed;
4. the crossing mode named at the root (:mod:`whipple.stability.crossing_modes`);
5. stability between consecutive crossings from the Routh-Hurwitz test at the midpoint
   (:func:`whipple.stability.polynomial.hurwitz_stable`), no eigenvalues.

The dense-grid method this replaced (eigenvalues on a 0.01 m/s grid, brackets, Newton) lives on
as an independent check in the tests (tests/grid_critical.py).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import InputError
from whipple.model.linear import LinearModel, check_model, second_order_model
from whipple.stability import modes
from whipple.stability.polynomial import characteristic_at, conditions, hurwitz_stable
from whipple.stability.polyroots import real_roots
from whipple.stability.root_spectrum import directions, merge, merge_touches, verify_roots
from whipple.stability.whipple_form import (
    WhippleFormTable,
    is_whipple_form,
    whipple_form_table,
    whipple_form_table_of_matrices,
)

__all__ = ["CHUNK_SIZE", "KINDS", "Crossing", "CriticalSpeeds", "critical_speeds", "critical_speeds_batch",
           "crossing_arrays", "CriticalSpeedTable", "critical_speed_table", "whipple_speed_table"]

#: Parameter sets of a 4-state model solved together (scaled by 16 / n^2 for n states).
CHUNK_SIZE = 8192
KINDS = ("hopf", "real")


@dataclass(frozen=True)
class Crossing:
    """One eigenvalue crossing (or touching) the imaginary axis.

    Attributes
    ----------
    speed : float
        Forward speed [m/s].
    kind : str
        ``hopf`` (a complex pair crosses at +/- i w) or ``real`` (a real eigenvalue crosses 0).
    mode : str
        Label of the crossing mode (``weave``, ``capsize``, ... see :mod:`whipple.stability.modes`).
    direction : str
        ``destabilising`` (real part becomes positive with increasing speed),
        ``stabilising``, or ``touch`` (tangential: same sign either side).
    eigenvalue : complex
        The eigenvalue on the axis at the crossing [1/s] (positive imaginary part for hopf).
    method : str
        How the root was found: ``closed-form`` (a quadratic in v or v^2), ``companion``
        (companion-matrix eigenvalues) or ``companion+scan`` (a sign change near a companion
        pair, bisected), with ``+newton`` or ``+secant`` when polishing then moved it.
    """

    speed: float
    kind: str
    mode: str
    direction: str
    eigenvalue: complex
    method: str


@dataclass(frozen=True)
class CriticalSpeeds:
    """Critical speeds and stable speed ranges of one model in ``[low, high]``.

    Attributes
    ----------
    low, high : float
        The searched speed interval [m/s].
    crossings : tuple of Crossing
        Every crossing and touch found, by increasing speed.
    weave_speeds, capsize_speeds : tuple of float
        Speeds [m/s] of all weave (resp. capsize) crossings, touches excluded, sorted.
    stable_speed_ranges : tuple of (float, float)
        Every interval [m/s] where all eigenvalues have negative real parts (open at
        crossings; an end equal to `low` or `high` is where the search stopped).
    weave_speed, capsize_speed : float or None
        The oscillatory (real) crossing bounding the main stable range, i.e. the longest, from
        below (above), whatever the mode's label (with a controller the modes need not look
        like the uncontrolled bicycle's); if it is not bounded so, the first weave (capsize)
        crossing; None if there is none in the interval.
    """

    low: float
    high: float
    crossings: tuple[Crossing, ...]
    weave_speeds: tuple[float, ...]
    capsize_speeds: tuple[float, ...]
    stable_speed_ranges: tuple[tuple[float, float], ...]
    weave_speed: float | None
    capsize_speed: float | None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: speed range, weave and capsize speeds, stable ranges and crossings [m/s]."""
        return {
            "speed_range": [self.low, self.high],
            "weave_speed": self.weave_speed,
            "capsize_speed": self.capsize_speed,
            "weave_speeds": list(self.weave_speeds),
            "capsize_speeds": list(self.capsize_speeds),
            "stable_speed_ranges": [list(r) for r in self.stable_speed_ranges],
            "crossings": [{"speed": c.speed, "kind": c.kind, "mode": c.mode, "direction": c.direction,
                           "eigenvalue": [c.eigenvalue.real, c.eigenvalue.imag], "method": c.method}
                          for c in self.crossings],
        }

    def summary(self, std: Mapping[str, float | None] | None = None) -> list[str]:
        """Lines for people: the weave and capsize speeds and the stable speed ranges.

        Parameters
        ----------
        std : mapping, optional
            Standard deviations [m/s] by ``"weave"`` and ``"capsize"``, shown after the speeds.
        """
        std = std or {}

        def speed_text(kind: str, value: float | None) -> str:
            if value is None:
                return f"none in {self.low:g}-{self.high:g} m/s"
            spread = std.get(kind)
            return f"{value:.12g} m/s" + (f" +/- {spread:.3g}" if spread is not None else "")

        lines = [f"weave speed:   {speed_text('weave', self.weave_speed)}",
                 f"capsize speed: {speed_text('capsize', self.capsize_speed)}"]
        if self.stable_speed_ranges:
            ranges = ", ".join(f"{low:.6g} to {high:.6g}" for low, high in self.stable_speed_ranges)
            lines.append(f"stable speed ranges (m/s): {ranges}")
        else:
            lines.append(f"stable speed ranges: none in {self.low:g}-{self.high:g} m/s")
        return lines


def _check_interval(low: float, high: float) -> None:
    if not (np.isfinite(low) and np.isfinite(high) and low < high):
        raise InputError(f"speed range must satisfy low < high, got {low}:{high}")


def critical_speeds(model: LinearModel, low: float = 0.0, high: float = 10.0, *,
                    step: float | None = None, polish: bool = True) -> CriticalSpeeds:
    """All critical speeds and stable speed ranges of one model between `low` and `high`.

    Parameters
    ----------
    model : LinearModel
        A single model (no batch); any number of states.
    low, high : float
        Speed interval searched [m/s]; any finite width, at the same cost.
    step : float, optional
        Ignored (the solver has no speed grid); accepted so that older calls keep working.
    polish : bool
        Polish each root by Newton's method on its polynomial (default).

    Returns
    -------
    CriticalSpeeds

    Raises
    ------
    InputError
        If the interval or the model's matrices are invalid.
    """
    if model.batch_shape:
        raise ValueError("critical_speeds takes one model; use critical_speeds_batch")
    return critical_speeds_batch(model, low, high, step=step, polish=polish)[0]


def critical_speeds_batch(model: LinearModel, low: float = 0.0, high: float = 10.0, *,
                          step: float | None = None, polish: bool = True,
                          chunk_size: int = CHUNK_SIZE,
                          progress: Callable[[int], None] | None = None
                          ) -> list[CriticalSpeeds]:
    """:func:`critical_speeds` for every parameter set of a batched model, vectorised.

    Parameters
    ----------
    model : LinearModel
        Models with any batch shape.
    low, high, step, polish
        As for :func:`critical_speeds` (speeds in m/s).
    chunk_size : int
        Parameter sets of a 4-state model solved together; scaled by 16 / n^2 for n states.
    progress : callable, optional
        Called with the number of parameter sets finished after each chunk.

    Returns
    -------
    list of CriticalSpeeds
        One per parameter set, in C order of ``model.batch_shape``.
    """
    del step
    results: list[CriticalSpeeds] = []
    coefficients = _checked_coefficients(model, low, high)
    for _, count, found, segments in _solved_chunks(coefficients, low, high, polish, chunk_size):
        results += _package_all(found, segments, count, low, high)
        if progress is not None:
            progress(len(results))
    return results


def crossing_arrays(coefficients: NDArray[np.float64], low: float, high: float,
                    polish: bool = True) -> dict[str, NDArray]:
    """Every verified crossing of a batch of models, as flat arrays sorted by (model, speed).

    Parameters
    ----------
    coefficients : ndarray, shape (B, T, n, n)
        Polynomial coefficients of the state matrices, constant term first.
    low, high : float
        Speed interval [m/s].
    polish : bool
        Newton polishing of the roots.

    Returns
    -------
    dict
        ``model``, ``speed`` [m/s], ``value`` (eigenvalue on the axis [1/s]), ``kind``,
        ``method``, ``mode``, ``direction``; plus ``conditions`` (the polynomials).
    """
    polynomials = conditions(coefficients)
    parts = []
    for kind, poly in (("hopf", polynomials.hopf), ("real", polynomials.real)):
        roots = real_roots(poly, low, high, polish)
        parts.append(verify_roots(kind, coefficients, roots.model, roots.speed, roots.near,
                                  roots.method))
    found = merge(parts)
    found["direction"] = directions(found, coefficients, polynomials.characteristic)
    found = merge_touches(found)
    return {**found, "characteristic": polynomials.characteristic}


def _checked_coefficients(model: LinearModel, low: float, high: float) -> NDArray[np.float64]:
    """Check the interval and the model; return A's coefficients as (sets, T, n, n)."""
    _check_interval(low, high)
    check_model(model)
    n, terms = model.n_states, model.A.shape[-3]
    return model.A.reshape(-1, terms, n, n)


def _solved_chunks(coefficients: NDArray[np.float64], low: float, high: float, polish: bool,
                   chunk_size: int) -> Iterator[tuple[int, int, dict[str, NDArray], dict[str, NDArray]]]:
    """Solve parameter sets (A's coefficients, (sets, T, n, n)) a chunk at a time.

    Yields the chunk's first set, its number of sets, its crossings (:func:`crossing_arrays`)
    and its stable segments (:func:`_stable_segments`). ``chunk_size`` is for a 4-state model,
    scaled by 16 / n^2 for n states.
    """
    n = coefficients.shape[-1]
    chunk_size = max(1, int(chunk_size * 16 / n**2))
    for start in range(0, coefficients.shape[0], chunk_size):
        chunk = coefficients[start:start + chunk_size]
        found = crossing_arrays(chunk, float(low), float(high), polish)
        yield start, chunk.shape[0], found, _stable_segments(found, found["characteristic"], chunk.shape[0], low, high)


def _stable_segments(found: dict[str, NDArray], characteristic: NDArray[np.float64],
                     model_count: int, low: float, high: float) -> dict[str, NDArray]:
    """Segments between consecutive crossings of every model and whether each is stable.

    Stability at each segment's midpoint by the Routh-Hurwitz test on the characteristic
    polynomial there (no crossing inside a segment, so it holds on the whole segment). Each
    segment also says whether a (non-touch) Hopf crossing starts it and a real one ends it.
    """
    speed, moving = found["speed"], found["direction"] != "touch"
    inside = (speed > low) & (speed < high)
    model = np.concatenate([found["model"][inside], np.arange(model_count),
                            np.arange(model_count)])
    knots = np.concatenate([speed[inside], np.full(model_count, low), np.full(model_count, high)])
    flags = np.zeros(model_count)
    hopf = np.concatenate([(moving & (found["kind"] == "hopf"))[inside], flags, flags])
    real = np.concatenate([(moving & (found["kind"] == "real"))[inside], flags, flags])
    order = np.lexsort((knots, model))
    model, knots, hopf, real = model[order], knots[order], hopf[order], real[order]
    first = np.concatenate([[True], (model[1:] != model[:-1]) | (knots[1:] != knots[:-1])])
    starts = np.nonzero(first)[0]
    hopf = np.maximum.reduceat(hopf, starts) > 0
    real = np.maximum.reduceat(real, starts) > 0
    model, knots = model[first], knots[first]
    segment = model[1:] == model[:-1]
    seg_model, start, end = model[:-1][segment], knots[:-1][segment], knots[1:][segment]
    a = characteristic_at(characteristic[seg_model], 0.5 * (start + end))
    return {"model": seg_model, "start": start, "end": end, "stable": hurwitz_stable(a),
            "hopf_start": hopf[:-1][segment], "real_end": real[1:][segment]}


def _instance(cls: type, **fields: Any) -> Any:
    """Return a frozen dataclass instance made without its __init__ (fields already checked).

    Packaging is most of the cost of a large batch; filling ``__dict__`` directly gives the
    same object, about twice as fast as the frozen ``__init__``.
    """
    instance: Any = object.__new__(cls)
    instance.__dict__.update(fields)
    return instance


def _first_per_model(model: NDArray[np.intp], values: NDArray[np.float64],
                     count: int) -> NDArray[np.float64]:
    """Return the first of `values` of each model (sorted by model), NaN where there is none."""
    out = np.full(count, np.nan)
    if model.size:
        first = np.concatenate([[True], model[1:] != model[:-1]])
        out[model[first]] = values[first]
    return out


def _main_speeds(found: dict[str, NDArray], segments: dict[str, NDArray], count: int
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64], dict[str, NDArray]]:
    """Weave and capsize speed of every model (NaN for none) and the stable segments.

    The weave (capsize) speed is the start (end) of the longest stable range when a Hopf (real)
    crossing bounds it there, whatever the mode's label (with a controller the modes need not
    look like the uncontrolled bicycle's); otherwise the first weave (capsize) crossing.
    """
    model, speed = found["model"], found["speed"]
    moving = found["direction"] != "touch"
    weave = moving & (found["mode"] == modes.WEAVE) & (found["kind"] == "hopf")
    capsize = moving & (found["mode"] == modes.CAPSIZE) & (found["kind"] == "real")
    stable = segments["stable"]
    seg_model, start, end = (segments[key][stable] for key in ("model", "start", "end"))
    # The longest stable range of each model (the first of equal ones).
    order = np.lexsort((np.arange(seg_model.size), -(end - start), seg_model))
    leading = np.concatenate([[True], seg_model[order][1:] != seg_model[order][:-1]])
    main = order[leading[:order.size]]
    weave_speed = _first_per_model(model[weave], speed[weave], count)
    capsize_speed = _first_per_model(model[capsize], speed[capsize], count)
    below = main[segments["hopf_start"][stable][main]]
    weave_speed[seg_model[below]] = start[below]
    above = main[segments["real_end"][stable][main]]
    capsize_speed[seg_model[above]] = end[above]
    ranges = {"model": seg_model, "low": start, "high": end, "weave": weave, "capsize": capsize}
    return weave_speed, capsize_speed, ranges


@dataclass(frozen=True)
class CriticalSpeedTable:
    """Weave and capsize speeds and stable ranges of many models, as arrays (no objects).

    Attributes
    ----------
    weave_speed, capsize_speed : ndarray, shape (N,)
        As :attr:`CriticalSpeeds.weave_speed` and ``capsize_speed`` [m/s]; NaN for none.
    range_model : ndarray of int, shape (R,)
        Model (C-order index in the batch) of each stable range, ascending.
    range_low, range_high : ndarray, shape (R,)
        Ends [m/s] of each stable range, by increasing speed within a model.
    """

    weave_speed: NDArray[np.float64]
    capsize_speed: NDArray[np.float64]
    range_model: NDArray[np.intp]
    range_low: NDArray[np.float64]
    range_high: NDArray[np.float64]


def critical_speed_table(model: LinearModel, low: float = 0.0, high: float = 10.0, *,
                         polish: bool = True, chunk_size: int = CHUNK_SIZE) -> CriticalSpeedTable:
    """Return the speeds of :func:`critical_speeds_batch` as arrays, for sweeps of many models.

    Same numbers, without building a :class:`CriticalSpeeds` per model (which is most of the
    cost of a large batch). Models of the Whipple form (no steer damping, no controller) are
    solved in closed form (:mod:`whipple.stability.whipple_form`) where that settles their
    speeds, and by the general solver otherwise; the two agree to rounding (tested).

    Parameters
    ----------
    model : LinearModel
        Models with any batch shape.
    low, high, polish, chunk_size
        As for :func:`critical_speeds_batch` (speeds in m/s).

    Returns
    -------
    CriticalSpeedTable
    """
    coefficients = _checked_coefficients(model, low, high)
    if not (polish and low >= 0 and coefficients.shape[0] and is_whipple_form(coefficients)):
        return _general_table(coefficients, low, high, polish, chunk_size)
    return _closed_form_first(lambda part: whipple_form_table(coefficients[part], low, high),
                              lambda rows: coefficients[rows], coefficients.shape[0], low, high, chunk_size)


def whipple_speed_table(M: ArrayLike, C1: ArrayLike, K0: ArrayLike, K2: ArrayLike, low: float = 0.0,
                        high: float = 10.0, *, chunk_size: int = CHUNK_SIZE) -> CriticalSpeedTable:
    """:func:`critical_speed_table` of models ``M q'' + v C1 q' + (K0 + v^2 K2) q = 0`` given by their matrices.

    The same numbers as :func:`critical_speed_table` of their first-order models, which are
    formed only for the few models the closed form leaves to the general solver: for sweeps,
    where forming them all costs as much as solving them.

    Parameters
    ----------
    M, C1, K0, K2 : array_like, shape (..., 2, 2)
        Mass [kg m^2], velocity damping [kg m], stiffness with gravity [N m/rad] and
        speed-squared stiffness [kg] matrices; the leading axes are a batch of models.
    low, high : float
        Speed interval [m/s].
    chunk_size : int
        As for :func:`critical_speeds_batch`.
    """
    _check_interval(low, high)
    shape = np.broadcast_shapes(*(np.shape(X) for X in (M, C1, K0, K2)))
    matrices = [np.broadcast_to(np.asarray(X, dtype=float), shape).reshape(-1, 2, 2) for X in (M, C1, K0, K2)]
    if not all(np.all(np.isfinite(X)) for X in matrices):
        raise InputError("the model's matrices have NaN or infinite entries")

    def coefficients(rows: Any) -> NDArray[np.float64]:
        model = second_order_model(*(X[rows] for X in matrices))
        check_model(model)
        return model.A

    count = matrices[0].shape[0]
    if low < 0 or not count:
        return _general_table(coefficients(slice(None)), low, high, True, chunk_size)

    def closed_form(part: slice) -> WhippleFormTable:
        mass, velocity_damping, stiffness, speed_stiffness = (X[part] for X in matrices)
        return whipple_form_table_of_matrices(mass, velocity_damping, stiffness, speed_stiffness, low, high)

    return _closed_form_first(closed_form, coefficients, count, low, high, chunk_size)


def _closed_form_first(closed_form: Callable[[slice], WhippleFormTable],
                       coefficients: Callable[[NDArray[np.intp]], NDArray[np.float64]], count: int,
                       low: float, high: float, chunk_size: int) -> CriticalSpeedTable:
    """Return the table of `count` Whipple-form models, in closed form where that settles them.

    `closed_form` solves a chunk (slice) of the models; the general solver those it did not
    settle, given their first-order `coefficients`.
    """
    closed = [closed_form(slice(start, start + chunk_size)) for start in range(0, count, chunk_size)]
    settled = np.concatenate([part.settled for part in closed])
    # The few models the closed form leaves go to the general solver together: its cost is
    # mostly per call.
    rest = np.nonzero(~settled)[0]
    general = _general_table(coefficients(rest), low, high, True, chunk_size)
    weave = np.concatenate([part.weave_speed for part in closed])
    capsize = np.concatenate([part.capsize_speed for part in closed])
    weave[rest], capsize[rest] = general.weave_speed, general.capsize_speed
    offsets = np.arange(0, count, chunk_size)
    range_model = np.concatenate([part.range_model + offset for part, offset in zip(closed, offsets, strict=True)]
                                 + [rest[general.range_model]])
    # Stable: the ranges of one model stay in increasing speed.
    order = np.argsort(range_model, kind="stable")
    return CriticalSpeedTable(weave, capsize, range_model[order],
                              np.concatenate([part.range_low for part in closed] + [general.range_low])[order],
                              np.concatenate([part.range_high for part in closed] + [general.range_high])[order])


def _concatenated(parts: list[CriticalSpeedTable]) -> CriticalSpeedTable:
    """One table of the models of all parts (none: an empty table)."""
    empty = np.zeros(0)
    parts = parts or [CriticalSpeedTable(empty, empty, np.zeros(0, dtype=np.intp), empty, empty)]
    return CriticalSpeedTable(*(np.concatenate([getattr(part, field) for part in parts])
                                for field in CriticalSpeedTable.__dataclass_fields__))


def _general_table(coefficients: NDArray[np.float64], low: float, high: float, polish: bool,
                   chunk_size: int) -> CriticalSpeedTable:
    """:func:`critical_speed_table` by the general solver."""
    parts = []
    for start, count, found, segments in _solved_chunks(coefficients, low, high, polish, chunk_size):
        weave, capsize, ranges = _main_speeds(found, segments, count)
        parts.append(CriticalSpeedTable(weave, capsize, ranges["model"] + start, ranges["low"],
                                        ranges["high"]))
    return _concatenated(parts)


def _package_all(found: dict[str, NDArray], segments: dict[str, NDArray], count: int,
                 low: float, high: float) -> list[CriticalSpeeds]:
    """Assemble the results of all `count` models from the chunk's flat arrays (sorted by model)."""
    model, speed = found["model"], found["speed"]
    weave_speed, capsize_speed, ranges_ = _main_speeds(found, segments, count)
    weave, capsize = ranges_["weave"], ranges_["capsize"]
    seg_model, start, end = ranges_["model"], ranges_["low"], ranges_["high"]

    crossings = [_instance(Crossing, speed=v, kind=k, mode=m, direction=d, eigenvalue=e, method=t)
                 for v, k, m, d, e, t in zip(
                     speed.tolist(), found["kind"].tolist(), found["mode"].tolist(),
                     found["direction"].tolist(), found["value"].astype(complex).tolist(),
                     found["method"].tolist(), strict=True)]
    ranges = list(zip(start.tolist(), end.tolist(), strict=True))
    weave_list, capsize_list = speed[weave].tolist(), speed[capsize].tolist()
    cuts = np.arange(count + 1)
    bounds = np.searchsorted(model, cuts).tolist()
    range_bounds = np.searchsorted(seg_model, cuts).tolist()
    weave_bounds = np.searchsorted(model[weave], cuts).tolist()
    capsize_bounds = np.searchsorted(model[capsize], cuts).tolist()
    weave_main = [None if x != x else x for x in weave_speed.tolist()]
    capsize_main = [None if x != x else x for x in capsize_speed.tolist()]
    return [_instance(CriticalSpeeds, low=low, high=high,
                      crossings=tuple(crossings[bounds[i]:bounds[i + 1]]),
                      weave_speeds=tuple(weave_list[weave_bounds[i]:weave_bounds[i + 1]]),
                      capsize_speeds=tuple(capsize_list[capsize_bounds[i]:capsize_bounds[i + 1]]),
                      stable_speed_ranges=tuple(ranges[range_bounds[i]:range_bounds[i + 1]]),
                      weave_speed=weave_main[i], capsize_speed=capsize_main[i])
            for i in range(count)]
