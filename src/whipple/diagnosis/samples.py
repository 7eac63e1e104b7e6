"""Models compared with the windows' samples: each window's free response of the model, fitted.

A window holds free coasting: on a treadmill, the solution ``x(t) = sum_j a_j v_j e^{lambda_j t}``
of the linear model at the window's speed, seen through the fitted signals (roll rate, steer
angle: states of the model) with sensor noise and offsets. A model is compared with a window by
fitting that solution to the samples: the model's eigenvalues ``lambda_j`` and eigenvectors
``v_j`` fixed, the modal amplitudes ``a_j`` (the window's initial state) and each signal's
offset fitted by linear least squares, each signal weighed by its noise. What is left is the
model's residual on every sample.

On the ground, where a window's speed changes (its measured acceleration), the bicycle is a
linear time-varying system along the window's speed profile: the model's response
``x(t) = Phi(t, 0) x0`` follows that profile, with the window's initial state ``x0`` fitted in
place of the modal amplitudes (:meth:`SampleComparison._changing_designs`). Windows at constant
speed keep the modal response, to the last bit. A model with more states than the bicycle's four
starts every window on its four slowest modes (:func:`slowest_modes`), as many amplitudes as every
model fits; where another of its modes grows, a window either shows it and fits its amplitudes
too, or cannot have come from the model (:mod:`whipple.diagnosis.growing_modes`).

This uses every mode the samples hold (the weave, and the castering and capsize modes the
seed paper's function leaves out) and ties the signals together through the model's mode
shapes; it needs no fitting function between model and data, so there is no fitting bias to
correct (:mod:`whipple.diagnosis.fit_bias`). On simulated runs the true model leaves each
clean window at its noise (chi-square per sample 1.0), and windows that eigenvalues alone
cannot tell apart (a steer inertia from a front wheel's inertia, a rack load from a heavier
rear frame) differ in their samples (docs/diagnosis.md).

Each signal's noise is estimated from the window's second differences
(:func:`whipple.measurement.noise.second_difference_noise`: robust to spikes, at least the
rounding's noise for a signal recorded in steps); a window that the fitting function leaves far
off counts less (:func:`~whipple.diagnosis.window_bins.signal_noise`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.growing_modes import fitted_modes, orthonormal_columns, resolved, shown_growth
from whipple.diagnosis.instrument import InstrumentErrors, profiled_residuals, yaw_gains, yaw_row
from whipple.diagnosis.observations import Observation, friction_gains, noise_free
from whipple.diagnosis.window_bins import BIN_DURATION, binned_window
from whipple.diagnosis.window_speed import window_speeds
from whipple.model.assembly import linear_model
from whipple.model.fleet import Model, members_of
from whipple.model.linear import LinearModel
from whipple.model.parameters import Bicycle
from whipple.stability.nearest_modes import MODE_SHAPE_STATES, window_state_matrices, window_steer_damping
from whipple.stability.slow_modes import FITTED_MODES, dropped_modes, lower_members

#: A window's residual on every sample [noise standard deviations] where a model cannot hold it:
#: its response overflows, or a fast mode grows that the window does not show
#: (:func:`~whipple.diagnosis.growing_modes.shown_growth`).
OVERFLOW_MISFIT = 1e3
#: Where a window's speed changes, the model's response is built over pieces of about this
#: duration [s] (whole bins), each frozen at the speed of its middle. The error falls with the
#: square of the piece's length (the frozen matrix within a piece, not the steps between pieces:
#: a fourth-order Magnus step gained nothing). Against pieces of one bin (0.04 s), on three
#: simulated no-effect ground trials (45 windows, 0.02-0.08 m/s^2), pieces of 0.2 s moved the
#: base model's residuals by 0.004-0.022 RMS (at most 0.31) in units of the noise and its
#: chi-square by 0.3-1.0 of about 1600-2800; pieces of 0.4 s by up to 6.4.
PIECE_DURATION = 0.2


@dataclass(frozen=True)
class _Pieces:
    """The pieces each window's response is built over, padded to the most pieces: (W, P), bins (W, P, g).

    ``starts``: each piece's first sample from the window's first sample [s]; ``spans``: from
    there to the end of its last bin [s]; ``lengths``: to the next piece's start [s] (the last
    piece: its span); ``offsets``: each of its g bins' first sample from its start [s];
    ``real``: which pieces the window holds (the rest pad it).
    """

    starts: NDArray[np.float64]
    spans: NDArray[np.float64]
    lengths: NDArray[np.float64]
    offsets: NDArray[np.float64]
    real: NDArray[np.bool_]


@dataclass(frozen=True)
class SampleComparison:
    """The windows' samples, stacked (padded to the longest window) for comparing models with them.

    Attributes
    ----------
    speeds : ndarray, shape (W,)
        The measured speed each window's model is evaluated at [m/s]: its mean, or where its
        speed changes the speed a fit reads (:func:`~whipple.diagnosis.window_speed.window_speeds`).
    tau : ndarray, shape (W, L)
        Each bin's first sample time from the window's first sample [s] (0 where padded).
    mask : ndarray of bool, shape (W, L)
        Which bins are real (the rest pad shorter windows).
    targets : ndarray, shape (W, k, L)
        The k fitted signals of each window averaged per bin, each divided by its noise (0 where
        padded).
    noise : ndarray, shape (W, k)
        Each signal's noise averaged per bin (its unit; :func:`second_difference_noise` of the
        samples over the square root of the bin's size).
    states : tuple of int
        The model state of each signal (:data:`~whipple.stability.nearest_modes.MODE_SHAPE_STATES`).
    names : tuple of str
        The signals' names.
    bins, steps : ndarray, shape (W,)
        Samples per bin and the sampling interval [s] of each window (None: one sample a bin).
    groups : tuple of str or None
        Each window's group (a model that is a fleet).
    friction : ndarray, shape (W,), or None
        Each window's equivalent steer damping per unit Coulomb steer friction [s/rad]
        (:func:`~whipple.diagnosis.observations.friction_gains`): a model with a steer friction
        has that damping times its friction added at the window.
    accelerations : ndarray, shape (W,), or None
        Each window's measured forward acceleration [m/s^2], which adds ``v' Ka q`` to the
        model's equations; None where every window's speed is constant.
    profiles : ndarray, shape (W, 2), or None
        Where the speed changes, each window's measured speed profile ``v(t) = v_c + v' (t - t_c)``:
        the regression's speed at its centre ``v_c`` [m/s] and that centre ``t_c`` from the
        window's first sample [s]; the model follows it (:meth:`_changing_designs`). None where
        every window's speed is constant.
    instrument : InstrumentErrors or None
        The roll gyro's scale and misalignment fitted with every model, shared by all windows
        (:mod:`whipple.diagnosis.instrument`); None: the signals are taken as read.
    """

    speeds: NDArray[np.float64]
    tau: NDArray[np.float64]
    mask: NDArray[np.bool_]
    targets: NDArray[np.float64]
    noise: NDArray[np.float64]
    states: tuple[int, ...]
    names: tuple[str, ...]
    bins: NDArray[np.int_] | None = None
    steps: NDArray[np.float64] | None = None
    groups: tuple[str, ...] | None = None
    friction: NDArray[np.float64] | None = None
    accelerations: NDArray[np.float64] | None = None
    profiles: NDArray[np.float64] | None = None
    instrument: InstrumentErrors | None = None

    @classmethod
    def of(cls, observations: Sequence[Observation], binned: bool = True,
           bicycle: Model | None = None, instrument: InstrumentErrors | None = None) -> SampleComparison | None:
        """Return the samples of the observations, or None where they cannot be compared so.

        None where a window's samples are unknown (windows read from a list of eigenvalues),
        where the windows fitted different signals, or where a signal is no state of the models.
        ``binned``: averaged in bins of about ``BIN_DURATION`` (else every sample on its own).
        ``bicycle``: the model whose mode shape gives the steer amplitude of windows without a
        steer angle (:func:`~whipple.diagnosis.observations.friction_gains`). ``instrument``: the
        roll gyro's errors fitted with every model (None: not).
        """
        if not observations or any(o.signals is None for o in observations):
            return None
        names = observations[0].signals.names  # type: ignore[union-attr]
        if any(o.signals.names != names for o in observations) or not all(  # type: ignore[union-attr]
                name in MODE_SHAPE_STATES for name in names):
            return None
        duration = BIN_DURATION if binned else 0.0
        bins_of = [binned_window(o.signals, duration) for o in observations]  # type: ignore[arg-type]
        length, count = max(b[0].size for b in bins_of), len(names)
        tau = np.zeros((len(observations), length))
        mask = np.zeros((len(observations), length), dtype=bool)
        targets = np.zeros((len(observations), count, length))
        noise = np.zeros((len(observations), count))
        bins = np.ones(len(observations), dtype=int)
        steps = np.zeros(len(observations))
        for row, (times, means, window_noise, size, step) in enumerate(bins_of):
            tau[row, :times.size] = times
            mask[row, :times.size] = True
            noise[row] = window_noise
            targets[row, :, :times.size] = means / window_noise[:, None]
            bins[row], steps[row] = size, step
        speeds, accelerations = window_speeds(observations)
        profiles = None if accelerations is None else np.array(
            [(o.speed, 0.5 * (o.start + o.stop) - float(o.signals.time[0])) for o in observations])  # type: ignore[union-attr]
        return cls(speeds, tau, mask, targets, noise, tuple(MODE_SHAPE_STATES[name] for name in names), names,
                   bins, steps, tuple(o.group for o in observations), friction_gains(observations, bicycle),
                   accelerations, profiles, instrument)

    @property
    def samples(self) -> int:
        """Number of residuals a model leaves: every bin of every signal."""
        return int(self.mask.sum()) * len(self.states)

    def window_of_residuals(self) -> NDArray[np.intp]:
        """Return the window of each residual, in :meth:`residuals`' order."""
        windows = np.repeat(np.arange(self.mask.shape[0])[:, None, None], len(self.states), axis=1)
        windows = np.broadcast_to(windows, (self.mask.shape[0], len(self.states), self.mask.shape[1]))
        return np.asarray(windows[self._residual_mask()], dtype=np.intp)

    def _residual_mask(self) -> NDArray[np.bool_]:
        return np.broadcast_to(self.mask[:, None, :], self.targets.shape)

    def residuals(self, models: Sequence[Model], linear: Sequence[LinearModel | None] | None = None
                  ) -> NDArray[np.float64]:
        """Return each model's residual on every sample, in units of the noise; shape (models, samples).

        Per window, the model's free response at the window's speed (``speed_scale`` applied),
        fitted by least squares with each signal's offset: at constant speed its modal
        amplitudes, where the speed changes its initial state, the response following the
        window's speed profile with ``v' Ka q`` (:meth:`_changing_designs`).
        ``linear``: the models' linear models where they are not the bicycles' own (a
        hidden-effect trial's true model); None entries are the bicycles'. A window where the
        model's response overflows (a mode growing beyond the arithmetic) gets residuals of
        1e3 on every sample.
        """
        linear = [None] * len(models) if linear is None else list(linear)
        plain = [model for model in models if isinstance(model, Bicycle)]
        if len(plain) < len(models):
            return self._fleet_residuals(models, linear)
        given = [linear_model(bicycle) if model is None else model
                 for bicycle, model in zip(plain, linear, strict=True)]
        changing = self._changing()
        constant, varying = np.flatnonzero(~changing), np.flatnonzero(changing)
        parts: dict[int, list[tuple[NDArray[np.intp], list[int], NDArray[np.float64], NDArray[np.bool_]]]] = {}
        for index, follows in ((constant, False), (varying, True)):
            if not index.size:
                continue
            part = self if index.size == changing.size else self._subset(index)
            built = part._changing_designs(plain, given) if follows else part._frozen_designs(plain, given)
            for states, (members, design, growing) in built.items():
                parts.setdefault(states, []).append((index, members, design, growing))
        residual = np.zeros((len(models), *self.targets.shape))
        for batch in parts.values():
            members = batch[0][1]
            # The constant-speed and the changing windows may fit different numbers of growing
            # modes: the fewer are padded with columns of zeros.
            columns = max(part[2].shape[-1] for part in batch)
            design = np.zeros((len(members), changing.size, *batch[0][2].shape[2:-1], columns))
            growing = np.zeros((len(members), changing.size), dtype=bool)
            for index, _, part_design, part_growing in batch:
                design[:, index, ..., :part_design.shape[-1]] = part_design
                growing[:, index] = part_growing
            with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
                residual[members] = self._held_residuals(design, growing)
        return residual[:, self._residual_mask()]

    def _held_residuals(self, design: NDArray[np.float64], growing: NDArray[np.bool_]) -> NDArray[np.float64]:
        """Residuals (M, W, k, L) of M models' designs (M, W, k', L, n'), growing fast modes fitted where shown.

        ``growing`` (M, W): where a mode beyond the slowest grows, whose amplitudes the columns
        beyond the first :data:`FITTED_MODES` hold. They are kept in the windows that show the
        mode (:func:`~whipple.diagnosis.growing_modes.shown_growth`) and dropped elsewhere; a
        model whose growing mode no window shows cannot hold the windows where it grows.
        """
        plain = self._fitted_residuals(design[..., :FITTED_MODES])
        if not growing.any():
            return plain
        samples = self.mask.sum(axis=1) * len(self.states)
        shown = shown_growth(growing, self._fitted_residuals(design), plain, samples)
        residual = plain
        if shown.any():
            residual = self._fitted_residuals(np.where(shown[..., None, None, None], design,
                                                       design * (np.arange(design.shape[-1]) < FITTED_MODES)))
        residual[growing & ~np.any(shown, axis=-1, keepdims=True)] = OVERFLOW_MISFIT
        return residual

    def _changing(self) -> NDArray[np.bool_]:
        """Return which windows' speed changes (W,): those the model follows along their speed profile."""
        if self.accelerations is None or self.profiles is None:
            return np.zeros(self.mask.shape[0], dtype=bool)
        return np.asarray(self.accelerations != 0, dtype=bool)

    def _frozen_designs(self, bicycles: Sequence[Bicycle], models: Sequence[LinearModel]
                        ) -> dict[int, tuple[list[int], NDArray[np.float64], NDArray[np.bool_]]]:
        """Designs of the models frozen at each window's speed, by number of states: members, (M, W, k', L, n').

        Columns: the responses of the modes :func:`~whipple.diagnosis.growing_modes.fitted_modes`
        picks, in units of the noise, in the rows of :meth:`_signal_rows`. Also where a mode
        beyond the slowest grows (M, W).
        """
        matrices = [self._state_matrices(bicycle, model) for bicycle, model in zip(bicycles, models, strict=True)]
        result: dict[int, tuple[list[int], NDArray[np.float64], NDArray[np.bool_]]] = {}
        # Models with as many states are evaluated together: one evaluation of all their windows.
        for states in sorted({matrix.shape[-1] for matrix in matrices}):
            members = [k for k, matrix in enumerate(matrices) if matrix.shape[-1] == states]
            stacked = np.concatenate([matrices[k] for k in members])  # (members * W, n, n)
            with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
                values, vectors = np.linalg.eig(stacked)
                repeated = self._repeated(len(members))
                speeds = np.concatenate([bicycles[k].model_speed(self.speeds) for k in members])
                yaw = np.concatenate([np.broadcast_to(yaw_gains(bicycles[k]), (self.speeds.size, 2))
                                      for k in members])
                rows = self._signal_rows(vectors, speeds, yaw) * repeated._bin_factors(values)[:, None, :]
                # Each mode's column is its own: build those fitted alone.
                kept, real = fitted_modes(values)
                growing = np.any(real[:, FITTED_MODES:], axis=-1)  # a growing mode's column is real
                values, rows = np.take_along_axis(values, kept, -1), np.take_along_axis(rows, kept[:, None], -1)
                # A growing mode the bins cannot resolve: no window shows it (its column is 0).
                real[:, FITTED_MODES:] &= resolved(values[:, FITTED_MODES:], repeated.steps, repeated.bins)
                design = repeated._modal_design(values, rows) * real[:, None, None, :]
            result[states] = (members, design.reshape(len(members), *self.mask.shape[:1], *design.shape[1:]),
                              growing.reshape(len(members), -1))
        return result

    def _signal_rows(self, vectors: NDArray[np.complex128], speeds: NDArray[np.float64],
                     yaw: NDArray[np.float64]) -> NDArray[np.complex128]:
        """Return the rows (..., k', n) of the signals in the eigenvectors (..., n, n), the yaw rate's last if fitted.

        ``speeds`` (...) [m/s] and ``yaw`` (..., 2): :func:`~whipple.diagnosis.instrument.yaw_row`'s.
        """
        rows = vectors[..., list(self.states), :]
        if self.instrument_row() is None:
            return rows
        return np.concatenate([rows, yaw_row(vectors, speeds, yaw)[..., None, :]], axis=-2)

    def instrument_row(self) -> int | None:
        """Return the roll rate's row whose instrument errors are fitted, None where they are not."""
        return None if self.instrument is None or "roll_rate" not in self.names else self.names.index("roll_rate")

    def _row_noise(self) -> NDArray[np.float64]:
        """Return each design row's noise (W, k'): the signals', then the roll rate's for the yaw rate's row."""
        row = self.instrument_row()
        return self.noise if row is None else np.concatenate([self.noise, self.noise[:, row, None]], axis=1)

    def _changing_designs(self, bicycles: Sequence[Bicycle], models: Sequence[LinearModel]
                          ) -> dict[int, tuple[list[int], NDArray[np.float64], NDArray[np.bool_]]]:
        """Designs of the models following each window's changing speed, by states: members, (M, W, k', L, n').

        The bicycle coasting on the ground is a linear time-varying system along the window's
        speed profile ``v(t)`` (:attr:`profiles`): ``x' = A(v(t)) x`` with ``A`` the model's state
        matrix at ``v(t)`` and the torques ``-v' Ka q``. Its free response ``x(t) = Phi(t, 0) x0``
        is built over pieces of about ``PIECE_DURATION`` (whole bins), each frozen at the speed of
        its middle (the exponential midpoint rule); within a piece the bins' means are exact
        (each mode's mean over a bin, as at constant speed). The initial state ``x0`` (real, n
        values) takes the place of the modal amplitudes in the least squares; at a constant
        speed the two span the same responses. Also where a mode beyond the slowest grows in a
        piece (M, W).
        """
        pieces = self._pieces
        windows, count = self.mask.shape[0], pieces.starts.shape[1]
        speeds = (self.profiles[:, 0, None]  # type: ignore[index]
                  + self.accelerations[:, None] * (pieces.starts + 0.5 * pieces.spans  # type: ignore[index]
                                                   - self.profiles[:, 1, None]))  # type: ignore[index]
        # Only the pieces a window holds (windows are padded to the longest).
        owner = np.broadcast_to(np.arange(windows)[:, None], (windows, count))[pieces.real]
        friction = None if self.friction is None else self.friction[owner]
        accelerations = self.accelerations[owner]  # type: ignore[index]
        matrices = [window_state_matrices(bicycle, model, bicycle.model_speed(speeds[pieces.real]),
                                          window_steer_damping(bicycle, friction), accelerations)
                    for bicycle, model in zip(bicycles, models, strict=True)]
        result: dict[int, tuple[list[int], NDArray[np.float64], NDArray[np.bool_]]] = {}
        for states in sorted({matrix.shape[-1] for matrix in matrices}):
            members = [k for k, matrix in enumerate(matrices) if matrix.shape[-1] == states]
            stacked = np.stack([matrices[k] for k in members])  # (members, real pieces, n, n)
            model_speeds = np.stack([bicycles[k].model_speed(speeds) for k in members])  # (members, W, P)
            yaw = np.stack([np.broadcast_to(yaw_gains(bicycles[k]), (*speeds.shape, 2)) for k in members])
            with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
                result[states] = (members, *self._changing_design(stacked, pieces, model_speeds, yaw))
        return result

    @cached_property
    def _pieces(self) -> _Pieces:
        """The pieces each window's response is built over: about ``PIECE_DURATION``, whole bins.

        Every window's pieces hold as many bins, those of the longest bins' duration (windows
        sampled alike: the same).
        """
        windows, length = self.mask.shape
        sizes = self.mask.sum(axis=1)
        bins = np.ones(windows, dtype=int) if self.bins is None else self.bins
        steps = np.zeros(windows) if self.steps is None else self.steps
        width = bins * steps  # each bin's duration [s]
        per_piece = max(1, int(round(PIECE_DURATION / float(width.max())))) if width.max() > 0 else 1
        count = int(np.max(-(-sizes // per_piece)))
        tau = np.zeros((windows, count * per_piece))
        tau[:, :length] = self.tau
        valid = np.zeros((windows, count * per_piece), dtype=bool)
        valid[:, :length] = self.mask
        # Padded bins continue the window's last bin (finite times for every piece).
        last = np.take_along_axis(self.tau, (sizes - 1)[:, None], axis=1)
        grid = np.where(valid, tau, last).reshape(windows, count, per_piece)
        starts = grid[:, :, 0]
        stops = grid[:, :, -1] + width[:, None]
        following = np.concatenate([starts[:, 1:], stops[:, -1:]], axis=1)
        real = np.arange(count)[None, :] < -(-sizes // per_piece)[:, None]
        return _Pieces(starts, stops - starts, following - starts, grid - starts[:, :, None], real)

    def _changing_design(self, matrices: NDArray[np.float64], pieces: _Pieces, speeds: NDArray[np.float64],
                         yaw: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Return the design (models, W, k', L, n') of the responses to each initial state, over the pieces.

        ``matrices`` (models, R, n, n): the constant state matrix of each of the R pieces the
        windows hold (:attr:`_Pieces.real`, in order); ``speeds`` (models, W, P) and ``yaw``
        (models, W, P, 2): each piece's model speed [m/s] and yaw-rate gains (:meth:`_signal_rows`),
        each signal divided by its noise, padded bins 0. A model with more than the bicycle's
        states: initial states on a real basis of the first piece's modes that
        :func:`~whipple.diagnosis.growing_modes.fitted_modes` picks, as many growing ones as grow
        in any piece. Also where a mode beyond the slowest grows in a piece (models, W).
        """
        models, states = matrices.shape[0], matrices.shape[-1]
        windows, count = pieces.real.shape
        # Padded pieces: no change of state (eigenvalues 0, eigenvectors the unit vectors).
        values = np.zeros((models, windows, count, states), dtype=complex)
        vectors = np.broadcast_to(np.eye(states, dtype=complex), (models, windows, count, states, states)).copy()
        inverse = vectors.copy()
        found, modes = np.linalg.eig(matrices)
        values[:, pieces.real], vectors[:, pieces.real], inverse[:, pieces.real] = found, modes, np.linalg.inv(modes)
        transitions = np.real((vectors * np.exp(values * pieces.lengths[..., None])[..., None, :]) @ inverse)
        # State transition from the window's start to each piece's start.
        start = np.empty((models, windows, count, states, states))
        start[:, :, 0] = np.eye(states)
        for piece in range(1, count):
            start[:, :, piece] = transitions[:, :, piece - 1] @ start[:, :, piece - 1]
        modal = inverse @ start  # each piece's modal amplitudes per unit initial state
        growing = np.max(dropped_modes(values)[1], axis=-1)  # the most of any piece
        if states > FITTED_MODES:
            first, shapes = values[:, :, 0], vectors[:, :, 0]
            columns = np.where(lower_members(first)[..., None, :], shapes.imag, shapes.real)
            kept, real = fitted_modes(first, growing)
            real[..., FITTED_MODES:] &= resolved(np.take_along_axis(first, kept, -1)[..., FITTED_MODES:],
                                                 self.steps, self.bins)
            basis = np.take_along_axis(columns, kept[..., None, :], axis=-1) * real[..., None, :]
            modal = modal @ basis[:, :, None]
        factors = self._bin_factors(np.moveaxis(values, 1, 0).reshape(windows, -1))
        factors = np.moveaxis(factors.reshape(windows, models, count, states), 0, 1)
        rows = self._signal_rows(vectors, speeds, yaw) * factors[..., None, :]  # (M, W, P, k', n)
        growth = np.exp(values[:, :, :, None, :] * pieces.offsets[None, :, :, :, None])  # (M, W, P, g, n)
        design = np.real(np.einsum("mwpkj,mwpgj,mwpjc->mwkpgc", rows, growth, modal))
        length = self.mask.shape[1]
        design = design.reshape(models, windows, rows.shape[-2], -1, modal.shape[-1])[:, :, :, :length]
        return design * self.mask[None, :, None, :, None] / self._row_noise()[None, :, :, None, None], growing > 0

    def _state_matrices(self, bicycle: Bicycle, model: LinearModel) -> NDArray[np.float64]:
        """Return the model's state matrix at each window's speed (W, n, n).

        With its steer friction's damping per window, and ``-v' Ka q`` where the speed changes.
        """
        return window_state_matrices(bicycle, model, bicycle.model_speed(self.speeds),
                                     window_steer_damping(bicycle, self.friction), self.accelerations)

    def _fleet_residuals(self, models: Sequence[Model], linear: Sequence[LinearModel | None]) -> NDArray[np.float64]:
        """:meth:`residuals` of models some of which are fleets: each member on its group's windows.

        The members of every model that evaluate the same windows are solved together.
        """
        result = np.zeros((len(models), self.samples))
        owner = self.window_of_residuals()
        batches: dict[tuple[int, ...] | None, list[tuple[int, Bicycle, LinearModel | None]]] = {}
        for k, (model, given) in enumerate(zip(models, linear, strict=True)):
            for bicycle, index in members_of(model, self.groups):
                batches.setdefault(None if index is None else tuple(int(n) for n in index), []).append(
                    (k, bicycle, given))
        for key, members in batches.items():
            comparison = self if key is None else self._subset(np.array(key, dtype=np.intp))
            found = comparison.residuals([bicycle for _, bicycle, _ in members], [given for _, _, given in members])
            where = slice(None) if key is None else np.isin(owner, key)
            for row, (k, _, _) in enumerate(members):
                result[k, where] = found[row]
        return result

    def _subset(self, index: NDArray[np.intp]) -> SampleComparison:
        """Return the comparison of the windows ``index`` (in order) alone."""
        def pick(array: NDArray | None) -> NDArray | None:
            return None if array is None else array[index]

        return replace(self, speeds=self.speeds[index], tau=self.tau[index], mask=self.mask[index],
                       targets=self.targets[index], noise=self.noise[index], bins=pick(self.bins),
                       steps=pick(self.steps), friction=pick(self.friction), accelerations=pick(self.accelerations),
                       profiles=pick(self.profiles),
                       groups=None if self.groups is None else tuple(self.groups[int(n)] for n in index))

    def _repeated(self, copies: int) -> SampleComparison:
        """Return the windows repeated ``copies`` times (several models' windows evaluated at once)."""
        if copies == 1:
            return self

        def tile(array: NDArray | None) -> NDArray | None:
            return None if array is None else np.concatenate([array] * copies)

        return SampleComparison(np.concatenate([self.speeds] * copies), np.concatenate([self.tau] * copies),
                                np.concatenate([self.mask] * copies), np.concatenate([self.targets] * copies),
                                np.concatenate([self.noise] * copies), self.states, self.names, tile(self.bins),
                                tile(self.steps), friction=tile(self.friction),
                                accelerations=tile(self.accelerations), profiles=tile(self.profiles),
                                instrument=self.instrument)

    def _bin_factors(self, values: NDArray[np.complex128]) -> NDArray[np.complex128]:
        """Return each mode's mean over a bin relative to its value at the bin's first sample (W, n).

        ``values`` (W, n): eigenvalues [1/s] whose bins are each window's (any number per window:
        one model's, or several models' and pieces').
        """
        if self.bins is None or self.steps is None or np.all(self.bins == 1):
            return np.ones(values.shape, dtype=complex)
        offsets = np.arange(int(self.bins.max()))[None, :] * self.steps[:, None]  # (W, m)
        inside = np.arange(int(self.bins.max()))[None, :] < self.bins[:, None]
        terms = np.exp(values[:, None, :] * offsets[:, :, None]) * inside[:, :, None]
        return np.asarray(terms.sum(axis=1) / self.bins[:, None], dtype=complex)

    def _modal_design(self, values: NDArray[np.complex128], rows: NDArray[np.complex128]) -> NDArray[np.float64]:
        """Design (W, k', L, n) of the models' responses with eigenvalues (W, n) and signal rows (W, k', n).

        A complex pair's response ``Re(a v e^{lambda t})`` takes two real amplitudes: the real
        part of its upper member's column and the imaginary part of its lower member's (the
        conjugate), so that every mode gives one real column, n in all; in units of each row's noise.
        """
        noise = self._row_noise()
        lower = lower_members(values)
        # design[w, k, l, j] = first[w, k, j] Re(e^{lambda_j t_l}) + second[w, k, j] Im(e^{lambda_j t_l}).
        first = np.where(lower[:, None, :], rows.imag, rows.real) / noise[:, :, None]
        second = np.where(lower[:, None, :], rows.real, -rows.imag) / noise[:, :, None]
        exponent = values[:, None, :] * self.tau[:, :, None]
        envelope = np.exp(exponent.real) * self.mask[:, :, None]
        cosine, sine = envelope * np.cos(exponent.imag), envelope * np.sin(exponent.imag)
        return first[:, :, None, :] * cosine[:, None, :, :] + second[:, :, None, :] * sine[:, None, :, :]

    def _fitted_residuals(self, design: NDArray[np.float64]) -> NDArray[np.float64]:
        """Residuals (M, W, k, L) of M models' designs (M, W, k', L, n), each at its instrument's errors if fitted."""
        models, windows = design.shape[:2]
        count = len(self.states)
        if self.instrument_row() is None:
            residual = self._repeated(models)._least_squares(design.reshape(models * windows, *design.shape[2:]))
            return residual.reshape(models, windows, *residual.shape[1:])
        return self._instrument_residuals(design[:, :, :count], design[:, :, count])

    def _centred(self, design: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return a design (..., W, k, L, n) centred on each window's mean (each signal's offset taken out)."""
        sizes = self.mask.sum(axis=1)[:, None, None, None]
        valid = self.mask[:, None, :, None]
        return design - (design.sum(axis=-2, keepdims=True) / sizes) * valid

    def _least_squares(self, design: NDArray[np.float64]) -> NDArray[np.float64]:
        """Residuals (W, k, L) of the targets fitted by the columns of ``design`` (W, k, L, n) and offsets.

        ``design``: each response column in units of the signal's noise, 0 on padded bins. Each
        signal's offset is taken out by centring the signal and every column on the window's mean.
        """
        windows, count, length = self.targets.shape
        design = self._centred(design).reshape(windows, count * length, -1)
        targets = self._centred(self.targets[..., None])[..., 0].reshape(windows, count * length)
        finite = np.isfinite(design).all(axis=(1, 2))
        residual = np.full((windows, count * length), OVERFLOW_MISFIT)
        if finite.any():
            q, _ = orthonormal_columns(design[finite])
            fitted = np.einsum("wsc,wc->ws", q, np.einsum("wsc,ws->wc", q, targets[finite]))
            residual[finite] = targets[finite] - fitted
        return residual.reshape(windows, count, length)

    def _instrument_residuals(self, design: NDArray[np.float64], yaw: NDArray[np.float64]) -> NDArray[np.float64]:
        """Residuals (M, W, k, L) of M models, each with the roll gyro's errors it fits best.

        ``design`` (M, W, k, L, n): the signals' responses; ``yaw`` (M, W, L, n): the yaw rate's,
        in the roll rate's noise (:func:`~whipple.diagnosis.instrument.profiled_residuals`); 1e3 where it overflows.
        """
        assert self.instrument is not None and (row := self.instrument_row()) is not None
        design, yaw = self._centred(design), self._centred(yaw[:, :, None])[:, :, 0]
        finite = np.asarray(np.isfinite(design).all(axis=(2, 3, 4)) & np.isfinite(yaw).all(axis=(2, 3)), dtype=bool)
        design, yaw = np.where(finite[..., None, None, None], design, 0.0), np.where(finite[..., None, None], yaw, 0.0)
        residual = profiled_residuals(design, yaw, self._centred(self.targets[..., None])[..., 0], row, finite,
                                      self.instrument)
        return np.where(finite[..., None, None], residual, OVERFLOW_MISFIT)

    def fitted(self, bicycle: Model, model: LinearModel | None = None) -> list[NDArray[np.float64]]:
        """Return each window's free response of a model fitted to its samples, (k, bins) in signal units."""
        residual = np.zeros(self.targets.shape)
        residual[self._residual_mask()] = self.residuals([bicycle], [model])[0]
        curves = (self.targets - residual) * self.noise[:, :, None]
        return [curve[:, :size] for curve, size in zip(curves, self.mask.sum(axis=1), strict=True)]

    def chi2_per_sample(self, bicycle: Model, model: LinearModel | None = None) -> float:
        """Return a model's chi-square per sample (1 where it leaves only the noise)."""
        residual = self.residuals([bicycle], [model])[0]
        return float(np.mean(residual**2))


def noise_free_samples(bicycle: Model, observations: Sequence[Observation],
                       model: LinearModel | None = None) -> list[Observation]:
    """Return the observations a model would give at the same windows without noise, samples and all.

    Each window's samples become the model's free response fitted to them (what of the window
    the model explains), with the window's noise kept as its stated noise
    (:attr:`~whipple.diagnosis.observations.WindowSignals.noise`); its eigenvalue and mode shape
    become the model's (:func:`~whipple.diagnosis.observations.noise_free`). Compared with them,
    models are told apart by what the windows could tell at best if the model were true.
    ``model``: the linear model where it is not the bicycle's own. Windows without samples
    keep none.
    """
    twins = noise_free(bicycle, observations)
    comparison = SampleComparison.of(observations, binned=False, bicycle=bicycle)
    if comparison is None:
        return twins
    curves = comparison.fitted(bicycle, model)
    return [replace(twin, signals=replace(o.signals, values=curve, noise=noise))
            if o.signals is not None else twin
            for twin, o, curve, noise in zip(twins, observations, curves, comparison.noise, strict=True)]
