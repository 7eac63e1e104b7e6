"""Which windows a diagnosis uses: those that hold no one free motion set aside, short ones where too few pass."""

from __future__ import annotations

import numpy as np
import pytest

from whipple.measurement.experiment import FitOptions, measure_window, with_short_windows
from whipple.measurement.free_motion import free_response_misfit, outlying, set_aside_outlying
from whipple.measurement.runs import Run
from whipple.measurement.windows import Window

RATE = 100.0
SIGNALS = ("roll_rate", "steer_angle")
NOISE = np.array([0.01, 0.002])  # roll rate [rad/s], steer angle [rad]


def free_motion(tau: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """A free response of a 4-state model (a weave pair, a fast and a slow real mode), (2, n)."""
    phase = rng.uniform(0, 2 * np.pi)
    weave = np.exp(-0.6 * tau) * np.cos(5.0 * tau + phase)
    fast, slow = np.exp(-9.0 * tau), np.exp(-0.2 * tau)
    roll_rate = 0.3 * weave + 0.05 * fast + 0.02 * slow
    steer = 0.08 * np.exp(-0.6 * tau) * np.cos(5.0 * tau + phase + 0.7) - 0.03 * fast + 0.004 * slow
    return np.vstack([roll_rate, steer])


def run_of(values: np.ndarray, rng: np.random.Generator, name: str = "run") -> Run:
    time = np.arange(values.shape[1]) / RATE
    noisy = values + NOISE[:, None] * rng.standard_normal(values.shape)
    signals = {"roll_rate": noisy[0], "steer_angle": noisy[1], "speed": np.full(time.size, 5.0)}
    return Run(name, f"{name}.csv", time, signals, {}, RATE)


def whole_window(run: Run) -> Window:
    return Window(run.name, float(run.time[0]), float(run.time[-1]), 0, run.time.size, "test")


def measured(run: Run):
    return measure_window(run, whole_window(run), FitOptions(signals=SIGNALS, baseline="constant"))


def caught_and_pushed_again(rng: np.random.Generator) -> np.ndarray:
    """A free motion caught after 2.5 s, held for a second, then pushed into another free motion."""
    first = free_motion(np.arange(0, 2.5, 1 / RATE), rng)
    hold_time = np.arange(0, 1.0, 1 / RATE)
    held = first[:, -1:] * np.exp(-25.0 * hold_time)  # the hand stops the bicycle within 0.1 s
    second = -1.3 * free_motion(np.arange(0, 3.0, 1 / RATE), rng)
    return np.hstack([first, held, second])


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_free_window_sits_at_its_noise(seed):
    rng = np.random.default_rng(seed)
    window = measured(run_of(free_motion(np.arange(0, 4.0, 1 / RATE), rng), rng))
    assert 0.8 < free_response_misfit(window.fit) < 1.3


def test_a_window_spanning_a_catch_and_a_push_is_far_off():
    rng = np.random.default_rng(3)
    window = measured(run_of(caught_and_pushed_again(rng), rng))
    clean = measured(run_of(free_motion(np.arange(0, 6.5, 1 / RATE), rng), rng))
    assert free_response_misfit(window.fit) > 3 * free_response_misfit(clean.fit)


def test_outlying_needs_both_the_ratio_and_the_spread():
    assert outlying([1.0, 1.1, 0.95, 1.05, 4.5]).tolist() == [False, False, False, False, True]
    # Within twice the median: no outlier, however tight the rest.
    assert not outlying([1.0, 1.0, 1.0, 1.0, 1.9]).any()
    # Real records spread over a decade: a window within that spread is no outlier.
    spread = np.array([3.0, 5.0, 8.0, 9.0, 12.0, 20.0, 40.0, 30.0])
    assert not outlying(spread).any()
    assert outlying(np.r_[spread, 2000.0])[-1]
    # Too few windows to judge by; a misfit that is not finite is neither judged nor counted.
    assert not outlying([1.0, 50.0]).any()
    assert outlying([np.nan, 1.0, 1.1, 0.9, 4.5]).tolist() == [False, False, False, False, True]


def test_set_aside_marks_only_the_window_with_the_catch():
    rng = np.random.default_rng(4)
    runs = [run_of(free_motion(np.arange(0, 4.0, 1 / RATE), rng), rng, f"free{k}") for k in range(4)]
    runs.append(run_of(caught_and_pushed_again(rng), rng, "caught"))
    windows = [measured(run) for run in runs]
    assert all(w.usable for w in windows)
    result = set_aside_outlying(windows)
    assert [w.run.name for w in result] == [w.run.name for w in windows]
    assert [w.usable for w in result] == [True, True, True, True, False]
    assert result[-1].quality.startswith("not one free motion")
    assert result[-1].fit is windows[-1].fit  # the fit is kept, only not used
    assert all(w.quality is None for w in windows)  # the input is not changed



# Slow (a whole hidden-effect trial): run with `pytest -m slow`.
@pytest.mark.slow
def test_a_hidden_effect_trial_whose_window_spans_a_catch():
    # Browser with a hidden steer damping, seed 29: at 4 m/s (weave barely unstable, period
    # 4.6 s) the finder reads a catch, the hold and the next push as one 8.7 s swing. That
    # window alone is set aside, and the steer damping is named (before the rule: ambiguous,
    # every cause's fit pulled towards that one window).
    from hidden_effects import run_trial, trial_options, trial_runs

    from whipple.measurement.experiment import diagnosis_signals, measure_run

    base, _, runs = trial_runs("steer_damping", 29, "browser")
    options = trial_options(base, signals=diagnosis_signals(runs))
    found = [m for run in runs for m in measure_run(run, None, options)]
    aside = [m for m, kept in zip(found, set_aside_outlying(found), strict=True) if m.usable and not kept.usable]
    assert [(round(m.speed.mean), m.window.duration > 5.0) for m in aside] == [(4, True)]
    assert run_trial("steer_damping", 29, "browser").outcome == "right"


def short_window(rng: np.random.Generator, cycles: float, name: str):
    """A measured window of a free motion holding ``cycles`` weave cycles (weave at 5 rad/s)."""
    return measured(run_of(free_motion(np.arange(0, cycles * 2 * np.pi / 5.0, 1 / RATE), rng), rng, name))


def test_short_windows_are_used_only_where_too_few_pass_the_checks():
    rng = np.random.default_rng(5)
    short = [short_window(rng, 0.6, f"short{k}") for k in range(2)]
    assert all(w.quality.startswith("too short") for w in short)
    used = with_short_windows(short)
    assert all(w.usable for w in used)
    assert all(any(note.startswith("used though short") for note in w.window.notes) for w in used)
    # One long window and one short: both used, the long one unchanged.
    long = short_window(rng, 3.0, "long")
    assert long.usable
    mixed = with_short_windows([long, short[0]])
    assert mixed[0] is long and mixed[1].usable
    # Enough windows pass: nothing changes.
    enough = [long, short_window(rng, 3.0, "long2"), short[0]]
    assert with_short_windows(enough) == enough
    # Windows without a fit (under half a period), or still fewer than two: nothing changes either.
    tiny = short_window(rng, 0.3, "tiny")
    assert tiny.fit is None
    assert with_short_windows([tiny, tiny, short[0]]) == [tiny, tiny, short[0]]
