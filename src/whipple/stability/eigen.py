"""Eigenvalues and modes of a linear bicycle model over forward speed.

:func:`eigen_analysis` computes the eigenvalues and eigenvectors of ``A(v)`` for many speeds
and many parameter sets in one batched ``numpy.linalg.eig`` call, follows each eigenvalue
continuously along the speed axis and names the modes (weave, capsize, castering, and the two
real modes that merge into the weave); see :mod:`whipple.stability.modes` for the rules. Tracking needs
neighbouring speeds to be close, so the analysis runs on the requested speeds merged with a
fine grid covering at least 0 to 10 m/s and returns the requested speeds only. Labels
therefore do not depend on which speeds were asked for.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import InputError
from whipple.model.linear import LinearModel, check_model
from whipple.model.physical_checks import MAX_SPEED
from whipple.stability import modes

__all__ = ["TRACKING_STEP", "TRACKING_SPAN", "GEOMETRIC_FROM", "RELATIVE_STEP", "EigenResult", "tracking_grid",
           "check_speeds", "tracked_eigenvalues", "eigen_analysis", "weave_eigenvalue", "eigenvalue_table"]

#: Largest speed step [m/s] of the grid on which eigenvalues are tracked.
TRACKING_STEP = 0.01
#: Speed span [m/s] always covered by the tracking grid, so labels are the same for any query.
TRACKING_SPAN = (0.0, 10.0)
#: Above this speed [m/s] the tracking grid's spacing grows in proportion to the speed ...
GEOMETRIC_FROM = 100.0
#: ... as this fraction of it: eigenvalues change by about as little from point to point,
#: and a grid to 10^6 m/s has some 2 x 10^4 points instead of 10^8.
RELATIVE_STEP = 1e-3


@dataclass(frozen=True)
class EigenResult:
    """Eigenvalues, eigenvectors and mode labels of a model over speed.

    Attributes
    ----------
    speeds : ndarray, shape (S,)
        Forward speeds [m/s], as requested.
    eigenvalues : ndarray, shape batch + (S, n), complex
        Eigenvalues [1/s]; column k follows one mode continuously over speed.
    eigenvectors : ndarray, shape batch + (S, n, n), complex, or None
        Unit eigenvectors as columns: ``eigenvectors[..., s, :, k]`` belongs to
        ``eigenvalues[..., s, k]``; state order and units as the model's states. None when
        not asked for (``eigen_analysis(..., vectors=False)``).
    labels : ndarray of str, shape batch + (S, n)
        Mode of each eigenvalue: ``weave``, ``weave_real_upper``, ``weave_real_lower``,
        ``capsize``, ``castering`` or ``mode_<column>``.
    state_names : tuple of str
        The model's state names (rows of the eigenvectors).
    """

    speeds: NDArray[np.float64]
    eigenvalues: NDArray[np.complex128]
    eigenvectors: NDArray[np.complex128] | None
    labels: NDArray[np.str_]
    state_names: tuple[str, ...] = ()

    def mode(self, name: str) -> NDArray[np.complex128]:
        """Return the eigenvalue [1/s] labelled `name` at each speed, NaN where there is none.

        Of a complex pair the member with positive imaginary part is returned; of several
        real eigenvalues with the same label, the one with the largest real part.

        Returns
        -------
        ndarray, shape batch + (S,), complex
        """
        match = self.labels == name
        key = np.where(match, self.eigenvalues.imag, -np.inf)
        key = np.where(match & (key == np.max(key, axis=-1, keepdims=True)),
                       self.eigenvalues.real, -np.inf)
        column = np.argmax(key, axis=-1)[..., None]
        value = np.take_along_axis(self.eigenvalues, column, axis=-1)[..., 0]
        return np.where(np.any(match, axis=-1), value, np.nan + 0j)


def _coordinate(v: NDArray[np.float64], step: float) -> NDArray[np.float64]:
    """Grid coordinate: uniform in v up to GEOMETRIC_FROM (unit `step`), in log(v) beyond."""
    size = np.abs(v)
    beyond = GEOMETRIC_FROM / step + np.log(np.maximum(size, GEOMETRIC_FROM) / GEOMETRIC_FROM) / RELATIVE_STEP
    return np.sign(v) * np.where(size <= GEOMETRIC_FROM, size / step, beyond)


def _speed(u: NDArray[np.float64], step: float) -> NDArray[np.float64]:
    """Inverse of :func:`_coordinate`."""
    size = np.abs(u)
    edge = GEOMETRIC_FROM / step
    beyond = GEOMETRIC_FROM * np.exp((np.maximum(size, edge) - edge) * RELATIVE_STEP)
    return np.sign(u) * np.where(size <= edge, size * step, beyond)


def tracking_grid(speeds: NDArray[np.float64], step: float = TRACKING_STEP) -> NDArray[np.float64]:
    """Return the speeds [m/s] on which eigenvalues are tracked.

    The sorted union of `speeds` with a grid over their span extended to
    :data:`TRACKING_SPAN`: spacing at most 1.25 `step` [m/s] up to :data:`GEOMETRIC_FROM`, and
    :data:`RELATIVE_STEP` times the speed beyond, so that its size stays bounded (some 2 x 10^4
    points up to :data:`MAX_SPEED` on top of those below).

    Raises
    ------
    InputError
        For speeds beyond :data:`MAX_SPEED`.
    """
    low = min(float(np.min(speeds)), TRACKING_SPAN[0])
    high = max(float(np.max(speeds)), TRACKING_SPAN[1])
    if max(-low, high) > MAX_SPEED:
        raise InputError(f"speeds beyond {MAX_SPEED:g} m/s are not analysed, got {max(-low, high):g} m/s")
    knots = np.unique(np.concatenate([speeds, [low, high]]))
    gaps = np.diff(knots)
    u = _coordinate(knots, step)
    # Gaps up to 1.25 steps are kept whole, so a user grid close to the step is not doubled.
    pieces = np.maximum(np.ceil(np.diff(u) - 0.25).astype(int), 1)
    starts = np.repeat(knots[:-1], pieces)
    offsets = np.arange(pieces.sum()) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    linear = starts + offsets * np.repeat(gaps / pieces, pieces)
    if max(-low, high) <= GEOMETRIC_FROM:
        return np.concatenate([linear, knots[-1:]])
    # Beyond GEOMETRIC_FROM the points are uniform in the grid coordinate instead.
    curved = _speed(np.repeat(u[:-1], pieces) + offsets * np.repeat(np.diff(u) / pieces, pieces), step)
    flat = np.repeat((np.abs(knots[:-1]) <= GEOMETRIC_FROM) & (np.abs(knots[1:]) <= GEOMETRIC_FROM), pieces)
    grid = np.where(flat, linear, curved)
    return np.concatenate([grid, knots[-1:]])


def check_speeds(speeds: ArrayLike) -> NDArray[np.float64]:
    """Speeds [m/s] as a finite 1-D float array; InputError otherwise."""
    array = np.atleast_1d(np.asarray(speeds, dtype=float))
    if array.ndim != 1 or array.size == 0:
        raise InputError(f"speeds must be a non-empty 1-D sequence, got shape {array.shape}")
    if not np.all(np.isfinite(array)):
        raise InputError("speeds must be finite numbers")
    return array


def tracked_eigenvalues(
    A: NDArray[np.float64], grid: NDArray[np.float64], vectors: bool
) -> dict[str, Any]:
    """Eigen-decompose, track and label state matrices on an increasing speed grid.

    Parameters
    ----------
    A : ndarray, shape (B, G, n, n)
        State matrices [1/s] of B models at the G speeds of `grid` [m/s].
    vectors : bool
        Also return all eigenvectors (otherwise a tenth of them are computed, for labels).

    Returns
    -------
    dict
        ``eigenvalues`` (B, G, n), ``codes`` (B, G, n) of the labels (see
        :func:`whipple.stability.modes.names`), and when `vectors` is true
        ``eigenvectors`` (B, G, n, n), all in display order.
    """
    n = A.shape[-1]
    if vectors:
        values, vecs = np.linalg.eig(A)
        amplitude = np.abs(vecs[..., :2, :])
    else:
        values = np.linalg.eigvals(A)
        # Eigenvectors only enter the labels through a mean over speed: a tenth of the
        # speeds is plenty and saves most of the cost of computing them.
        sub = np.arange(0, grid.size, 10)
        sub_values, sub_vecs = np.linalg.eig(A[:, sub])
        values[:, sub] = sub_values
        amplitude = np.full(values.shape[:2] + (2, n), np.nan)
        amplitude[:, sub] = np.abs(sub_vecs[..., :2, :])
    with np.errstate(invalid="ignore", divide="ignore"):
        roll_share = amplitude[..., 0, :] / (amplitude[..., 0, :] + amplitude[..., 1, :])
    order = modes.track(values)
    columns, codes = modes.label(modes.reorder(values, order), modes.reorder(roll_share, order), grid)
    # One gather from eig's order to display order: branch order, then label order.
    full = modes.reorder(order, columns[:, None, :])
    result: dict[str, Any] = {"eigenvalues": modes.reorder(values, full), "codes": codes}
    if vectors:
        result["eigenvectors"] = modes.reorder(vecs, full[..., None, :])
    return result


def eigen_analysis(model: LinearModel, speeds: ArrayLike, *, vectors: bool = True) -> EigenResult:
    """Eigenvalues, eigenvectors and mode labels of `model` at forward speeds.

    Parameters
    ----------
    model : LinearModel
        One model or a batch of parameter sets (``model.batch_shape``).
    speeds : array_like, shape (S,)
        Forward speeds [m/s], in any order.
    vectors : bool, optional
        Return the eigenvectors at every speed (default). Without them (tables, plots, the
        weave eigenvalue) the analysis costs little more than the eigenvalues alone: the labels
        need eigenvectors at a tenth of the speeds only.

    Returns
    -------
    EigenResult
        Arrays of shape ``model.batch_shape + (S, ...)``.

    Raises
    ------
    InputError
        If the speeds or the model's matrices are not finite.
    """
    speeds = check_speeds(speeds)
    check_model(model)
    grid = tracking_grid(speeds)
    batch, n = model.batch_shape, model.n_states
    A = model.state_matrix(grid).reshape(-1, grid.size, n, n)
    analysed = tracked_eigenvalues(A, grid, vectors=vectors)
    if speeds.size == grid.size and np.array_equal(speeds, grid):
        picked = analysed  # the requested speeds are the tracking grid: no copies
    else:
        index = np.clip(np.searchsorted(grid, speeds), 0, grid.size - 1)
        picked = {key: value[:, index] for key, value in analysed.items()}
    return EigenResult(
        speeds=speeds,
        eigenvalues=picked["eigenvalues"].reshape(batch + (speeds.size, n)),
        eigenvectors=picked["eigenvectors"].reshape(batch + (speeds.size, n, n)) if vectors else None,
        labels=modes.names(picked["codes"]).reshape(batch + (speeds.size, n)),
        state_names=model.state_names,
    )


def weave_eigenvalue(model: LinearModel, speeds: ArrayLike) -> NDArray[np.complex128]:
    """Return the weave eigenvalue [1/s] (positive imaginary part) at forward speeds [m/s].

    Parameters
    ----------
    model : LinearModel
        The model (one parameter set or a batch).
    speeds : array_like, shape (S,)
        Forward speeds [m/s].

    Returns
    -------
    ndarray, shape ``model.batch_shape + (S,)``, complex
        NaN where the weave is not oscillatory (below the speed where it forms).
    """
    return eigen_analysis(model, speeds, vectors=False).mode(modes.WEAVE)


def eigenvalue_table(result: EigenResult) -> tuple[list[str], list[list[Any]]]:
    """Rows of a table of eigenvalues versus speed, for CSV export.

    Parameters
    ----------
    result : EigenResult
        The analysis of a single model (no batch).

    Returns
    -------
    header : list of str
        ``speed_m_per_s``, then for each column k ``eig<k>_real_per_s``,
        ``eig<k>_imag_per_s`` and ``eig<k>_mode``.
    rows : list of list
        One row per speed: the speed [m/s], then real part [1/s], imaginary part [1/s] and
        label of each eigenvalue.
    """
    if result.eigenvalues.ndim != 2:
        raise ValueError("eigenvalue_table needs the analysis of a single model, not a batch")
    n = result.eigenvalues.shape[-1]
    header = ["speed_m_per_s"]
    for k in range(1, n + 1):
        header += [f"eig{k}_real_per_s", f"eig{k}_imag_per_s", f"eig{k}_mode"]
    rows = []
    for s, speed in enumerate(result.speeds.tolist()):
        row: list[Any] = [speed]
        for value, name in zip(result.eigenvalues[s].tolist(), result.labels[s].tolist(),
                               strict=True):
            row += [value.real, value.imag, name]
        rows.append(row)
    return header, rows
