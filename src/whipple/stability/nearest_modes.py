"""The model's mode nearest a measured eigenvalue, and its mode shape.

A measured oscillation is one of the model's modes; matching the mode nearest the measured
eigenvalue (rather than a label such as "weave") keeps a comparison meaningful for models with
extra modes (tyres, a controller's actuator) and below the speed where the weave forms. Used by
the measurement (the steer signal's sign, the model column of ``whipple fit``) and the diagnosis.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.model.assembly import linear_model, second_order_matrices
from whipple.model.fleet import Model, members_of
from whipple.model.linear import LinearModel
from whipple.model.parameters import Bicycle
from whipple.model.speed_change import acceleration_stiffness
from whipple.stability.quartic import second_order_eigenvalues, second_order_eigenvectors
from whipple.stability.slow_modes import unseen_growth

#: Model states a mode shape can relate: the first four states of every model.
MODE_SHAPE_STATES = {"roll_angle": 0, "steer_angle": 1, "roll_rate": 2, "steer_rate": 3}


#: A window's mode shape is compared only where the base model has an oscillatory mode within
#: this fraction of the measured eigenvalue's magnitude: a "weave" fitted to a catch or to
#: noise (strongly damped, far from every model mode) has no mode shape to speak of, and the
#: shape of whichever real mode lies nearest would make it a huge outlier.
SHAPE_MATCH = 0.3


def near_oscillation(predicted: ArrayLike, measured: ArrayLike) -> NDArray[np.bool_]:
    """Return where a model's mode is an oscillation near the measured eigenvalue.

    Parameters
    ----------
    predicted : array_like of complex
        The model's eigenvalue nearest each measured one [1/s] (:func:`nearest_modes`).
    measured : array_like of complex
        The measured eigenvalues [1/s], same shape.

    Returns
    -------
    ndarray of bool
        True where the model's mode oscillates (positive imaginary part) and lies within
        :data:`SHAPE_MATCH` of the measured eigenvalue's magnitude: only there do the mode's
        frequency and shape describe the measured oscillation.
    """
    predicted, measured = np.asarray(predicted, dtype=complex), np.asarray(measured, dtype=complex)
    return (predicted.imag > 0) & (np.abs(measured - predicted) < SHAPE_MATCH * np.abs(measured))


def nearest_oscillations(bicycle: Bicycle, speeds: ArrayLike, targets: ArrayLike
                          ) -> tuple[NDArray[np.complex128], NDArray[np.bool_]]:
    """Return the model's oscillating mode nearest each measured eigenvalue, and whether it is near.

    Parameters
    ----------
    bicycle : Bicycle
        The model (its controller, extensions and ``speed_scale`` included).
    speeds : array_like
        Measured speeds [m/s], shape (N,).
    targets : array_like of complex
        Measured eigenvalues [1/s], shape (N,).

    Returns
    -------
    eigenvalues : ndarray of complex, shape (N,)
        At each speed, the model eigenvalue with a positive imaginary part nearest the target
        [1/s]; NaN where the model has no oscillating mode at that speed.
    near : ndarray of bool, shape (N,)
        Whether it lies near the target (:func:`near_oscillation`): only there does the
        comparison describe the measured oscillation.
    """
    speeds = np.asarray(speeds, dtype=float)
    targets = np.asarray(targets, dtype=complex)
    with np.errstate(all="ignore"):
        values = np.linalg.eigvals(linear_model(bicycle).state_matrix(bicycle.model_speed(speeds)))
    # Real modes (an imaginary part below 1e-9 of the magnitude) are not oscillations.
    oscillating = values.imag > 1e-9 * np.abs(values)
    distance = np.where(oscillating, np.abs(values - targets[:, None]), np.inf)
    nearest = np.argmin(distance, axis=1)
    chosen = values[np.arange(len(nearest)), nearest]
    chosen = np.where(np.isfinite(distance[np.arange(len(nearest)), nearest]), chosen, np.nan + 0j)
    return chosen.astype(np.complex128), near_oscillation(chosen, targets)


def nearest_modes(bicycle: Model, speeds: NDArray[np.float64], targets: NDArray[np.complex128],
                  signals: Sequence[tuple[str, str] | None], groups: Sequence[str] | None = None,
                  friction: NDArray[np.float64] | None = None,
                  accelerations: NDArray[np.float64] | None = None
                  ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Return the model's eigenvalue nearest each target, and its eigenvector's ratio of two signals.

    At each measured speed [m/s] (speed_scale applied), the model eigenvalue (upper half plane)
    nearest ``targets`` [1/s], and its eigenvector's ratio of two signals (MODE_SHAPE_STATES;
    NaN where ``signals`` is None). ``groups``: each window's group, where ``bicycle`` is a
    :class:`~whipple.model.fleet.Fleet` (each window is evaluated with its group's bicycle).
    ``friction``: each window's equivalent steer damping per unit Coulomb steer friction
    [s/rad] (:func:`~whipple.model.steer_friction.describing_gain`): a bicycle with a steer
    friction F [N m] has the damping F times it added at that window (None: friction left out).
    ``accelerations``: each window's measured forward acceleration [m/s^2] (None: constant
    speed), which adds ``v' Ka q`` to the equations (:func:`with_speed_change`).
    """
    chosen, shapes = nearest_modes_of_models([bicycle], speeds, targets, signals, groups, friction, accelerations)
    return chosen[0], shapes[0]


def window_steer_damping(bicycle: Bicycle, friction: NDArray[np.float64] | None) -> NDArray[np.float64] | None:
    """Return the Coulomb steer friction's equivalent damping at each window [N m s/rad], or None where none.

    ``friction``: each window's damping per unit friction [s/rad]; the bicycle's
    ``extensions.steer_friction`` [N m] times it.
    """
    size = float(bicycle.extensions.steer_friction)
    if friction is None or size == 0.0:
        return None
    return size * np.asarray(friction, dtype=float)


def with_steer_damping(A: NDArray[np.float64], B: NDArray[np.float64], damping: NDArray[np.float64] | None
                       ) -> NDArray[np.float64]:
    """Return state matrices (W, n, n) with a steer torque ``-damping * steer_rate`` per window added.

    ``B`` (W, n, 2) maps the roll and steer torque into the state derivative; the steer rate is
    the fourth state of every model.
    """
    if damping is None:
        return A
    A = np.array(A, dtype=float)
    A[..., :, 3] -= np.asarray(damping)[..., None] * B[..., :, 1]
    return A


def nearest_modes_of_models(bicycles: Sequence[Model], speeds: NDArray[np.float64],
                            targets: NDArray[np.complex128], signals: Sequence[tuple[str, str] | None],
                            groups: Sequence[str] | None = None, friction: NDArray[np.float64] | None = None,
                            accelerations: NDArray[np.float64] | None = None
                            ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """:func:`nearest_modes` of several models at the same windows; each result (models, windows).

    As :func:`nearest_modes_and_holds`, without whether each model holds each window.
    """
    chosen, shapes, _ = nearest_modes_and_holds(bicycles, speeds, targets, signals, groups, friction, accelerations)
    return chosen, shapes


def nearest_modes_and_holds(bicycles: Sequence[Model], speeds: NDArray[np.float64],
                            targets: NDArray[np.complex128], signals: Sequence[tuple[str, str] | None],
                            groups: Sequence[str] | None = None, friction: NDArray[np.float64] | None = None,
                            accelerations: NDArray[np.float64] | None = None
                            ) -> tuple[NDArray[np.complex128], NDArray[np.complex128], NDArray[np.bool_]]:
    """:func:`nearest_modes` of several models at the same windows, and where each cannot hold a window.

    Each result has the shape (models, windows): the eigenvalues [1/s], the mode shapes, and
    ``unheld``, True where a mode beyond the model's four slowest grows at the window
    (:func:`~whipple.stability.slow_modes.unseen_growth`). A window holds free coasting, which
    starts such modes at rest; one that grows would have swamped the window. A model with the
    states ``[q, q']`` alone has no other modes and holds every window.

    Models with the states ``[q, q']`` only are solved together: one closed-form solve of all
    their quartics costs little more than one model's, whose many small array operations are
    what an evaluation costs (a fit's finite-difference Jacobian evaluates several models at
    once). Other models are solved one by one, and a fleet group by group on its group's
    windows (``groups``: each window's group). ``friction``: as :func:`nearest_modes` takes it.
    """
    plain = [bicycle for bicycle in bicycles if isinstance(bicycle, Bicycle)]
    if len(plain) < len(bicycles):
        return _nearest_of_fleets(bicycles, speeds, targets, signals, groups, friction, accelerations)
    rows = np.array([n for n, pair in enumerate(signals) if pair is not None], dtype=int)
    true_speeds = [bicycle.model_speed(speeds) for bicycle in plain]
    dampings = [window_steer_damping(bicycle, friction) for bicycle in plain]
    matrices = [_with_window_damping(second_order_matrices(bicycle, v), damping)
                for bicycle, v, damping in zip(plain, true_speeds, dampings, strict=True)]
    if accelerations is not None:
        matrices = [None if m is None else (m[0], m[1], m[2] + speed_change_stiffness(bicycle, accelerations))
                    for bicycle, m in zip(plain, matrices, strict=True)]
    if all(m is not None for m in matrices):
        M, C, K = (np.stack([m[k] for m in matrices if m is not None]) for k in range(3))
        chosen, vectors = _nearest_second_order(M[:, None], C, K, targets, rows)
        unheld = np.zeros(chosen.shape, dtype=bool)
    else:
        # Each model once, those with the states [q, q'] from the matrices already built.
        solved = [(*_nearest_second_order(*m, targets, rows), np.zeros(len(targets), dtype=bool)) if m is not None
                  else _nearest_by_eig(bicycle, v, targets, rows, damping, accelerations)
                  for bicycle, v, m, damping in zip(plain, true_speeds, matrices, dampings, strict=True)]
        chosen = np.stack([values for values, _, _ in solved])
        vectors = np.stack([vector[:, :4] for _, vector, _ in solved])
        unheld = np.stack([held for _, _, held in solved])
    shapes = np.full(chosen.shape, np.nan, dtype=complex)
    if len(rows):
        numerator = [MODE_SHAPE_STATES[signals[n][0]] for n in rows]  # type: ignore[index]
        denominator = [MODE_SHAPE_STATES[signals[n][1]] for n in rows]  # type: ignore[index]
        along = np.arange(len(rows))
        shapes[:, rows] = vectors[:, along, numerator] / vectors[:, along, denominator]
    return chosen, shapes, unheld


def _with_window_damping(matrices: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None,
                         damping: NDArray[np.float64] | None
                         ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None:
    """Return M, C, K with each window's steer damping [N m s/rad] added to C's steer entry."""
    if matrices is None or damping is None:
        return matrices
    M, C, K = matrices
    C = np.array(np.broadcast_to(C, damping.shape + (2, 2)), dtype=float)
    C[..., 1, 1] += damping
    return M, C, K


def _nearest_of_fleets(models: Sequence[Model], speeds: NDArray[np.float64], targets: NDArray[np.complex128],
                       signals: Sequence[tuple[str, str] | None], groups: Sequence[str] | None,
                       friction: NDArray[np.float64] | None = None,
                       accelerations: NDArray[np.float64] | None = None
                       ) -> tuple[NDArray[np.complex128], NDArray[np.complex128], NDArray[np.bool_]]:
    """:func:`nearest_modes_and_holds` of models some of which are fleets: each member on its windows.

    The members of every model that evaluate the same windows are solved together, as plain
    models are (a fit's finite-difference Jacobian evaluates many models at once).
    """
    speeds, targets = np.asarray(speeds, dtype=float), np.asarray(targets, dtype=complex)
    chosen = np.full((len(models), len(speeds)), np.nan, dtype=complex)
    shapes = np.full((len(models), len(speeds)), np.nan, dtype=complex)
    unheld = np.zeros((len(models), len(speeds)), dtype=bool)
    batches: dict[tuple[int, ...] | None, list[tuple[int, Bicycle]]] = {}
    for k, model in enumerate(models):
        for bicycle, index in members_of(model, groups):
            batches.setdefault(None if index is None else tuple(int(n) for n in index), []).append((k, bicycle))
    for key, members in batches.items():
        rows = list(range(len(speeds))) if key is None else list(key)
        found, shape, held = nearest_modes_and_holds([bicycle for _, bicycle in members], speeds[rows], targets[rows],
                                                     [signals[n] for n in rows], None,
                                                     None if friction is None else np.asarray(friction)[rows],
                                                     None if accelerations is None else np.asarray(accelerations)[rows])
        for row, (k, _) in enumerate(members):
            chosen[k, rows], shapes[k, rows], unheld[k, rows] = found[row], shape[row], held[row]
    return chosen, shapes, unheld


def nearest_eigen(bicycle: Bicycle, true_speeds: NDArray[np.float64], targets: ArrayLike,
                  rows: NDArray[np.intp]) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Return the model's eigenvalue nearest each target and, for `rows`, its eigenvector.

    At each true speed [m/s], of the bicycle's linear model (controller and extensions
    included) the eigenvalue in the upper half plane nearest the target [1/s], and for the
    speeds listed in `rows` its eigenvector over the model's states (``[q, q']`` first),
    shape (len(rows), states).
    """
    matrices = second_order_matrices(bicycle, true_speeds)
    if matrices is not None:
        # The closed form of the 4-state models: a fraction of eig's cost at this size.
        return _nearest_second_order(*matrices, np.asarray(targets), rows)
    return _nearest_by_eig(bicycle, true_speeds, targets, rows)[:2]


def _nearest_by_eig(bicycle: Bicycle, true_speeds: NDArray[np.float64], targets: ArrayLike,
                    rows: NDArray[np.intp], damping: NDArray[np.float64] | None = None,
                    accelerations: NDArray[np.float64] | None = None
                    ) -> tuple[NDArray[np.complex128], NDArray[np.complex128], NDArray[np.bool_]]:
    """:func:`nearest_eigen` by ``numpy.linalg.eig`` of the state matrices (a model with more states).

    ``damping``: a steer damping [N m s/rad] per speed added (:func:`with_steer_damping`);
    ``accelerations``: the measured forward accelerations [m/s^2] (None: constant speed).
    Also returns where a mode beyond the four slowest grows (:func:`nearest_modes_and_holds`).
    """
    values, vectors = np.linalg.eig(window_state_matrices(bicycle, linear_model(bicycle), true_speeds, damping,
                                                          accelerations))
    unheld = unseen_growth(values.astype(complex))
    lower = values.imag < 0
    values = np.where(lower, np.conj(values), values)
    nearest = np.argmin(np.abs(values - np.asarray(targets)[:, None]), axis=1)
    chosen = np.asarray(values[np.arange(len(nearest)), nearest], dtype=complex)
    if not len(rows):
        return chosen, np.zeros((0, vectors.shape[-1]), dtype=complex), unheld
    vector = vectors[rows, :, nearest[rows]]
    # The eigenvector of the upper-half-plane eigenvalue: conjugated where eig gave the lower.
    return chosen, np.where(lower[rows, nearest[rows]][:, None], np.conj(vector), vector), unheld


def _nearest_second_order(M: NDArray[np.float64], C: NDArray[np.float64], K: NDArray[np.float64],
                          targets: NDArray[np.complex128], rows: NDArray[np.intp]
                          ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """:func:`nearest_eigen` of ``M q'' + C q' + K q = 0``, C and K (..., windows, 2, 2).

    Returns the eigenvalues (..., windows) and the eigenvectors of `rows` (..., len(rows), 4).
    """
    values = second_order_eigenvalues(M, C, K)
    values = np.where(values.imag < 0, np.conj(values), values)
    nearest = np.argmin(np.abs(values - targets[:, None]), axis=-1)
    chosen = np.take_along_axis(values, nearest[..., None], axis=-1)[..., 0]
    if not len(rows):
        return chosen, np.zeros(chosen.shape[:-1] + (0, 4), dtype=complex)
    return chosen, second_order_eigenvectors(M, C[..., rows, :, :], K[..., rows, :, :], chosen[..., rows])


def speed_change_stiffness(bicycle: Bicycle, accelerations: ArrayLike) -> NDArray[np.float64]:
    """Return ``v' Ka`` [N m/rad], shape (windows, 2, 2): the stiffness a changing speed adds.

    ``accelerations``: measured forward accelerations [m/s^2], divided by the bicycle's
    ``speed_scale`` as its speeds are (:func:`whipple.model.speed_change.acceleration_stiffness`).
    """
    true = bicycle.model_speed(accelerations)
    return true[:, None, None] * acceleration_stiffness(bicycle)


def window_state_matrices(bicycle: Bicycle, model: LinearModel, true_speeds: NDArray[np.float64],
                          damping: NDArray[np.float64] | None, accelerations: ArrayLike | None
                          ) -> NDArray[np.float64]:
    """Return a model's state matrix at each window (windows, n, n), with what each window adds.

    ``model`` at the true speeds [m/s], with a steer damping [N m s/rad] per window
    (:func:`with_steer_damping`; None: none) and the torques ``-v' Ka q`` of the measured
    accelerations [m/s^2] (:func:`with_speed_change`; None: constant speed).
    """
    A, B = model.state_matrix(true_speeds), model.input_matrix(true_speeds)
    return with_speed_change(bicycle, with_steer_damping(A, B, damping), B, accelerations)


def with_speed_change(bicycle: Bicycle, A: NDArray[np.float64], B: NDArray[np.float64],
                      accelerations: ArrayLike | None) -> NDArray[np.float64]:
    """Return the state matrices (windows, n, n) with the torques ``-v' Ka q`` of a changing speed.

    ``B`` (windows, n, 2): the roll and steer torques' input matrices; ``accelerations``
    [m/s^2] measured (None: ``A`` itself, constant speed).
    """
    if accelerations is None:
        return A
    changed = np.array(A, dtype=float, copy=True)
    changed[:, :, 0:2] -= B[:, :, 0:2] @ speed_change_stiffness(bicycle, accelerations)
    return changed
