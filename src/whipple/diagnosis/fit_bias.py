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
compares the eigenvalues directly): see docs/diagnosis.md, "The fitting function's bias".
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.observations import MODE_SHAPE_STATES, SHAPE_MATCH, Observation, WindowSignals
from whipple.errors import InputError
from whipple.measurement.weavefit import NoOscillationError, refit_weave
from whipple.model.assembly import linear_model
from whipple.model.parameters import Bicycle

#: Steps of the fixed point that finds a window's own weave eigenvalue (each a refit; the
#: bias changes by a small fraction of itself per step).
FIXED_POINT_STEPS = 3


def fitting_bias(bicycle: Bicycle, observations: Sequence[Observation]) -> NDArray[np.complex128]:
    """Return, per observation, the fitting function's bias [1/s] on the bicycle model's own response.

    Zero where a window's samples are unknown (:attr:`Observation.signals` is None), where a
    fitted signal is no state of the model, where no oscillatory mode of the model lies
    within ``SHAPE_MATCH`` of the measured eigenvalue, or where the refit fails or moves
    further than that (then the window's fit is no weave of this model to correct).
    """
    bias = np.zeros(len(observations), dtype=complex)
    known = [n for n, o in enumerate(observations)
             if o.signals is not None and all(name in MODE_SHAPE_STATES for name in o.signals.names)]
    if not known:
        return bias
    speeds = bicycle.model_speed(np.array([observations[n].speed for n in known], dtype=float))
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        values, vectors = np.linalg.eig(linear_model(bicycle).state_matrix(speeds))
    for k, n in enumerate(known):
        bias[n] = _window_bias(values[k], vectors[k], observations[n])
    return bias


def debiased(observations: Sequence[Observation], bias: NDArray[np.complex128]) -> list[Observation]:
    """Return the observations with each eigenvalue less its fitting bias.

    What a model's own eigenvalue is compared with, for functions that take observations.
    """
    return [o if b == 0 else replace(o, eigenvalue=o.eigenvalue - complex(b))
            for o, b in zip(observations, bias, strict=True)]


def _window_bias(values: NDArray[np.complex128], vectors: NDArray[np.complex128], observation: Observation) -> complex:
    """Return the bias of one window, given the model's eigenvalues and eigenvectors at its speed."""
    if not (np.isfinite(values).all() and np.isfinite(vectors).all()):
        return 0.0j
    measured = observation.eigenvalue
    upper = np.where(values.imag < 0, np.conj(values), values)
    nearest = int(np.argmin(np.abs(upper - measured)))
    weave = complex(upper[nearest])
    if weave.imag <= 0 or abs(weave - measured) > SHAPE_MATCH * abs(measured):
        return 0.0j
    signals = observation.signals
    assert signals is not None
    pair = np.flatnonzero(np.abs(upper - weave) <= 1e-9 * abs(weave))

    def with_weave(eigenvalue: complex) -> NDArray[np.complex128]:
        changed = values.copy()
        changed[pair] = np.where(values[pair].imag < 0, np.conj(eigenvalue), eigenvalue)
        return changed

    try:
        # The window's own weave, found as the eigenvalue whose response (with the other modes
        # as the window holds them) the fitted function reports as the measured one.
        own = measured
        for _ in range(FIXED_POINT_STEPS):
            modes = with_weave(own)
            response = _modal_response(modes, modes, vectors, signals)
            own = measured - (refit_weave(signals.time, response, own, signals.baseline) - own)
        response = _modal_response(with_weave(own), values, vectors, signals)
        fitted = refit_weave(signals.time, response, weave, signals.baseline)
    except InputError:
        return 0.0j
    bias = fitted - weave
    return bias if np.isfinite(bias) and abs(bias) <= SHAPE_MATCH * abs(weave) else 0.0j


def _modal_response(fitted_values: NDArray[np.complex128], values: NDArray[np.complex128],
                    vectors: NDArray[np.complex128], signals: WindowSignals) -> NDArray[np.float64]:
    """Return a free response of the model with the modal amplitudes that best match the window's samples.

    The amplitudes are fitted with the modes ``fitted_values``, and the response has the modes
    ``values`` (the same but for the weave's eigenvalue; given the same array, its columns are
    built once). Each signal is weighted by the inverse of its standard deviation and has its
    own constant (a sensor's offset, which the fitted function's baseline holds too).

    Raises
    ------
    NoOscillationError
        If a signal is constant or a mode grows beyond the arithmetic over the window.
    """
    tau = signals.time - signals.time[0]
    with np.errstate(over="ignore", invalid="ignore"):
        fitted_modes = np.exp(np.outer(tau, fitted_values))
        modes = fitted_modes if values is fitted_values else np.exp(np.outer(tau, values))
    if not (np.isfinite(fitted_modes).all() and np.isfinite(modes).all()):
        raise NoOscillationError("a mode grows beyond the arithmetic over the window")
    count = len(signals.names)
    fitted_blocks: list[NDArray[np.float64]] = []
    blocks: list[NDArray[np.float64]] = []
    targets, spreads = [], []
    for k, name in enumerate(signals.names):
        measured = signals.values[k]
        spread = float(np.std(measured))
        if spread == 0.0:
            raise NoOscillationError("a signal is constant over the window")
        offsets = np.zeros((tau.size, count))
        offsets[:, k] = 1.0
        row = vectors[MODE_SHAPE_STATES[name]]
        fitted_blocks.append(_columns(fitted_modes, row, offsets) / spread)
        blocks.append(fitted_blocks[-1] if modes is fitted_modes else _columns(modes, row, offsets) / spread)
        targets.append(measured / spread)
        spreads.append(spread)
    coefficients = np.linalg.lstsq(np.vstack(fitted_blocks), np.concatenate(targets), rcond=None)[0]
    response = np.vstack(blocks) @ coefficients
    return np.array([response[k * tau.size:(k + 1) * tau.size] * spreads[k] for k in range(count)])


def _columns(modes: NDArray[np.complex128], row: NDArray[np.complex128], offsets: NDArray[np.float64]
             ) -> NDArray[np.float64]:
    """Return one signal's design columns: each mode's time course times the signal's eigenvector entry, then offsets.

    Real amplitudes of the complex modes: the real and (negated) imaginary part of each column.
    """
    signal = modes * row[None, :]
    return np.hstack([signal.real, -signal.imag, offsets])
