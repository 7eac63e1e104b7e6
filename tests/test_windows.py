"""Free-coasting windows: on the bundled real runs, on simulated runs, and windows files."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from whipple.errors import RunFileError
from whipple.measurement.bundled import bundled_reference_windows, bundled_runs
from whipple.measurement.reference_windows import compare_windows, read_windows, write_windows
from whipple.measurement.runs import Run, read_run
from whipple.measurement.weavefit import fit_window
from whipple.measurement.windows import Window, find_windows
from whipple.model.linear import second_order_model
from whipple.model.parameters import Payload, load_bicycle
from whipple.simulation.run_writer import parse_true_windows
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

# The instrumented bicycle of the seed paper (Kooijman & Schwab 2009, eq. 2).
SEED_MODEL = second_order_model(
    M=[[7.98981, 0.89569], [0.89569, 0.29857]],
    C1=[[0, 7.17025], [-0.59389, 1.32610]],
    K0=[[-109.91168, -13.45745], [-13.45745, -4.82272]],
    K2=[[0, 11.19798], [0, 1.42200]],
)


def simulate(speed, fs, duration, pushes=(), noise=0.01, start=(0, 0, 0, 0), catch=None, seed=0,
             holds=()):
    """A run of the seed bicycle: roll-torque pushes (time [s], peak [N m]), noise, a catch
    (the bicycle is held still once |roll rate| exceeds `catch` [rad/s]), and stretches
    (start, stop [s]) during which it is held still."""
    rng = np.random.default_rng(seed)
    A, B = SEED_MODEL.state_matrix(speed), SEED_MODEL.input_matrix(speed)
    step = expm(np.block([[A, B], [np.zeros((2, 6))]]) / fs)
    Ad, Bd = step[:4, :4], step[:4, 4:]
    t = np.arange(int(duration * fs)) / fs
    torque = np.zeros((t.size, 2))
    for when, peak in pushes:
        inside = (t >= when) & (t < when + 0.15)
        torque[inside, 0] = peak * np.sin(np.pi * (t[inside] - when) / 0.15)
    states = np.zeros((t.size, 4))
    x = np.array(start, dtype=float)
    held = False
    for k in range(t.size):
        states[k] = x
        held = held or (catch is not None and abs(x[2]) > catch)
        holding = held or any(a <= t[k] < b for a, b in holds)
        x = np.zeros(4) if holding else Ad @ x + Bd @ torque[k]
    signals = {"roll_rate": states[:, 2] + noise * rng.standard_normal(t.size)}
    eigenvalues = np.linalg.eigvals(A)
    weave = eigenvalues[np.argmax(eigenvalues.imag)]
    return Run("simulated", "<simulated>", t, signals, {"speed": str(speed)}, float(fs)), weave


@pytest.fixture(scope="module")
def real_runs():
    return [read_run(path) for path in bundled_runs()]


def test_every_hand_picked_window_is_found_on_the_real_runs(real_runs):
    reference = read_windows(bundled_reference_windows(), real_runs)
    assert len(reference) == 39  # 37 distinct windows; the file repeats or nests two
    found = [w for run in real_runs for w in find_windows(run).windows]
    comparison = compare_windows(found, reference)
    assert comparison.unmatched == ()
    assert comparison.matched == 39
    for match in comparison.matches:
        # The found window lies (almost) inside the hand-picked one and starts where it does:
        # at the extreme of the roll rate that ends the push.
        assert match.agreement > 0.95
        assert abs(match.found.start - match.reference.start) <= 0.05
    # Extra windows are other pushes of the same runs (the hand-picked list is a selection).
    assert len(comparison.extra) == len(found) - len({id(m.found) for m in comparison.matches})


def test_found_windows_are_ordered_disjoint_and_inside_the_run(real_runs):
    for run in real_runs:
        search = find_windows(run)
        assert search.noise > 0 and search.background > search.noise
        assert 0.3 < search.frequency < 3.0  # the weave, about 1 Hz
        previous = -np.inf
        for window in search.windows:
            assert previous <= window.start < window.stop <= run.time[-1]
            assert window.stop_index - window.start_index >= 3
            assert window.run == run.name
            assert window.reason.startswith(("perturbation at", "growth from", "free motion from the record"))
            previous = window.stop


@pytest.mark.parametrize(("speed", "fs"), [(5.0, 500), (6.0, 100), (7.0, 500)])
def test_simulated_pushes_give_one_window_each_and_the_weave_eigenvalue(speed, fs):
    pushes = ((3.0, 40.0), (12.0, -50.0), (21.0, 30.0))
    run, weave = simulate(speed, fs, 30.0, pushes, noise=0.01)
    windows = find_windows(run).windows
    assert len(windows) == 3
    for (when, _), window in zip(pushes, windows, strict=True):
        assert when < window.start < when + 0.5
        fit = fit_window(run, window)
        # The fitted model ignores the slow capsize mode, which biases it slightly.
        assert abs(fit.eigenvalue - weave) < 0.1


def test_seed_like_unstable_run_from_release_to_catch():
    # Below the weave speed the weave grows from small initial conditions until the catch.
    run, weave = simulate(3.0, 500, 12.0, start=(0, 0, 0.002, 0), noise=0.005, catch=1.0)
    caught = run.time[np.argmax(np.abs(run.signals["roll_rate"]) > 1.0)]
    windows = find_windows(run).windows
    assert len(windows) == 1
    window = windows[0]
    assert window.stop < caught and window.stop > caught - 0.5
    assert "caught" in window.reason and "growing" in window.notes[0]
    fit = fit_window(run, window)
    assert weave.real > 0 and abs(fit.eigenvalue - weave) < 0.05


@pytest.mark.parametrize("fs", [100, 500])
def test_catch_and_hold_between_pushes(fs):
    # As in a lab run: push, coast, caught and held still, released, pushed again.
    run, weave = simulate(4.5, fs, 16.0, ((1.0, 40.0), (8.0, -40.0)), noise=0.01,
                          holds=((6.0, 7.9), (14.0, 16.0)))
    windows = find_windows(run).windows
    assert len(windows) == 2
    first, second = windows
    assert 1.0 < first.start < 1.5 and 5.0 < first.stop <= 6.05
    assert 8.0 < second.start < 8.5 and 12.0 < second.stop <= 14.05
    for window in windows:
        assert abs(fit_window(run, window).eigenvalue - weave) < 0.1


def _coasting_share(run: Run, window: Window) -> float:
    """The share of a window of a simulated run that lies in the run's true free coasting."""
    inside = sum(max(0.0, min(window.stop, stop) - max(window.start, start))
                 for start, stop in parse_true_windows(run.metadata["true_windows"]))
    return inside / window.duration


@pytest.mark.parametrize("bicycle", ["benchmark", "kooijman2008"])
def test_a_fall_and_its_catch_are_no_window(bicycle):
    """Below the weave speed the bicycle falls within a swing or two of each push and is caught;
    the catch (a swing far quicker than the record's oscillation, starting while the bicycle
    moves fast) and the hand's return must not pass for a heavily damped free swing."""
    base = load_bicycle(bicycle)
    found = 0
    for speed in (1.5, 2.0, 3.0):
        for seed in range(4):
            truth = base.with_extensions(steer_damping=0.5) if seed % 2 else base
            run = simulate_run(truth, RunScenario(speed=speed, seed=seed, n_pushes=3))
            for window in find_windows(run).windows:
                found += 1
                assert _coasting_share(run, window) >= 0.9, (speed, seed, window)
    # Not vacuous: growth up to a catch, where it spans more than a swing, is still found.
    assert found > 0


def test_a_catch_at_the_turn_of_a_growing_weave_is_no_window():
    """Just below the weave speed the weave grows slowly and is caught when the roll angle is
    largest, where the roll rate is slow: the catch is a swing far quicker than its neighbours
    and than the record's oscillation, but does not start fast. The catch and the hand's
    ringing must not pass for a free oscillation (they did: -2.6 + 17.5i 1/s on a weave of
    0.75 + 2.7i); the growth up to it is the window."""
    base = load_bicycle("benchmark")
    grown = 0
    for speed in (3.5, 4.0):
        for seed in range(6):
            truth = base.with_extensions(payload=Payload(15.0, -0.1, -0.55)) if seed % 2 else base
            run = simulate_run(truth, RunScenario(speed=speed, seed=seed, n_pushes=3))
            for window in find_windows(run).windows:
                grown += window.reason.startswith("growth")
                assert _coasting_share(run, window) >= 0.9, (speed, seed, window)
    assert grown >= 12


def test_same_run_at_two_sample_rates_gives_the_same_windows():
    # The same sensor sampled faster: the same noise density, so sqrt(5) times the noise per
    # sample.
    slow, _ = simulate(5.5, 100, 20.0, ((3.0, 40.0), (11.0, -40.0)), noise=0.01, seed=2)
    fast, _ = simulate(5.5, 500, 20.0, ((3.0, 40.0), (11.0, -40.0)), noise=0.0224, seed=2)
    a, b = find_windows(slow).windows, find_windows(fast).windows
    assert len(a) == len(b) == 2
    period = 2 * np.pi / 5.5  # about the weave period
    for x, y in zip(a, b, strict=True):
        # The start is sharp (the end of the push); where a decay sinks into the noise is not
        # (it varies by about a period from one noise draw to the next).
        assert abs(x.start - y.start) < 0.03 and abs(x.stop - y.stop) < 2 * period


def test_quiet_record_and_a_push_without_oscillation():
    rng = np.random.default_rng(4)
    t = np.arange(0, 20, 0.01)
    quiet = Run("quiet", "<q>", t, {"roll_rate": 0.01 * rng.standard_normal(t.size)}, {}, 100.0)
    assert find_windows(quiet).windows == ()
    # A push that leaves the bicycle rolling at a new rate: nothing oscillates afterwards.
    drift = 0.01 * rng.standard_normal(t.size) + 0.5 * np.clip((t - 10) / 0.3, 0, 1)
    search = find_windows(Run("drift", "<d>", t, {"roll_rate": drift}, {}, 100.0))
    assert search.windows == ()
    assert [w.reason.split(":")[0] for w in search.rejected] == ["rejected"]
    assert "no oscillation" in search.rejected[0].reason
    with pytest.raises(RunFileError, match="no yaw_rate"):
        find_windows(quiet, signal="yaw_rate")


def test_windows_files_by_time_and_by_row(tmp_path, real_runs):
    run = real_runs[2]
    by_time = tmp_path / "w.csv"
    by_time.write_text(f"# picked by hand\nrun,start,stop\n{run.name}.log,20.28,22.46\n")
    (window,) = read_windows(by_time, real_runs)
    assert (window.start_index, window.stop_index) == (2028, 2247)
    by_row = tmp_path / "r.csv"
    by_row.write_text(f"file,start_row,stop_row\n{run.name}.log.gz,2028,2246\nother,1,5\n")
    (row_window,) = read_windows(by_row, real_runs)  # windows of other runs are left out
    assert row_window.start == pytest.approx(20.28) and row_window.stop == pytest.approx(22.46)
    unresolved = read_windows(by_time)
    assert unresolved[0].start == 20.28 and unresolved[0].start_index == -1
    out = tmp_path / "found.csv"
    write_windows(out, find_windows(run).windows)
    again = read_windows(out, [run])
    assert [w.start_index for w in again] == [w.start_index for w in find_windows(run).windows]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("run,begin,end\nx,1,2\n", "needs a run"),
        ("run,start,stop\nx,1,soon\n", "line 2: bad start/stop"),
        ("run,start,stop\nx,3,2\n", "stop must be after start"),
        ("run,start_row,stop_row\nx,1,2\n", "row windows need the run x"),
    ],
)
def test_bad_windows_files(tmp_path, text, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(RunFileError, match=message):
        read_windows(path)


def test_rows_outside_the_run(tmp_path, real_runs):
    path = tmp_path / "bad.csv"
    path.write_text(f"run,start_row,stop_row\n{real_runs[0].name},10,99999999\n")
    with pytest.raises(RunFileError, match="outside the run"):
        read_windows(path, real_runs)


def test_comparison_reports_matches_misses_and_extras():
    def window(run, start, stop):
        return Window(run, start, stop, int(100 * start), int(100 * stop) + 1)

    reference = [window("a", 1.0, 3.0), window("a", 10.0, 12.0), window("b", 1.0, 3.0)]
    found = [window("a", 1.1, 2.0), window("a", 5.0, 6.0), window("b", 2.5, 6.0)]
    comparison = compare_windows(found, reference)
    assert comparison.matched == 1
    first = comparison.matches[0]
    assert first.found is found[0]
    assert first.coverage == pytest.approx(0.45) and first.agreement == pytest.approx(1.0)
    assert comparison.unmatched == (reference[1], reference[2])  # b overlaps by 0.5 s of 2 s
    assert comparison.extra == (found[1], found[2])
