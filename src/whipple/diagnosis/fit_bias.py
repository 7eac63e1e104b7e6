"""The fitting function's bias: what a window's fit would report if a model were true.

A window's weave eigenvalue comes from fitting ``c1 + e^{dt} [c2 cos wt + c3 sin wt]`` (or a
polynomial baseline) to a response that also holds the model's other modes: the fast
castering mode, the slow capsize mode. The fit absorbs part of them into d and w. In simulated
hidden-effect trials this leaves the true model several times the windows' stated
uncertainty off where windows are long and precise (``benchmarks/bench_fit_bias.py``), and
that misfit is what makes a true cause look speed-dependent or leaves room for a wrong one.

A model can be compared with a window through the same function (indirect inference): its
prediction of the fitted eigenvalue is its weave eigenvalue plus the bias the fit shows on the
model's own free response over that window. The free response needs the window's modal
amplitudes, which are fitted to its samples; with the model's weave eigenvalue in that fit,
the other modes would mimic the difference between the model's weave and the window's (and
the window's noise), and the "bias" would swallow the model's error. So the amplitudes are
fitted with the weave at the window's own eigenvalue: the one whose response the fitted
function reports as the measured eigenvalue (a fixed point, ``FIXED_POINT_STEPS`` refits),
and the model's response is those amplitudes with the model's weave eigenvalue.

Used by :func:`whipple.diagnosis.evidence.diagnose_observations` (by default; ``bias=False``
compares the eigenvalues directly): see the research log
benchmarks/results/diagnosis-log.md, "The fitting function's bias".
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.observations import Observation, WindowSignals
from whipple.measurement.refit import refit_weaves
from whipple.model.assembly import linear_model
from whipple.model.fleet import Model, members_of
from whipple.model.parameters import Bicycle
from whipple.stability.nearest_modes import MODE_SHAPE_STATES, SHAPE_MATCH

#: Steps of the fixed point that finds a window's own weave eigenvalue (each a refit; the
#: bias changes by a small fraction of itself per step).
FIXED_POINT_STEPS = 3


def fitting_bias(bicycle: Model, observations: Sequence[Observation],
                 amplitudes: str = "own", start: str = "measured") -> NDArray[np.complex128]:
    """Return, per observation, the fitting function's bias [1/s] on the bicycle model's own response.

    Zero where a window's samples are unknown (:attr:`Observation.signals` is None), where a
    fitted signal is no state of the model, where no oscillatory mode of the model lies
    within ``SHAPE_MATCH`` of the measured eigenvalue, or where the refit fails or moves
    further than that (then the window's fit is no weave of this model to correct). All
    windows are refitted at once (:func:`~whipple.measurement.refit.refit_weaves`).

    ``amplitudes``: ``"own"`` (what the diagnosis uses) fits the modal amplitudes with the
    weave at the window's own eigenvalue (the module's fixed point); ``"model"`` with the
    model's weave. The latter is exact where the model is the truth, but lets the other modes
    absorb any other model's error; benchmarks use it on the true model of a simulated trial
    to see how much of the bias the fixed point misses (``benchmarks/bench_fit_bias.py``).
    ``start``: where the fixed point starts, the window's measured eigenvalue (``"measured"``,
    the default) or the model's weave (``"model"``, an experiment: benchmarks/results/diagnosis-log.md, "What the
    fixed point misses").
    """
    if start not in ("measured", "model"):
        raise ValueError(f"start must be 'measured' or 'model', got {start!r}")
    if not isinstance(bicycle, Bicycle):
        # An experiment's groups: each group's windows with its own bicycle.
        bias = np.zeros(len(observations), dtype=complex)
        for member, index in members_of(bicycle, [o.group for o in observations]):
            chosen = range(len(observations)) if index is None else index
            bias[list(chosen)] = fitting_bias(member, [observations[int(n)] for n in chosen], amplitudes, start)
        return bias
    if amplitudes not in ("own", "model"):
        raise ValueError(f"amplitudes must be 'own' or 'model', got {amplitudes!r}")
    bias = np.zeros(len(observations), dtype=complex)
    known = [n for n, o in enumerate(observations)
             if o.signals is not None and all(name in MODE_SHAPE_STATES for name in o.signals.names)]
    if not known:
        return bias
    speeds = bicycle.model_speed(np.array([observations[n].speed for n in known], dtype=float))
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        values, vectors = np.linalg.eig(linear_model(bicycle).state_matrix(speeds))
    windows = [window for k, n in enumerate(known)
               if (window := _model_weave(n, values[k], vectors[k], observations[n])) is not None]
    groups: dict[tuple[int, int], list[_Window]] = {}
    for window in windows:
        groups.setdefault((len(window.signals.names), window.pair.size), []).append(window)
    for members in groups.values():
        for window, found in zip(members, _Stack(members).bias(at_own=amplitudes == "own", start=start), strict=True):
            if np.isfinite(found) and abs(found) <= SHAPE_MATCH * abs(window.weave):
                bias[window.index] = found
    return bias


def debiased(observations: Sequence[Observation], bias: NDArray[np.complex128]) -> list[Observation]:
    """Return the observations with each eigenvalue less its fitting bias.

    What a model's own eigenvalue is compared with, for functions that take observations.
    """
    return [o if b == 0 else replace(o, eigenvalue=o.eigenvalue - complex(b))
            for o, b in zip(observations, bias, strict=True)]


@dataclass(frozen=True)
class _Window:
    """A window with the model's modes at its speed, its weave the mode nearest the measured eigenvalue."""

    index: int
    measured: complex
    weave: complex
    values: NDArray[np.complex128]
    vectors: NDArray[np.complex128]
    pair: NDArray[np.intp]
    signals: WindowSignals


def _model_weave(index: int, values: NDArray[np.complex128], vectors: NDArray[np.complex128],
                 observation: Observation) -> _Window | None:
    """Return the window with the model's weave, or None if no oscillatory mode lies near its eigenvalue."""
    if not (np.isfinite(values).all() and np.isfinite(vectors).all()):
        return None
    measured = observation.eigenvalue
    upper = np.where(values.imag < 0, np.conj(values), values)
    weave = complex(upper[int(np.argmin(np.abs(upper - measured)))])
    if weave.imag <= 0 or abs(weave - measured) > SHAPE_MATCH * abs(measured):
        return None
    assert observation.signals is not None
    pair = np.flatnonzero(np.abs(upper - weave) <= 1e-9 * abs(weave))
    return _Window(index, measured, weave, values, vectors, pair, observation.signals)


class _Stack:
    """Windows with the same number of signals and weave modes, their modal responses solved together.

    Padded with samples of weight zero to the longest window. The design's columns for the
    modes other than the weave, and for the signals' offsets, are the same in every response
    (only the weave's eigenvalue changes), so they are built once.
    """

    def __init__(self, windows: Sequence[_Window]) -> None:
        self.windows = windows
        count, length = len(windows[0].signals.names), max(window.signals.time.size for window in windows)
        self.sizes = np.array([window.signals.time.size for window in windows])
        self.tau = np.zeros((len(windows), length))
        self.mask = np.zeros((len(windows), length))
        targets = np.zeros((len(windows), count, length))
        for row, window in enumerate(windows):
            signals = window.signals
            self.tau[row, :signals.time.size] = signals.time - signals.time[0]
            self.mask[row, :signals.time.size] = 1.0
            targets[row, :, :signals.time.size] = signals.values
        self.spreads = np.std(targets, axis=2, where=self.mask[:, None, :].astype(bool))
        for row, window in enumerate(windows):
            if window.signals.weights is not None:
                # The signals as the window's fit weighed them (several signals: by their
                # residuals), in the modal amplitudes' fit as in the refit.
                with np.errstate(divide="ignore"):
                    self.spreads[row] = 1.0 / window.signals.weights
        rows = np.array([window.vectors[[MODE_SHAPE_STATES[name] for name in window.signals.names]]
                         for window in windows])
        others = np.array([np.setdiff1d(np.arange(window.values.size), window.pair) for window in windows])
        pairs = np.array([window.pair for window in windows])
        self.pair_rows = np.take_along_axis(rows, pairs[:, None, :], axis=2)
        self.pair_lower = np.array([window.values[window.pair].imag < 0 for window in windows])
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            self.targets = (targets / self.spreads[:, :, None]).reshape(len(windows), -1)
            offsets = np.zeros((len(windows), count, length, count))
            for k in range(count):
                offsets[:, k, :, k] = self.mask / self.spreads[:, k, None]
            other_values = np.array([window.values[other] for window, other in zip(windows, others, strict=True)])
            self.fixed = np.concatenate([self._mode_columns(np.arange(len(windows)), other_values,
                                                            np.take_along_axis(rows, others[:, None, :], axis=2)),
                                         offsets.reshape(len(windows), count * length, count)], axis=2)
        self.usable = (((self.spreads > 0) & np.isfinite(self.spreads)).all(axis=1)
                       & np.isfinite(self.fixed).all(axis=(1, 2)))

    def _mode_columns(self, members: NDArray[np.intp], modes: NDArray[np.complex128],
                      rows: NDArray[np.complex128]) -> NDArray[np.float64]:
        """Return design columns (M, k n, 2 m): each mode's time course times the signal's eigenvector entry.

        Real amplitudes of the complex modes: the real and (negated) imaginary part of each
        column; each signal weighted by the inverse of its spread; a padded sample's row zero.
        """
        courses = np.exp(self.tau[members, :, None] * modes[:, None, :]) * self.mask[members, :, None]
        blocks = []
        for k in range(rows.shape[1]):
            signal = courses * rows[:, k, None, :]
            blocks.append(np.concatenate([signal.real, -signal.imag], axis=2) / self.spreads[members, k, None, None])
        return np.concatenate(blocks, axis=1)

    def _weave_columns(self, members: NDArray[np.intp], eigenvalues: NDArray[np.complex128]) -> NDArray[np.float64]:
        modes = np.where(self.pair_lower[members], np.conj(eigenvalues)[:, None], eigenvalues[:, None])
        return self._mode_columns(members, modes, self.pair_rows[members])

    def responses(self, members: NDArray[np.intp], fitted: NDArray[np.complex128],
                  weaves: NDArray[np.complex128]) -> tuple[list[NDArray[np.float64]], NDArray[np.bool_]]:
        """Return free responses of the model with the modal amplitudes that best match each window's samples.

        The amplitudes are fitted with the weave at ``fitted`` and the response has it at
        ``weaves`` [1/s]. Each signal has its own constant (a sensor's offset, which the fitted
        function's baseline holds too). Also returns which responses are finite: a mode may
        grow beyond the arithmetic over a window.
        """
        with np.errstate(over="ignore", invalid="ignore"):
            fitted_design = np.concatenate([self._weave_columns(members, fitted), self.fixed[members]], axis=2)
            design = (fitted_design if weaves is fitted else
                      np.concatenate([self._weave_columns(members, weaves), self.fixed[members]], axis=2))
        finite = np.isfinite(fitted_design).all(axis=(1, 2)) & np.isfinite(design).all(axis=(1, 2))
        count = self.spreads.shape[1]
        coefficients = _minimum_norm(np.where(finite[:, None, None], fitted_design, 0.0), self.targets[members],
                                     self.sizes[members] * count)
        curves = (np.where(finite[:, None, None], design, 0.0) @ coefficients[:, :, None]).reshape(
            len(members), count, -1) * self.spreads[members, :, None]
        return [curve[:, :size] for curve, size in zip(curves, self.sizes[members], strict=True)], finite

    def _refits(self, members: NDArray[np.intp], fitted: NDArray[np.complex128], weaves: NDArray[np.complex128],
                starts: NDArray[np.complex128]) -> NDArray[np.complex128]:
        curves, finite = self.responses(members, fitted, weaves)
        windows = [self.windows[int(n)] for n in members]
        refitted = refit_weaves([window.signals.time for window in windows], curves, starts,
                                [window.signals.baseline for window in windows],
                                [window.signals.weights for window in windows])[0]
        return np.where(finite, refitted, np.nan)

    def bias(self, at_own: bool = True, start: str = "measured") -> NDArray[np.complex128]:
        """Return each window's fitting bias [1/s]: NaN where a response or refit failed.

        ``at_own``: modal amplitudes fitted with the window's own weave (else the model's).
        """
        found = np.full(len(self.windows), np.nan, dtype=complex)
        members = np.flatnonzero(self.usable)
        measured = np.array([window.measured for window in self.windows])
        weaves = np.array([window.weave for window in self.windows])
        # The window's own weave: the eigenvalue whose response (with the other modes as the
        # window holds them) the fitted function reports as the measured one.
        own = measured[members] if start == "measured" else weaves[members]
        for _ in range(FIXED_POINT_STEPS if at_own else 0):
            if members.size == 0:
                break
            refitted = self._refits(members, own, own, own)
            kept = np.isfinite(refitted)
            members, own = members[kept], measured[members[kept]] - (refitted[kept] - own[kept])
        model = weaves[members]
        if members.size:
            found[members] = self._refits(members, own if at_own else model, model, model) - model
        return found


def _minimum_norm(designs: NDArray[np.float64], targets: NDArray[np.float64], samples: NDArray[np.float64]
                  ) -> NDArray[np.float64]:
    """Return each design's minimum-norm least-squares solution, as ``numpy.linalg.lstsq`` would.

    Singular values below ``eps max(samples, columns)`` times the largest are dropped, as
    lstsq's default does with the window's own number of samples: the design of a model with
    complex pairs and real modes has dependent columns.
    """
    u, s, vh = np.linalg.svd(designs, full_matrices=False)
    cutoff = np.finfo(float).eps * np.maximum(samples, designs.shape[2])[:, None] * s[:, :1]
    inverse = np.divide(1.0, s, out=np.zeros_like(s), where=s > cutoff)
    projected = np.einsum("nrc,nr->nc", u, targets) * inverse
    return np.asarray(np.einsum("nci,nc->ni", vh, projected), dtype=float)
