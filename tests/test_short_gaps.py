"""Short gaps filled by interpolation: dropped rows and empty cells cost no window."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from whipple.cli import main
from whipple.measurement.experiment import measure_run
from whipple.measurement.runs import read_run
from whipple.measurement.short_gaps import fill_short_gaps, fill_speed_gaps, longest_filled


def _weave(time: np.ndarray) -> np.ndarray:
    return 0.5 * np.exp(-0.8 * time) * np.sin(8.0 * time + 0.3)  # a fast weave: 8 rad/s


def test_dropped_rows_and_empty_cells_get_the_cubic_through_their_neighbours():
    time = np.arange(0.0, 3.0, 0.01)
    keep = np.ones(time.size, dtype=bool)
    keep[[50, 120, 121]] = False  # one row dropped, then two in a row
    keep[200:203] = False  # three in a row: 0.03 s, beyond the 0.02 s filled
    roll = _weave(time)
    roll[[80, 150, 151]] = np.nan  # empty cells, one and two in a row
    roll[[0, 1]] = np.nan  # at the record's start: no neighbour before them
    signals = {"roll_rate": roll[keep].copy(), "speedometer": np.where(np.arange(time.size) % 10 < 5, 5.0, 0.0)[keep]}
    filled_time, notes = fill_short_gaps(time[keep].copy(), signals)
    assert filled_time.size == time.size - 3  # the three rows of the long jump stay out
    back = np.isin(np.round(time * 100), np.round(filled_time * 100))
    assert np.allclose(filled_time, time[back])
    values = signals["roll_rate"]
    inside = np.isfinite(roll[back])
    assert np.max(np.abs(values[inside] - roll[back][inside])) < 1e-4 * 0.5
    assert np.max(np.abs(values[[80, 150, 151]] - _weave(time[[80, 150, 151]]))) < 1e-4 * 0.5
    assert np.isnan(values[:2]).all()  # no neighbours before them: a gap
    # A speedometer's pulses by straight lines: never beyond the pulse's levels.
    assert np.all((signals["speedometer"] >= 0) & (signals["speedometer"] <= 5))
    assert notes == ["3 dropped row(s) put back in 2 jump(s) in time of up to 2 sample(s), their values filled by "
                     "interpolation",
                     "roll_rate: 3 missing sample(s) in gaps of up to 2 sample(s) filled by interpolation"]


@pytest.mark.parametrize("rate, most", [(50.0, 1), (100.0, 2), (200.0, 4), (1000.0, 20)])
def test_the_longest_gap_filled_is_two_samples_at_100_hz(rate, most):
    assert longest_filled(1.0 / rate) == most


def test_nothing_filled_when_asked_not_to():
    time = np.array([0.0, 0.01, 0.03, 0.04])
    signals = {"roll_rate": np.array([0.0, np.nan, 1.0, 2.0])}
    assert fill_short_gaps(time, signals, 0.0) == (time, [])
    assert np.isnan(signals["roll_rate"][1])


def _dropped(run_file: Path, target: Path, share: float, seed: int) -> Path:
    lines = run_file.read_text(encoding="utf-8").splitlines()
    header = next(k for k, line in enumerate(lines) if not line.startswith("#"))
    rng = np.random.default_rng(seed)
    rows = [line for line in lines[header + 1:] if rng.random() >= share]
    target.write_text("\n".join([*lines[:header + 1], *rows]) + "\n", encoding="utf-8")
    return target


@pytest.fixture(scope="module")
def run_file(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("drops") / "run.csv"
    assert main(["simulate", "--bicycle", "benchmark", "--speed", "5", "--seed", "3", "--output", str(path)]) == 0
    return path


def test_a_logger_that_drops_one_row_in_twenty_loses_no_window(run_file, tmp_path, capsys):
    clean = [m.fit for m in measure_run(read_run(run_file)) if m.fit is not None]
    path = _dropped(run_file, tmp_path / "dropped.csv", 0.05, seed=0)
    before = path.read_bytes()
    run = read_run(path)
    assert any("dropped row(s) put back" in note for note in run.warnings)
    fitted = [m.fit for m in measure_run(run) if m.fit is not None]
    assert len(fitted) == len(clean) == 3
    for a, b in zip(clean, fitted, strict=True):
        assert abs(a.start - b.start) < 0.1 and abs(a.stop - b.stop) < 0.1
        # 5% fewer samples: the estimate moves by sampling variation, a fraction of its error.
        std = np.sqrt(np.diag(a.covariance))[:2]
        assert abs(a.damping - b.damping) < 2 * std[0] and abs(a.frequency - b.frequency) < 2 * std[1]
        assert np.allclose(np.sqrt(np.diag(b.covariance))[:2], std, rtol=0.1)
    # Without filling, every dropped row is a gap that no window spans.
    unfilled = [m for m in measure_run(read_run(path, filled_gap=0.0))]
    assert sum(m.fit is not None and m.quality is None for m in unfilled) < len(clean)
    capsys.readouterr()
    assert main(["fit", str(path)]) == 0
    assert "dropped row(s) put back in" in capsys.readouterr().out
    assert path.read_bytes() == before


def test_a_row_sent_twice_is_dropped_and_a_time_repeated_with_other_values_is_refused(run_file, tmp_path, capsys):
    lines = run_file.read_text(encoding="utf-8").splitlines()
    header = next(k for k, line in enumerate(lines) if not line.startswith("#"))
    twice = [*lines[:header + 502], lines[header + 501], *lines[header + 502:]]  # data row 500 sent again
    path = tmp_path / "twice.csv"
    path.write_text("\n".join(twice) + "\n", encoding="utf-8")
    run = read_run(path)
    assert "1 repeated row(s) (the same time and values as the row before) dropped" in run.warnings
    assert np.array_equal(run.time, read_run(run_file).time)
    cells = lines[header + 501].split(",")
    other = [*lines[:header + 502], ",".join([cells[0], "0.5", *cells[2:]]), *lines[header + 502:]]
    path = tmp_path / "other.csv"
    path.write_text("\n".join(other) + "\n", encoding="utf-8")
    capsys.readouterr()
    assert main(["fit", str(path)]) == 2
    assert capsys.readouterr().err == (f"whipple fit: error: {path}: time repeats with other values than the row "
                                       "before at data row 501 (t = 5 s)\n")


def test_the_cubic_across_two_missing_samples_is_off_a_fast_weave_by_at_most_5e_5_of_its_amplitude():
    time = np.arange(0.0, 0.1, 0.01)
    worst = 0.0
    for phase in np.linspace(0.0, 2 * np.pi, 73):
        weave = np.sin(10.0 * time + phase)  # 10 rad/s, unit amplitude
        signals = {"roll_rate": np.where(np.isin(np.arange(time.size), [4, 5]), np.nan, weave)}
        fill_short_gaps(time, signals)
        worst = max(worst, float(np.max(np.abs(signals["roll_rate"] - weave))))
    assert 1e-5 < worst <= 5e-5


@pytest.mark.parametrize("speed_rate", [1.0, 10.0])
def test_a_speed_logged_at_a_lower_rate_is_filled_and_costs_no_window(run_file, tmp_path, speed_rate):
    clean = [m for m in measure_run(read_run(run_file)) if m.fit is not None]
    lines = run_file.read_text(encoding="utf-8").splitlines()
    header = next(k for k, line in enumerate(lines) if not line.startswith("#"))
    names = lines[header].split(",")
    speed_column, every = names.index("speed"), int(round(100 / speed_rate))
    rows = []
    for k, line in enumerate(lines[header + 1:]):
        cells = line.split(",")
        if k % every:
            cells[speed_column] = ""
        rows.append(",".join(cells))
    path = tmp_path / "sparse.csv"
    path.write_text("\n".join([*lines[:header + 1], *rows]) + "\n", encoding="utf-8")
    run = read_run(path)
    assert any("filled by straight lines (a speed logged at a lower rate" in note for note in run.warnings)
    fitted = [m for m in measure_run(run) if m.fit is not None]
    assert len(fitted) == len(clean) == 3
    for a, b in zip(clean, fitted, strict=True):
        assert abs(a.fit.start - b.fit.start) < 0.1 and abs(a.fit.stop - b.fit.stop) < 0.1
        # The simulated speed sensor's noise is 0.02 m/s; a speed from one sample in 100 moves by that.
        assert abs(a.speed.mean - b.speed.mean) < 0.05
    assert np.isnan(read_run(path, filled_gap=0.0).signals["speed"]).sum() > 0  # asked not to fill


def test_speed_gaps_are_filled_by_straight_lines_up_to_two_seconds():
    time = np.arange(0.0, 10.0, 0.01)
    speed = 5.0 - 0.05 * time
    sparse = speed.copy()
    sparse[101:300] = np.nan  # 2 s between measured speeds: filled
    sparse[401:702] = np.nan  # 3 s: stays a gap
    sparse[950:] = np.nan  # at the end: no speed after it
    notes = fill_speed_gaps(time, sparse)
    assert np.allclose(sparse[101:300], speed[101:300])
    assert np.isnan(sparse[401:702]).all() and np.isnan(sparse[950:]).all()
    assert notes == ["speed: 199 missing sample(s) in gaps of up to 2 s filled by straight lines (a speed logged at "
                     "a lower rate than the other signals?)"]
