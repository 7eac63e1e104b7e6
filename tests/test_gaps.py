"""Real logs with empty cells: unused columns do not matter, gaps in used ones split windows.

The fixtures are the bundled steer-by-wire treadmill log at 12.6 km/h (sbw-treadmill layout)
with cells emptied as real logs have them: the controller's ``sil_command`` empty for the first
2,000 rows (before the controller was switched on), and stretches of ``lean_rate`` (the roll
rate) or ``speed`` missing.
"""

from __future__ import annotations

import gzip
import json
from pathlib import Path

import numpy as np
import pytest

from whipple.cli import main
from whipple.measurement.bundled import bundled_runs
from whipple.measurement.experiment import diagnosis_signals, measure_run
from whipple.measurement.measure import measure_runs
from whipple.measurement.runs import read_run
from whipple.model.parameters import load_bicycle

HEADER = "sil_command,speed,lean_angle,lean_rate,hand_angle,fork_angle,fork_rate,lean_torque,hand_torque," \
         "x_acceleration,y_acceleration,command_fork,command_hand"


def _log_lines() -> list[str]:
    entry = next(e for e in bundled_runs() if "12.6kph" in e.name)
    return gzip.decompress(entry.read_bytes()).decode().splitlines()


def _blank(lines: list[str], column: str, rows: range) -> list[str]:
    """Empty one column's cells in data rows `rows` (0-based, after the header)."""
    j = lines[0].split(",").index(column)
    out = list(lines)
    for row in rows:
        cells = out[row + 1].split(",")
        cells[j] = ""
        out[row + 1] = ",".join(cells)
    return out


def _write(path: Path, lines: list[str]) -> Path:
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture(scope="module")
def lines() -> list[str]:
    found = _log_lines()
    assert found[0] == HEADER
    return found


@pytest.fixture(scope="module")
def original(lines, tmp_path_factory):
    path = _write(tmp_path_factory.mktemp("log") / "eigen_normal_sil6.5n2_12.6kph.log", lines)
    return measure_run(read_run(path))


def _fitted(measurement) -> list[tuple[float, float, complex]]:
    return [(m.window.start, m.window.stop, m.fit.eigenvalue) for m in measurement if m.fit is not None]


def test_controller_cells_empty_before_it_starts_are_fitted(lines, original, tmp_path, capsys):
    path = _write(tmp_path / "controller_off.log", _blank(lines, "sil_command", range(2000)))
    before = path.read_bytes()
    run = read_run(path)
    assert np.isnan(run.signals["controller_torque"][:2000]).all()
    assert not np.isnan(run.signals["controller_torque"][2000:]).any()
    assert any("column 'sil_command': 2000 empty or NaN cell(s) (lines 2-2001)" in w for w in run.warnings)
    # The analysis never reads that column: the same windows and eigenvalues as the full log.
    assert _fitted(measure_run(run)) == _fitted(original) != []
    assert main(["fit", str(path), "--json", str(tmp_path / "fit.json")]) == 0
    entries = json.loads((tmp_path / "fit.json").read_text())
    assert sum(e["eigenvalue"] is not None for e in entries) == len(_fitted(original))
    assert "note: column 'sil_command': 2000 empty or NaN cell(s)" in capsys.readouterr().out
    assert path.read_bytes() == before


def test_text_in_an_unused_column_is_a_gap_there_only(lines, original, tmp_path):
    edited = list(lines)
    edited[5] = "off," + edited[5].split(",", 1)[1]
    path = _write(tmp_path / "text.log", edited)
    run = read_run(path, filled_gap=0.0)
    assert np.isnan(run.signals["controller_torque"][4])
    assert _fitted(measure_run(run)) == _fitted(original)
    # One missing sample is filled by interpolation, and noted.
    filled = read_run(path)
    assert np.isfinite(filled.signals["controller_torque"][4])
    assert "controller_torque: 1 missing sample(s) in gaps of up to 2 sample(s) filled by interpolation" in \
        filled.warnings


@pytest.mark.parametrize("column", ["lean_rate", "speed"])
def test_a_gap_in_a_used_column_splits_windows_and_is_reported(lines, original, tmp_path, column):
    windows = _fitted(original)
    # Empty 40 cells in the middle of the second fitted window.
    start, stop, _ = windows[1]
    middle = int(round((start + stop) / 2 * 100))
    gap = range(middle - 20, middle + 20)
    path = _write(tmp_path / "gap.log", _blank(lines, column, gap))
    if column == "speed":
        # A speed gap of up to 2 s is filled by a straight line (a speed logged at a lower rate):
        # no gap is left; read without filling, it is a gap as any other.
        assert not any(m.rejected and m.rejected.startswith("gap") for m in measure_run(read_run(path)))
    run = read_run(path, filled_gap=0.0)
    measured = measure_run(run)
    for m in measured:
        if m.fit is not None:
            assert m.window.stop_index <= gap.start or m.window.start_index >= gap.stop, "fitted across the gap"
    (reported,) = [m for m in measured if m.rejected and m.rejected.startswith("gap")]
    assert reported.rejected == "gap: 40 sample(s) without a value; no window spans a gap"
    assert (reported.window.start_index, reported.window.stop_index) == (gap.start, gap.stop)
    # The window that held the gap is cut into the parts before and after it.
    parts = [m for m in measured if any(note.startswith("cut at a gap") for note in m.window.notes)]
    assert [m.window.start for m in parts][0] == start
    assert parts[0].window.stop_index == gap.start and parts[-1].window.start_index == gap.stop
    # The other windows are found as before, up to small shifts: bridging the gap changes the
    # record's levels a little (its dominant frequency is estimated over the whole record).
    starts = {m.window.start for m in measured if m.fit is not None}
    assert sum(w[0] in starts for w in windows) >= 0.75 * len(windows)


def test_a_window_from_a_file_across_a_gap_is_not_fitted(lines, original, tmp_path, capsys):
    start, stop, _ = _fitted(original)[0]
    middle = int(round((start + stop) / 2 * 100))
    path = _write(tmp_path / "gap.log", _blank(lines, "lean_rate", range(middle - 5, middle + 5)))
    windows = tmp_path / "windows.csv"
    windows.write_text(f"run,start,stop\ngap,{start},{stop}\n")
    assert main(["fit", str(path), "--windows", str(windows), "--json", str(tmp_path / "out.json")]) == 2
    assert capsys.readouterr().err.count("\n") == 1  # one line: no window fitted, and why
    (entry,) = json.loads((tmp_path / "out.json").read_text())
    assert entry["eigenvalue"] is None
    assert entry["skipped"] == "window spans a gap in roll_rate (samples without a value): not fitted across it"


def test_negative_speeds_are_never_fitted(lines, tmp_path, capsys):
    j = lines[0].split(",").index("speed")
    flipped = [lines[0]] + [",".join(c if i != j else f"{-float(c):.5f}" for i, c in enumerate(line.split(",")))
                            for line in lines[1:]]
    run = read_run(_write(tmp_path / "backwards.log", flipped))
    assert any("speed is negative in" in w for w in run.warnings)
    measured = measure_run(run)
    assert not any(m.fit is not None for m in measured)
    assert any(m.rejected and m.rejected.startswith("negative speed (-3.") for m in measured)
    # The diagnosis names no cause from them.
    path = tmp_path / "backwards.log"
    assert main(["diagnose", str(path), "--bicycle", "sbw2024"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "only 0 usable window(s)" in err and "most often skipped: negative speed" in err


def test_a_bicycle_at_rest_is_never_fitted(lines, tmp_path):
    # A speed column of zeros (a logger whose speed channel was off): no window is fitted at 0 m/s.
    j = lines[0].split(",").index("speed")
    still = [lines[0]] + [",".join(c if i != j else "0" for i, c in enumerate(line.split(","))) for line in lines[1:]]
    measured = measure_run(read_run(_write(tmp_path / "still.log", still)))
    assert measured.windows and not any(m.fit is not None for m in measured)
    assert any(m.rejected and m.rejected.startswith("zero speed (0 m/s): the model needs forward speed")
               for m in measured)


def test_the_diagnosis_fits_the_steer_angle_only_where_it_loses_no_window(lines, tmp_path):
    full = read_run(_write(tmp_path / "full.log", lines))
    assert diagnosis_signals([full]) == ("roll_rate", "steer_angle")
    # A steer gap where the roll rate is measured would cost a joint fit the windows across it.
    steer_gap = read_run(_write(tmp_path / "steer_gap.log", _blank(lines, "fork_angle", range(3000, 3040))))
    assert diagnosis_signals([full, steer_gap]) == ("roll_rate",)
    # A gap in both costs those windows either way.
    both = _blank(_blank(lines, "fork_angle", range(3000, 3040)), "lean_rate", range(3000, 3040))
    assert diagnosis_signals([full, read_run(_write(tmp_path / "both.log", both))]) == ("roll_rate", "steer_angle")
    j = lines[0].split(",").index("fork_angle")
    without = [",".join(c for i, c in enumerate(line.split(",")) if i != j) for line in lines]
    assert "steer_angle" not in (no_steer := read_run(_write(tmp_path / "no_steer.log", without))).signals
    assert diagnosis_signals([full, no_steer]) == ("roll_rate",)
    assert diagnosis_signals([]) == ("roll_rate",)


def test_a_steer_angle_that_never_changes_is_not_fitted(lines, tmp_path, capsys):
    j = lines[0].split(",").index("fork_angle")
    stuck = [lines[0]] + [",".join(c if i != j else "0.0123" for i, c in enumerate(line.split(",")))
                          for line in lines[1:]]
    path = _write(tmp_path / "stuck.log", stuck)
    run = read_run(path)
    full = read_run(_write(tmp_path / "full.log", lines))
    assert diagnosis_signals([run]) == diagnosis_signals([full, run]) == ("roll_rate",)
    measured = measure_runs([run], bicycle=load_bicycle("sbw2024"))
    assert measured.steer_sign == "constant in stuck"
    assert "the steer angle does not change in stuck (a sensor not connected?), so the roll rate was fitted alone" \
        in measured.describe()
    assert any(m.usable for m in measured.windows)
    # Named, it cannot be fitted: a one-line error, not a fit of a flat line.
    assert main(["fit", str(path), "--signals", "roll_rate,steer_angle"]) == 2
    assert "steer_angle never changes (a sensor not connected?): nothing to fit" in capsys.readouterr().err
