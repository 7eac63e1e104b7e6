"""Critical speeds and stable speed ranges of linear bicycle models.

A model ``x' = A(v) x`` is asymptotically stable at speed v [m/s] when every eigenvalue of
A(v) has a negative real part. Stability changes only where an eigenvalue crosses the
imaginary axis, at a zero of one of two scalar conditions (:mod:`whipple.stability.characteristic`):

* the Hopf condition (Hurwitz determinant Delta_(n-1)), where a complex pair crosses: for the
  bicycle the **weave speed**;
* the real condition ``det A(v)``, where a real eigenvalue crosses zero: the **capsize speed**
  (``det(K0 + v^2 K2) = 0`` for the Whipple model).

Every zero in ``[low, high]`` is bracketed on a speed grid, refined, and solved with
``casadi.rootfinder`` (:mod:`whipple.stability.roots`). Each root is then checked on the
eigenvalues there: a Hopf root where the pair summing to zero is two real eigenvalues of
opposite sign (not an axis crossing; e.g. at v = 0 for the Whipple model) is dropped. The
eigenvalues just either side give the direction, and the tracked mode labels
(:mod:`whipple.stability.modes`) say which mode crosses. Tangential roots (an eigenvalue touching the
axis without crossing) are reported as crossings with direction ``touch``; a stable range is
split at them since stability is not asymptotic at that single speed. Stable ranges are read
off the eigenvalues at the midpoints between consecutive crossings.

As a safety net, stability on the grid is compared with the stable ranges; a change of
stability between grid points without a crossing found is located by bisection on the
largest real part (method ``eigenvalue-bisection``). The property tests check that this net
is never needed on random bicycles.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from whipple.errors import InputError
from whipple.model.linear import LinearModel
from whipple.stability import modes
from whipple.stability.eigen import check_model, tracked_eigenvalues, tracking_grid
from whipple.stability.roots import KINDS, Roots, condition, find_roots, polynomial_matrices

#: Largest |real part| [1/s, relative to 1 + |lambda|] of an eigenvalue accepted as touching
#: the imaginary axis at a tangential root.
TOUCH_TOLERANCE = 1e-9
#: Offset [m/s, relative to 1 + |v|] either side of a root where the direction is read.
SIDE_STEP = 1e-6
#: Steps in which eigenvalues are followed from the nearest grid speed to a root.
MODE_SUBSTEPS = 8


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
        How the speed was solved: ``casadi-newton``, ``bisection``, ``grid`` (exactly on the
        grid), ``touch`` (minimum of the condition) or ``eigenvalue-bisection``.
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


def _check_interval(low: float, high: float, step: float) -> None:
    if not (np.isfinite(low) and np.isfinite(high) and low < high):
        raise InputError(f"speed range must satisfy low < high, got {low}:{high}")
    if not (np.isfinite(step) and step > 0):
        raise InputError(f"speed step must be positive, got {step}")


def critical_speeds(model: LinearModel, low: float = 0.0, high: float = 10.0, *,
                    step: float = 0.01, polish: bool = True) -> CriticalSpeeds:
    """All critical speeds and stable speed ranges of one model between `low` and `high`.

    Parameters
    ----------
    model : LinearModel
        A single model (no batch); any number of states.
    low, high : float
        Speed interval searched [m/s].
    step : float
        Spacing [m/s] of the grid on which roots are bracketed and modes tracked. Two
        crossings closer than this are still found (see :mod:`whipple.stability.roots`).
    polish : bool
        Solve each root with ``casadi.rootfinder`` (default); otherwise bisection only.

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
                          step: float = 0.01, polish: bool = True, chunk_size: int = 256,
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
        Parameter sets of a 4-state model analysed together; scaled by 16 / n^2 for n states
        (bounds memory to about ``chunk_size * 1e4 / step`` bytes for 10 m/s).
    progress : callable, optional
        Called with the number of parameter sets finished after each chunk.

    Returns
    -------
    list of CriticalSpeeds
        One per parameter set, in C order of ``model.batch_shape``.
    """
    _check_interval(low, high, step)
    check_model(model)
    n, terms = model.n_states, model.A.shape[-3]
    coefficients = model.A.reshape(-1, terms, n, n)
    grid = tracking_grid(np.array([low, high], dtype=float), step)
    chunk_size = max(1, int(chunk_size * 16 / n**2))
    results: list[CriticalSpeeds] = []
    for start in range(0, coefficients.shape[0], chunk_size):
        chunk = coefficients[start:start + chunk_size]
        results += _analyse_chunk(chunk, grid, float(low), float(high), polish)
        if progress is not None:
            progress(len(results))
    return results


def _analyse_chunk(coefficients: NDArray[np.float64], grid: NDArray[np.float64], low: float,
                   high: float, polish: bool) -> list[CriticalSpeeds]:
    count, _, n, _ = coefficients.shape
    chunk_model = LinearModel(coefficients, np.zeros(coefficients.shape[:2] + (n, 1)))
    A = chunk_model.state_matrix(grid)
    tracked = tracked_eigenvalues(A, grid, vectors=False)
    size = np.max(np.linalg.norm(A, axis=(-2, -1)), axis=1) / np.sqrt(n)
    scale = np.asarray(2.0 ** np.round(np.log2(np.where(size > 0, size, 1.0))), dtype=float)
    inside = (grid >= low) & (grid <= high)
    crossings = []
    for kind in KINDS:
        values = condition(kind, tracked["eigenvalues"][:, inside] / scale[:, None, None])
        roots = find_roots(kind, coefficients, scale, grid[inside], values, polish)
        crossings.append(_verify(kind, roots, coefficients, tracked, grid))
    found = _safety_net(_merge(crossings), coefficients, tracked, grid, inside)
    directions = _directions(found, coefficients)
    segments = _stable_segments(found, coefficients, count, low, high)
    return [_package(found, directions, segments, index, low, high) for index in range(count)]


def _eigenvalues_at(coefficients: NDArray[np.float64], model: NDArray[np.intp],
                    speed: NDArray[np.float64]) -> NDArray[np.complex128]:
    if speed.size == 0:
        return np.zeros((0, coefficients.shape[-1]), dtype=complex)
    return np.asarray(np.linalg.eigvals(polynomial_matrices(coefficients[model], speed)),
                      dtype=complex)


def _nearest(values: NDArray[np.complex128], target: NDArray[np.complex128]) -> NDArray[np.intp]:
    return np.argmin(np.abs(values - target[:, None]), axis=-1)


def _verify(kind: str, roots: Roots, coefficients: NDArray[np.float64],
            tracked: dict[str, NDArray], grid: NDArray[np.float64]) -> dict[str, NDArray]:
    """Keep the roots where an eigenvalue is on the imaginary axis; name its mode."""
    lam = _eigenvalues_at(coefficients, roots.model, roots.speed)
    rows = np.arange(lam.shape[0])
    n = lam.shape[-1]
    if kind == "hopf":
        first, second = np.triu_indices(n, 1)
        pair = np.argmin(np.abs(lam[:, first] + lam[:, second]), axis=-1)
        one, other = lam[rows, first[pair]], lam[rows, second[pair]]
        value = np.where(one.imag > 0, one, other)
        genuine = np.abs(value.imag) > modes.REAL_TOLERANCE * (1.0 + np.abs(value))
        on_axis = np.abs(value.real)
    else:
        value = lam[rows, np.argmin(np.abs(lam), axis=-1)]
        genuine = np.abs(value.imag) <= modes.REAL_TOLERANCE * (1.0 + np.abs(value))
        on_axis = np.abs(value)
    touch = roots.method == "touch"
    genuine &= ~touch | (on_axis <= TOUCH_TOLERANCE * (1.0 + np.abs(value)))
    model, speed, value = roots.model[genuine], roots.speed[genuine], value[genuine]
    return {"model": model, "speed": speed, "value": value,
            "kind": np.full(speed.shape, kind), "method": roots.method[genuine],
            "mode": _mode_of(kind, model, speed, value, coefficients, tracked, grid)}


def _mode_of(kind: str, model: NDArray[np.intp], speed: NDArray[np.float64],
             value: NDArray[np.complex128], coefficients: NDArray[np.float64],
             tracked: dict[str, NDArray], grid: NDArray[np.float64]) -> NDArray[np.str_]:
    """Label of the crossing eigenvalue `value` at each root.

    The eigenvalues are tracked in a few small steps from the closest grid speed, where
    labels are known, to the root; there a weave-group eigenvalue is renamed by what it is
    at the root (complex: weave; real: upper or lower of the group's real ones).
    """
    if speed.size == 0:
        return np.zeros(0, dtype="<U16")
    after = np.clip(np.searchsorted(grid, speed), 1, grid.size - 1)
    index = np.where(np.abs(grid[after - 1] - speed) <= np.abs(grid[after] - speed),
                     after - 1, after)
    fractions = np.linspace(0.0, 1.0, MODE_SUBSTEPS + 1)[1:]
    path = grid[index, None] + (speed - grid[index])[:, None] * fractions
    walk = _eigenvalues_at(coefficients, np.repeat(model, fractions.size), path.ravel())
    walk = np.concatenate([tracked["eigenvalues"][model, index][:, None],
                           walk.reshape(speed.size, fractions.size, -1)], axis=1)
    order = modes.track(walk)
    rows = np.arange(speed.size)
    at_root = np.take_along_axis(walk[:, -1], order[:, -1], axis=-1)
    codes = np.take_along_axis(tracked["codes"][model, index], order[:, 0], axis=-1)
    branch = _nearest(at_root, value)
    code = codes[rows, branch]
    in_weave = codes <= modes.NAMES.index(modes.WEAVE_LOWER)
    real = np.abs(at_root.imag) <= modes.REAL_TOLERANCE * (1.0 + np.abs(at_root))
    higher = np.where(in_weave & real, at_root.real, -np.inf)
    ranked_first = np.sum(higher > higher[rows, branch][:, None], axis=-1) == 0
    renamed = np.where(~real[rows, branch], 0, np.where(ranked_first, 1, 2))
    code = np.where(in_weave[rows, branch], renamed, code)
    return modes.names(code)


def _merge(parts: list[dict[str, NDArray]]) -> dict[str, NDArray]:
    merged = {key: np.concatenate([part[key] for part in parts]) for key in parts[0]}
    order = np.lexsort((merged["speed"], merged["model"]))
    return {key: array[order] for key, array in merged.items()}


def _directions(found: dict[str, NDArray], coefficients: NDArray[np.float64]) -> NDArray[np.str_]:
    """Sign of the crossing eigenvalue's real part just below and above each root."""
    model, speed, value = found["model"], found["speed"], found["value"]
    if speed.size == 0:
        return np.zeros(0, dtype=str)
    same = np.concatenate([[False], model[1:] == model[:-1]])
    gap_below = np.where(same, np.diff(speed, prepend=-np.inf), np.inf)
    gap_above = np.concatenate([gap_below[1:], [np.inf]])
    gap = np.minimum(gap_below, gap_above)
    gap = np.where(gap > 0, gap, np.inf)
    delta = np.minimum(SIDE_STEP * (1.0 + np.abs(speed)), 0.25 * gap)
    below = _eigenvalues_at(coefficients, model, speed - delta)
    above = _eigenvalues_at(coefficients, model, speed + delta)
    rows = np.arange(speed.size)
    re_below = below[rows, _nearest(below, value)].real
    re_above = above[rows, _nearest(above, value)].real
    return np.select([(re_below < 0) & (re_above > 0), (re_below > 0) & (re_above < 0)],
                     ["destabilising", "stabilising"], default="touch")


def _stable_segments(found: dict[str, NDArray], coefficients: NDArray[np.float64],
                     model_count: int, low: float, high: float
                     ) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64],
                                NDArray[np.bool_]]:
    """Segments between consecutive crossings of every model and whether each is stable."""
    inside = (found["speed"] > low) & (found["speed"] < high)
    model = np.concatenate([found["model"][inside], np.arange(model_count),
                            np.arange(model_count)])
    knots = np.concatenate([found["speed"][inside], np.full(model_count, low),
                            np.full(model_count, high)])
    order = np.lexsort((knots, model))
    model, knots = model[order], knots[order]
    keep = np.concatenate([[True], (model[1:] != model[:-1]) | (knots[1:] != knots[:-1])])
    model, knots = model[keep], knots[keep]
    segment = model[1:] == model[:-1]
    seg_model, start, end = model[:-1][segment], knots[:-1][segment], knots[1:][segment]
    lam = _eigenvalues_at(coefficients, seg_model, 0.5 * (start + end))
    return seg_model, start, end, np.max(lam.real, axis=-1, initial=-np.inf) < 0


def _safety_net(found: dict[str, NDArray], coefficients: NDArray[np.float64],
                tracked: dict[str, NDArray], grid: NDArray[np.float64],
                inside: NDArray[np.bool_]) -> dict[str, NDArray]:
    """Locate changes of stability between grid points that no crossing explains."""
    speeds = grid[inside]
    lam = tracked["eigenvalues"][:, inside]
    largest = np.max(lam.real, axis=-1)
    clear = np.abs(largest) > 1e-12 * (1.0 + np.max(np.abs(lam), axis=-1))
    stable = largest < 0
    change = clear[:, :-1] & clear[:, 1:] & (stable[:, :-1] != stable[:, 1:])
    # Number of crossings found in each grid cell, from keys that sort by (model, speed).
    span = float(speeds[-1] - speeds[0]) + 1.0
    crossing_key = found["model"] * span + (found["speed"] - speeds[0])
    cell_key = np.arange(coefficients.shape[0])[:, None] * span + (speeds - speeds[0])
    position = np.searchsorted(crossing_key, cell_key)
    explained = np.searchsorted(crossing_key, cell_key[:, 1:], side="right") > position[:, :-1]
    model, index = np.nonzero(change & ~explained)
    if model.size == 0:
        return found
    a, b = speeds[index], speeds[index + 1]
    for _ in range(60):
        middle = 0.5 * (a + b)
        lam_mid = _eigenvalues_at(coefficients, model, middle)
        same = (np.max(lam_mid.real, axis=-1) < 0) == stable[model, index]
        a, b = np.where(same, middle, a), np.where(same, b, middle)
    speed = 0.5 * (a + b)
    lam_root = _eigenvalues_at(coefficients, model, speed)
    value = lam_root[np.arange(speed.size), np.argmin(np.abs(lam_root.real), axis=-1)]
    is_hopf = np.abs(value.imag) > modes.REAL_TOLERANCE * (1.0 + np.abs(value))
    value = np.where(is_hopf, value.real + 1j * np.abs(value.imag), value)
    mode = np.empty(speed.shape, dtype="<U16")
    for kind, mask in (("hopf", is_hopf), ("real", ~is_hopf)):
        mode[mask] = _mode_of(kind, model[mask], speed[mask], value[mask], coefficients,
                              tracked, grid)
    extra = {"model": model, "speed": speed, "value": value,
             "kind": np.where(is_hopf, "hopf", "real"),
             "method": np.full(speed.shape, "eigenvalue-bisection"), "mode": mode}
    return _merge([found, extra])


def _package(found: dict[str, NDArray], directions: NDArray[np.str_],
             segments: tuple[NDArray, ...], index: int, low: float, high: float
             ) -> CriticalSpeeds:
    """Assemble the result of model `index` from the chunk's flat arrays."""
    mine = found["model"] == index
    crossings = tuple(
        Crossing(float(speed), str(kind), str(mode), str(direction), complex(value),
                 str(method))
        for speed, kind, mode, direction, value, method in zip(
            found["speed"][mine], found["kind"][mine], found["mode"][mine], directions[mine],
            found["value"][mine], found["method"][mine], strict=True))
    seg_model, start, end, stable = segments
    ranges = tuple((float(a), float(b)) for a, b in zip(
        start[(seg_model == index) & stable], end[(seg_model == index) & stable], strict=True))
    weave = tuple(c.speed for c in crossings if c.mode == modes.WEAVE and c.kind == "hopf"
                  and c.direction != "touch")
    capsize = tuple(c.speed for c in crossings if c.mode == modes.CAPSIZE and c.kind == "real"
                    and c.direction != "touch")
    main = max(ranges, key=lambda r: r[1] - r[0]) if ranges else None
    # The main range's bounds by kind of crossing: with a controller the oscillatory and real
    # modes that bound it need not carry the uncontrolled bicycle's labels.
    hopf = {c.speed for c in crossings if c.kind == "hopf" and c.direction != "touch"}
    real = {c.speed for c in crossings if c.kind == "real" and c.direction != "touch"}
    weave_speed = main[0] if main and main[0] in hopf else (weave[0] if weave else None)
    capsize_speed = main[1] if main and main[1] in real else (capsize[0] if capsize else None)
    return CriticalSpeeds(low, high, crossings, weave, capsize, ranges, weave_speed,
                          capsize_speed)
