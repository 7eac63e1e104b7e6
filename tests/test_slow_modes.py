"""Models with more states than the bicycle's four start each window on their slowest modes.

A window holds free coasting some time after its push; a tyre's relaxation or a controller's lag
adds modes tens of times faster than the weave, which have died out by the window's first
sample. Compared with a window's samples, such a model fits the amplitudes of its four slowest
modes only (:func:`whipple.stability.slow_modes.slowest_modes`), as many as the Whipple model, so
that no model gains on the noise of every window's first samples through free fast amplitudes.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.linalg import expm

from whipple.diagnosis.candidate_fits import refit_to_samples, singles_from_pairs
from whipple.diagnosis.families import combined_cause
from whipple.diagnosis.fitting import EIGENVALUE_MISFIT, CauseFit, models_residuals, window_whitening
from whipple.diagnosis.growing_modes import orthonormal_columns, resolved, shown_growth
from whipple.diagnosis.observations import Observation, WindowSignals
from whipple.diagnosis.registry import candidate_causes
from whipple.diagnosis.samples import OVERFLOW_MISFIT, SampleComparison
from whipple.measurement.weavefit import fit_weave
from whipple.model.assembly import linear_model
from whipple.model.fleet import Fleet
from whipple.model.parameters import TyreCompliance, load_bicycle
from whipple.stability.nearest_modes import nearest_modes_and_holds
from whipple.stability.slow_modes import FITTED_MODES, dropped_modes, slowest_modes, unseen_growth

NOISE = (0.002, 0.0005)  # rad/s, rad: a weave of 0.2 rad/s a hundred times its noise
SPEED = 5.0  # m/s
RATE = 100.0  # samples per second


def _tyred():
    # A bicycle tyre's values (shared spec tyre-model.md): its relaxation modes decay at about
    # speed / relaxation length, 33 1/s at 5 m/s, against the weave's 1 1/s or so.
    return load_bicycle("benchmark").with_extensions(tyre_compliance=TyreCompliance(11.5, 0.57, 0.15))


def _window(bicycle, fast_share=0.0, seed=0, duration=3.0):
    """A constant-speed window of the model's free response from its weave (and capsize) plus
    ``fast_share`` of the weave's size in its fastest mode, with white noise (roll rate, steer angle)."""
    matrix = linear_model(bicycle).state_matrix(np.array([SPEED]))[0]
    values, vectors = np.linalg.eig(matrix)
    weave = int(np.argmax(np.where(values.imag > 0, -np.abs(values.imag - 4.0), -np.inf)))
    state = np.real(vectors[:, weave] / vectors[2, weave]) * 0.2
    capsize = int(np.argmin(np.where(np.abs(values.imag) < 1e-9, np.abs(values.real), np.inf)))
    state += 0.02 * np.real(vectors[:, capsize] / np.max(np.abs(vectors[:2, capsize])))
    fastest = int(np.argmax(np.abs(values)))
    state += fast_share * 0.2 * np.real(vectors[:, fastest] / np.max(np.abs(vectors[:4, fastest])))
    time, values = _measured(matrix, state, duration, seed)
    fit = fit_weave(time, values, ("roll_rate", "steer_angle"))
    return Observation("run", 0.0, float(time[-1]), SPEED, (SPEED, SPEED), complex(fit.eigenvalue),
                       np.eye(2) * 1e-4, signals=WindowSignals(time, values, ("roll_rate", "steer_angle"), "none",
                                                               noise=np.asarray(NOISE, dtype=float)))


def _measured(matrix, state, duration, seed):
    """Times [s] and the roll rate and steer angle (2, n) of the free response from ``state``, with white noise."""
    time = np.arange(0.0, duration + 1e-9, 1.0 / RATE)
    step = expm(matrix / RATE)
    states = [state]
    for _ in time[1:]:
        states.append(step @ states[-1])
    clean = np.array(states)[:, [2, 1]].T
    return time, clean + np.asarray(NOISE)[:, None] * np.random.default_rng(seed).standard_normal(clean.shape)


def test_the_slowest_modes_are_those_of_the_longest_time_scale():
    # The benchmark with tyres at 5 m/s: capsize, weave, castering, and the tyres' two lightly
    # damped oscillations; by the real part alone a tyre oscillation (-11.8 1/s) would come
    # before the castering mode (-15.1 1/s) and split its pair.
    values = np.linalg.eigvals(linear_model(_tyred()).state_matrix(np.array([SPEED]))[0])
    kept = values[slowest_modes(values[None, :])[0]]
    assert FITTED_MODES == 4
    assert np.all(np.abs(kept) < 20.0) and np.all(np.abs(np.delete(values, slowest_modes(values[None, :])[0])) > 50.0)
    whipple = np.linalg.eigvals(linear_model(load_bicycle("benchmark")).state_matrix(np.array([SPEED]))[0])
    # Continuous with the Whipple model's four (soft tyres move them by up to about 1 1/s).
    assert np.all(np.min(np.abs(kept[:, None] - whipple[None, :]), axis=1) < 1.5)


def test_a_conjugate_pair_is_kept_together():
    values = np.array([-30.0 + 0j, -1.0 + 5.0j, -1.0 - 5.0j, 0.2 + 0j, -15.0 + 0j, -28.0 + 3.0j, -28.0 - 3.0j])
    assert slowest_modes(values[None, :])[0].tolist() == [3, 1, 2, 4]


def test_a_model_with_tyres_leaves_its_own_window_at_the_noise():
    bicycle = _tyred()
    assert linear_model(bicycle).n_states > FITTED_MODES
    comparison = SampleComparison.of([_window(bicycle)], binned=False)
    spread = np.sqrt(2.0 / comparison.samples)
    assert abs(comparison.chi2_per_sample(bicycle) - 1.0) < 4 * spread


def test_the_fast_modes_amplitudes_are_not_fitted():
    # The same window with the tyres' fastest oscillation excited at its first sample as much as
    # the weave: fitted freely, that mode would take it up; on the slow modes it is left in the
    # first samples' residuals.
    bicycle = _tyred()
    comparison = SampleComparison.of([_window(bicycle, fast_share=1.0)], binned=False)
    assert comparison.chi2_per_sample(bicycle) > 2.0


def test_the_speed_profile_response_starts_on_the_same_slow_modes():
    # Along a speed profile the initial state takes the place of the modal amplitudes: restricted
    # to the slow modes of the window's start it spans the same responses, so that a window whose
    # acceleration is negligible keeps the modal residuals.
    bicycle = _tyred()
    window = _window(bicycle, seed=1)
    modal = SampleComparison.of([window]).residuals([bicycle])[0]
    followed = SampleComparison.of([replace(window, acceleration=1e-12)])
    assert followed.profiles is not None
    np.testing.assert_allclose(followed.residuals([bicycle])[0], modal, rtol=1e-6, atol=1e-6)


def test_a_growing_mode_beyond_the_slowest_is_unseen_growth():
    # A growing weave among the slowest modes is fitted; a growing fast mode is not.
    slow_growth = np.array([-30.0 + 0j, 0.5 + 5.0j, 0.5 - 5.0j, -0.2 + 0j, -15.0 + 0j, -28.0 + 3.0j, -28.0 - 3.0j])
    fast_growth = np.array([-0.3 + 0j, -1.0 + 5.0j, -1.0 - 5.0j, -12.0 + 0j, 3.0 + 21.0j, 3.0 - 21.0j])
    assert unseen_growth(np.stack([slow_growth[:6], fast_growth])).tolist() == [False, True]
    assert not unseen_growth(fast_growth[None, :4])[0]  # no mode beyond the four


def test_a_model_whose_dropped_modes_grow_cannot_hold_a_window():
    # A tyre relaxing over 1 m at 5 m/s: its slowest four are the bicycle's, barely moved, but one
    # of its tyre oscillations grows (+3 1/s); started at rest it would cost nothing, yet no
    # bounded window can have come from it. Both the modal and the speed-profile response say so.
    soft = load_bicycle("benchmark").with_extensions(tyre_compliance=TyreCompliance(6.4, 0.57, 1.0))
    assert unseen_growth(np.linalg.eigvals(linear_model(soft).state_matrix(np.array([SPEED]))))[0]
    window = _window(_tyred(), seed=2)
    modal = SampleComparison.of([window], binned=False)
    followed = SampleComparison.of([replace(window, acceleration=1e-12)], binned=False)
    for comparison in (modal, followed):
        residuals = comparison.residuals([soft, _tyred()])
        assert np.all(residuals[0] == OVERFLOW_MISFIT)
        assert np.all(np.abs(residuals[1]) < 1e2)


def test_a_cause_whose_values_cannot_hold_a_window_is_refitted_to_the_samples():
    # A cause far from the best is evaluated on the samples at its values fitted to the
    # eigenvalues; a tyre relaxing over 1 m has a growing mode there, and its evidence at those
    # values would say nothing of tyres: it is refitted to the samples over its bounds instead.
    bicycle = load_bicycle("benchmark")
    window = _window(_tyred(), seed=3)
    observations = [window, replace(window, run="again")]
    whitening = window_whitening(observations, bicycle, comparison="samples")
    tyre = next(cause for cause in candidate_causes(bicycle) if cause.name == "tyre_compliance")
    held = CauseFit("tyre_compliance", tyre.parameters, tyre.units, (6.4, 1.0), (0.0, 0.0), 0.0)
    _, (refitted,) = refit_to_samples(bicycle, [tyre], [held], observations, whitening, near=[False])
    assert refitted.values != held.values
    assert np.all(np.abs(refitted.residuals) < OVERFLOW_MISFIT)
    assert refitted.chi2 < 2.0 * refitted.residuals.size


def test_the_eigenvalue_comparison_applies_the_same_rule():
    # Compared with the windows' eigenvalues, the soft tyre's weave lies near the measured one:
    # without the rule it would fit them; with it, every window is a misfit, as on the samples.
    soft = load_bicycle("benchmark").with_extensions(tyre_compliance=TyreCompliance(6.4, 0.57, 1.0))
    window = _window(_tyred(), seed=4)
    observations = [window, replace(window, run="again")]
    whitening = window_whitening(observations, load_bicycle("benchmark"), comparison="eigenvalues")
    residuals, predicted, _ = models_residuals([soft, _tyred()], observations, whitening)
    assert np.all(residuals[0] == EIGENVALUE_MISFIT) and np.all(np.abs(residuals[1]) < 10)
    # What the model predicts is still reported: the rule is about the windows, not the modes.
    assert np.all(np.isfinite(predicted)) and np.all(np.abs(predicted[0] - window.eigenvalue) < 1.0)


def test_a_fleet_is_checked_on_each_group_s_windows():
    soft = load_bicycle("benchmark").with_extensions(tyre_compliance=TyreCompliance(6.4, 0.57, 1.0))
    fleets = [Fleet((("a", bicycle), ("b", bicycle))) for bicycle in (soft, _tyred())]
    speeds, targets = np.full(3, SPEED), np.full(3, -1.0 + 4.0j)
    unheld = nearest_modes_and_holds([*fleets, load_bicycle("benchmark")], speeds, targets, [None] * 3,
                                     ["b", "a", "b"])[2]
    assert unheld.tolist() == [[True, True, True], [False, False, False], [False, False, False]]


def _showing(bicycle, share, seed, duration=2.0):
    """A window of the bicycle's free response from its weave plus ``share`` of the weave's size in
    its fastest-growing mode beyond the slowest four, with white noise (roll rate, steer angle)."""
    matrix = linear_model(bicycle).state_matrix(np.array([SPEED]))[0]
    values, vectors = np.linalg.eig(matrix)
    weave = int(np.argmax(np.where(values.imag > 0, -np.abs(values.imag - 4.0), -np.inf)))
    state = np.real(vectors[:, weave] / vectors[2, weave]) * 0.2
    growing = int(dropped_modes(values[None, :])[0][0, 0])
    assert values[growing].real > 0
    state += share * 0.2 * np.real(vectors[:, growing] / np.max(np.abs(vectors[:4, growing])))
    time, noisy = _measured(matrix, state, duration, seed)
    return Observation("run", 0.0, float(time[-1]), SPEED, (SPEED, SPEED), complex(values[weave]), np.eye(2) * 1e-4,
                       signals=WindowSignals(time, noisy, ("roll_rate", "steer_angle"), "none",
                                             noise=np.asarray(NOISE, dtype=float)))


def test_the_modes_beyond_the_slowest_come_fastest_growing_first():
    values = np.array([-0.3 + 0j, -1.0 + 5.0j, -1.0 - 5.0j, -12.0 + 0j, -20.0 + 50.0j, -20.0 - 50.0j,
                       3.0 + 21.0j, 3.0 - 21.0j])
    dropped, growing = dropped_modes(values[None, :])
    assert dropped[0].tolist() == [6, 7, 4, 5] and growing.tolist() == [2]


def test_a_column_of_zeros_leaves_the_least_squares_as_without_it():
    rng = np.random.default_rng(5)
    matrix = rng.standard_normal((3, 40, 4))
    padded = np.concatenate([matrix, np.zeros((3, 40, 2))], axis=-1)
    padded[0, :, 4:] = rng.standard_normal((40, 2))  # one matrix with real extra columns
    target = rng.standard_normal((3, 40))
    for full, columns in ((padded[1:], matrix[1:]), (padded[:1], padded[:1])):
        q, inverse = orthonormal_columns(full)
        expected = np.stack([np.linalg.lstsq(m, t, rcond=None)[0] for m, t in zip(columns, target[-len(full):],
                                                                                  strict=True)])
        fitted = np.einsum("wsc,wc->ws", q, np.einsum("wsc,ws->wc", q, target[-len(full):]))
        np.testing.assert_allclose(fitted, np.einsum("wsc,wc->ws", columns, expected), atol=1e-10)
        amplitudes = np.einsum("wcd,wd->wc", inverse, np.einsum("wsc,ws->wc", q, target[-len(full):]))
        np.testing.assert_allclose(amplitudes[:, :columns.shape[-1]], expected, atol=1e-10)


def test_a_window_that_shows_the_growing_mode_is_held_with_its_amplitudes():
    # The soft tyre's oscillation grows at 5 m/s (+3 1/s); started at a thousandth of the weave
    # it reaches a few times the noise in the window, which shows it. Fitted with its
    # amplitudes, the soft tyre leaves the window at its noise, modal and along a speed profile;
    # the stiffer tyres, whose modes all decay, cannot follow it.
    soft = load_bicycle("benchmark").with_extensions(tyre_compliance=TyreCompliance(6.4, 0.57, 1.0))
    window = _showing(soft, 1e-3, seed=6)
    for comparison in (SampleComparison.of([window], binned=False),
                       SampleComparison.of([replace(window, acceleration=1e-12)], binned=False)):
        spread = np.sqrt(2.0 / comparison.samples)
        assert abs(comparison.chi2_per_sample(soft) - 1.0) < 4 * spread
        assert comparison.chi2_per_sample(_tyred()) > 2.0
    # A second window that does not show it (started at rest) is held too: the runs hold the mode.
    quiet = replace(_showing(soft, 0.0, seed=7), run="quiet")
    both = SampleComparison.of([window, quiet], binned=False).residuals([soft])[0]
    assert np.all(np.abs(both) < 10)
    # Without the window that shows it, the mode is unseen: no window is held.
    assert np.all(SampleComparison.of([quiet], binned=False).residuals([soft])[0] == OVERFLOW_MISFIT)


def test_a_single_cause_is_refitted_from_its_values_in_a_pair_that_fits_better():
    # Windows of a soft tyre whose growing oscillation they show. The single tyre stalled where
    # its modes all decay; a pair with a steer damping at zero reached the soft tyre's values.
    # From those values the single tyre fits as well as the pair.
    bicycle = load_bicycle("benchmark")
    soft = bicycle.with_extensions(tyre_compliance=TyreCompliance(6.4, 0.57, 1.0))
    observations = [_showing(soft, 1e-3, seed=8), replace(_showing(soft, 2e-3, seed=9), run="again")]
    whitening = window_whitening(observations, bicycle, comparison="samples")
    causes = {cause.name: cause for cause in candidate_causes(bicycle, include_parameters=False)}
    tyre, damping = causes["tyre_compliance"], causes["steer_damping"]
    stalled = CauseFit("tyre_compliance", tyre.parameters, tyre.units, (248.7, 0.70), (0.0, 0.0), 0.0)
    _, (stalled,) = refit_to_samples(bicycle, [tyre], [stalled], observations, whitening, near=[False])
    pair = combined_cause(damping, tyre)
    _, (pair_fit,) = refit_to_samples(bicycle, [pair], [CauseFit(pair.name, pair.parameters, pair.units,
                                                                  (0.0, 6.4, 1.0), (0.0,) * 3, 0.0)],
                                      observations, whitening, near=[False])
    assert pair_fit.chi2 < 0.1 * stalled.chi2
    fits, refitted = singles_from_pairs(bicycle, [damping, tyre], [stalled, stalled], [pair], [pair_fit],
                                        observations, whitening)
    assert abs(stalled.values[0] - 6.4) > 1.0  # the single did not reach the soft tyre
    assert refitted == [1]
    np.testing.assert_allclose(fits[1].values, (6.4, 1.0), rtol=0.02)
    assert fits[1].chi2 <= pair_fit.chi2 * 1.01


def test_a_growing_mode_that_takes_up_a_little_misfit_is_not_shown():
    # Two windows of 400 residuals: in the first the mode's part of the fit has a mean square of
    # 0.3 of the noise's (a gain of 60, three times the evidence needed), in the second 5.
    rng = np.random.default_rng(10)
    extended = rng.standard_normal((1, 2, 2, 200))
    extended *= 1.0 / np.sqrt(np.mean(extended**2, axis=(-2, -1), keepdims=True))
    plain = extended * np.sqrt(np.array([1.3, 6.0]))[None, :, None, None]
    samples = np.array([400, 400])
    growing = np.array([[True, True]])
    assert shown_growth(growing, extended, plain, samples).tolist() == [[False, True]]
    # Where no mode grows, nothing is shown.
    assert not shown_growth(~growing, extended, plain, samples).any()


def test_a_growing_mode_faster_than_the_bins_resolve_is_shown_by_no_window():
    # A stiff tyre (308 1/rad, relaxing over 0.61 m) has a relaxation mode of 153 rad/s that grows
    # at 5 m/s (+0.35 1/s). Averaged in bins of 0.04 s it looks like a faint oscillation of
    # 157 - 153 = 4.1 rad/s, beside the weave: fitted freely, it took up a slow disturbance in
    # each window. The window below holds such a disturbance (an oscillation of 4.1 rad/s,
    # 5 noise standard deviations of the roll rate, on the base bicycle's response). Resolved
    # sample by sample the mode is plainly not there; in bins it is never shown either: the stiff
    # tyre holds no window, binned or not.
    base = load_bicycle("benchmark")
    stiff = base.with_extensions(tyre_compliance=TyreCompliance(308.0, 0.57, 0.613))
    values = np.linalg.eigvals(linear_model(stiff).state_matrix(np.array([SPEED]))[0])
    fast = values[np.argmax(values.real)]
    assert fast.real > 0 and 150 < abs(fast.imag) < 157
    steps, bins = np.full(2, 1.0 / RATE), np.array([4, 1])
    assert resolved(np.array([[fast, 34.0j], [fast, 34.0j]]), steps, bins).tolist() == [[False, True], [True, True]]
    window = _window(base, seed=11)
    time = window.signals.time
    disturbed = window.signals.values.copy()
    disturbed[0] += 5 * NOISE[0] * np.sin((2 * np.pi / 0.04 - abs(fast.imag)) * time)
    window = replace(window, signals=replace(window.signals, values=disturbed))
    for binned in (True, False):
        assert np.all(SampleComparison.of([window], binned=binned).residuals([stiff])[0] == OVERFLOW_MISFIT)
