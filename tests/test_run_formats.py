"""Run files as spreadsheets, loggers and other tools write them: units, separators, quotes, time stamps."""

from __future__ import annotations

import json
import math
from datetime import datetime, timedelta
from pathlib import Path

import numpy as np
import pytest

from whipple.cli import main
from whipple.errors import RunFileError
from whipple.measurement.experiment import measure_run
from whipple.measurement.measure import measure_runs
from whipple.measurement.reference_windows import read_windows
from whipple.measurement.runs import read_run
from whipple.measurement.units_row import is_units_row, unit_factors

N, RATE = 300, 100.0


def _signals():
    t = np.arange(N) / RATE
    return {"time": t, "roll_rate": 0.1 * np.sin(6 * t), "steer_angle": 0.01 * np.cos(6 * t),
            "speed": 4.5 - 0.01 * t}


def _text(units=None, factors=None, quote=False):
    signals = _signals()
    factors = factors or {}
    names = list(signals)
    q = (lambda cell: f'"{cell}"') if quote else (lambda cell: cell)
    lines = [",".join(q(name) for name in names)]
    if units is not None:
        lines.append(",".join(q(units.get(name, "")) for name in names))
    for i in range(N):
        lines.append(",".join(q(repr(float(signals[name][i] * factors.get(name, 1.0)))) for name in names))
    return "\n".join(lines) + "\n"


def _read(tmp_path, text):
    path = tmp_path / "run.csv"
    path.write_text(text)
    return path, read_run(path)


def test_units_row_in_other_units_is_converted_to_si(tmp_path):
    units = {"time": "ms", "roll_rate": "[deg/s]", "steer_angle": "°", "speed": "km/h"}
    factors = {"time": 1000.0, "roll_rate": 180 / math.pi, "steer_angle": 180 / math.pi, "speed": 3.6}
    path, run = _read(tmp_path, _text(units, factors))
    truth = _signals()
    np.testing.assert_allclose(run.time, truth["time"], atol=1e-12)
    np.testing.assert_allclose(run.signals["roll_rate"], truth["roll_rate"], atol=1e-12)
    np.testing.assert_allclose(run.signals["steer_angle"], truth["steer_angle"], atol=1e-12)
    np.testing.assert_allclose(run.speed(), truth["speed"], atol=1e-12)
    (note,) = [w for w in run.warnings if "row of units" in w]
    assert "line 2" in note and "roll_rate from [deg/s] to rad/s" in note and "speed from km/h to m/s" in note
    assert path.read_text() == _text(units, factors)


def test_units_row_in_si_units_or_blank_is_skipped_without_change(tmp_path):
    _, plain = _read(tmp_path, _text())
    for units in ({"time": "s", "roll_rate": "rad s^-1", "steer_angle": "(rad)", "speed": "m/s"},
                  {"time": "-", "roll_rate": "-"}):
        _, run = _read(tmp_path, _text(units))
        assert run.time.size == N
        np.testing.assert_array_equal(run.signals["roll_rate"], plain.signals["roll_rate"])
        assert not [w for w in run.warnings if "row of units" in w]


def test_unknown_unit_of_a_read_column_is_refused_naming_it(tmp_path):
    path = tmp_path / "run.csv"
    path.write_text(_text({"roll_rate": "V"}))
    with pytest.raises(RunFileError) as caught:
        read_run(path)
    message = str(caught.value)
    assert str(path) in message and "line 2" in message and "'V' for roll_rate" in message
    assert "\n" not in message


def test_quoted_header_and_cells_are_read(tmp_path):
    _, plain = _read(tmp_path, _text())
    _, quoted = _read(tmp_path, _text(quote=True))
    np.testing.assert_array_equal(quoted.signals["roll_rate"], plain.signals["roll_rate"])
    np.testing.assert_array_equal(quoted.time, plain.time)
    # R's write.csv: a first column of row names with an empty quoted header.
    rows = _text().splitlines()
    r_text = "\n".join(['"",' + ",".join(f'"{n}"' for n in rows[0].split(","))]
                       + [f'"{i}",{row}' for i, row in enumerate(rows[1:], 1)]) + "\n"
    _, r_run = _read(tmp_path, r_text)
    np.testing.assert_array_equal(r_run.signals["roll_rate"], plain.signals["roll_rate"])
    assert "ignored unknown column(s): (unnamed)" in r_run.warnings


def test_units_row_recognition():
    assert is_units_row(["s", "rad/s", ""])
    assert not is_units_row(["0.1", "rad/s"])  # a number: a data row
    assert not is_units_row(["nan", "deg"])  # NaN is a number (a gap)
    assert not is_units_row(["", " "])
    factors, notes = unit_factors({"roll_rate": "deg/s", "speed": "mph"}, 7, {"roll_rate"}, "f.csv")
    assert factors == {"speed": pytest.approx(0.44704)} and "line 7" in notes[0]  # a layout's scale wins


@pytest.mark.parametrize(("delimiter", "decimal", "note"), [(";", ",", "';'"), ("\t", ".", "tabs"), ("\t", ",", "tabs"),
                                                             (" ", ".", "blanks")])
def test_native_file_separated_otherwise_is_read(tmp_path, delimiter, decimal, note):
    _, plain = _read(tmp_path, _text())
    lines = _text().splitlines()
    other = "\n".join(line.replace(",", delimiter).replace(".", decimal) for line in lines) + "\n"
    _, run = _read(tmp_path, other)
    np.testing.assert_array_equal(run.signals["roll_rate"], plain.signals["roll_rate"])
    np.testing.assert_array_equal(run.time, plain.time)
    assert f"columns separated by {note}" in run.warnings
    assert ("decimal commas read as points" in run.warnings) == (decimal == ",")


def test_time_column_of_dates_and_times_is_read_as_seconds(tmp_path):
    _, plain = _read(tmp_path, _text())
    lines = _text().splitlines()
    start = datetime(2026, 12, 7, 23, 59, 59, 500000)  # crosses midnight
    rows = []
    for line in lines[1:]:
        time, rest = line.split(",", 1)
        rows.append(f"{(start + timedelta(seconds=float(time))).isoformat(' ', 'milliseconds')},{rest}")
    _, run = _read(tmp_path, "\n".join([lines[0], *rows]) + "\n")
    np.testing.assert_allclose(run.time, plain.time, atol=1e-9)
    np.testing.assert_array_equal(run.signals["roll_rate"], plain.signals["roll_rate"])
    assert "time read from dates and times, 0 s at 2026-12-07 23:59:59.500000" in run.warnings
    path = tmp_path / "run.csv"
    path.write_text("\n".join([lines[0], *rows[:100], "tea time," + rows[100].split(",", 1)[1], *rows[101:]]) + "\n")
    with pytest.raises(RunFileError, match="line 102, column 'time': non-numeric value 'tea time'"):
        read_run(path)


def test_units_after_the_column_names_are_read_and_converted(tmp_path):
    _, plain = _read(tmp_path, _text())
    factors = {"time": 1000.0, "roll_rate": 180 / math.pi, "steer_angle": 180 / math.pi, "speed": 3.6}
    lines = _text(factors=factors).splitlines()
    header = "time [ms],roll_rate (deg/s),steer_angle [°],speed (km/h)"
    path, run = _read(tmp_path, "\n".join([header, *lines[1:]]) + "\n")
    np.testing.assert_allclose(run.signals["roll_rate"], plain.signals["roll_rate"], atol=1e-12)
    np.testing.assert_allclose(run.time, plain.time, atol=1e-12)
    np.testing.assert_allclose(run.speed(), plain.speed(), atol=1e-12)
    assert "the header (line 1): converted time from ms to s, roll_rate from deg/s to rad/s, steer_angle from ° to " \
        "rad, speed from km/h to m/s" in run.warnings
    path.write_text("\n".join([header.replace("deg/s", "V"), *lines[1:]]) + "\n")
    with pytest.raises(RunFileError, match=r"line 1: the header gives 'V' for roll_rate, a unit whipple does not"):
        read_run(path)


def test_time_column_of_times_of_day_is_read_as_seconds(tmp_path):
    _, plain = _read(tmp_path, _text())
    lines = _text().splitlines()
    start = datetime(2026, 12, 7, 10, 0, 0)
    rows = [f"{(start + timedelta(seconds=float(line.split(',', 1)[0]))).time().isoformat('milliseconds')},"
            f"{line.split(',', 1)[1]}" for line in lines[1:]]
    _, run = _read(tmp_path, "\n".join([lines[0], *rows]) + "\n")
    np.testing.assert_allclose(run.time, plain.time, atol=1e-9)


def _logger_file(plain: Path, target: Path) -> Path:
    """Write a plain run file as a logger would: tabs, decimal commas, a units row, dates and times."""
    lines = plain.read_text().splitlines()
    meta = [line for line in lines if line.startswith("#")]
    header, *rows = [line for line in lines if not line.startswith("#")]
    names = header.split(",")
    units = {"roll_rate": "deg/s", "yaw_rate": "deg/s", "steer_angle": "deg", "speed": "km/h"}
    factors = {"roll_rate": 180 / math.pi, "yaw_rate": 180 / math.pi, "steer_angle": 180 / math.pi, "speed": 3.6}
    start = datetime(2026, 5, 1, 9, 30)
    logged = [*meta, "\t".join(names), "\t".join(units.get(name, "") for name in names)]
    for row in rows:
        cells = []
        for name, cell in zip(names, row.split(","), strict=True):
            if name == "time":
                cells.append((start + timedelta(seconds=float(cell))).isoformat(" ", "microseconds"))
            else:
                cells.append(f"{float(cell) * factors.get(name, 1.0):.12g}".replace(".", ","))
        logged.append("\t".join(cells))
    target.write_text("\n".join(logged) + "\n")
    return target


def test_a_logger_file_of_a_simulated_ground_run_gives_the_windows_of_the_plain_file(tmp_path):
    """Tabs, decimal commas, a units row with an empty first cell, dates and times: the same fits."""
    plain = tmp_path / "plain.csv"
    assert main(["simulate", "--bicycle", "benchmark", "--speed", "5", "--setting", "ground", "--seed", "3",
                 "--output", str(plain)]) == 0
    logger = _logger_file(plain, tmp_path / "logger.csv")
    ours = [m for m in measure_run(read_run(plain)) if m.fit is not None]
    theirs = [m for m in measure_run(read_run(logger)) if m.fit is not None]
    assert len(ours) == len(theirs) >= 2
    for a, b in zip(ours, theirs, strict=True):
        assert (a.window.start_index, a.window.stop_index) == (b.window.start_index, b.window.stop_index)
        assert abs(a.fit.eigenvalue - b.fit.eigenvalue) < 1e-6 * abs(a.fit.eigenvalue)


def test_diagnose_and_evaluate_say_how_each_run_file_was_read(tmp_path, capsys):
    runs = []
    for speed in (4.5, 5.5):
        plain = tmp_path / f"plain_{speed}.csv"
        assert main(["simulate", "--bicycle", "benchmark", "--speed", str(speed), "--seed", "1",
                     "--output", str(plain)]) == 0
        runs.append(_logger_file(plain, tmp_path / f"logger_{speed}.csv"))
    capsys.readouterr()
    report, data = tmp_path / "report", tmp_path / "diagnosis.json"
    assert main(["diagnose", *map(str, runs), "--bicycle", "benchmark", "--report", str(report),
                 "--json", str(data)]) == 0
    printed = capsys.readouterr().out
    assert "  note (logger_4.5): the row of units under the header (line " in printed
    notes = json.loads(data.read_text())["measurement"]["run_notes"]
    assert set(notes) == {"logger_4.5", "logger_5.5"} and "decimal commas read as points" in notes["logger_5.5"]
    markdown = (report / "report.md").read_text()
    assert "## How the run files were read" in markdown and "- logger_5.5: columns separated by tabs" in markdown
    assert main(["evaluate", *map(str, runs), "--bicycle", "benchmark", "--no-samples"]) == 0
    assert "  note (logger_5.5): decimal commas read as points" in capsys.readouterr().out


def test_column_names_other_than_the_specs_only_in_case_blanks_or_units_are_read(tmp_path):
    _, plain = _read(tmp_path, _text())
    lines = _text(factors={"roll_rate": 180 / math.pi}).splitlines()
    _, run = _read(tmp_path, "\n".join(["Time,Roll Rate (deg/s),steer-angle,SPEED", *lines[1:]]) + "\n")
    np.testing.assert_allclose(run.signals["roll_rate"], plain.signals["roll_rate"], atol=1e-12)
    np.testing.assert_array_equal(run.signals["steer_angle"], plain.signals["steer_angle"])
    np.testing.assert_array_equal(run.time, plain.time)
    assert ("column names read as the run-file spec's: 'Time' as time, 'Roll Rate' as roll_rate, 'steer-angle' as "
            "steer_angle, 'SPEED' as speed") in run.warnings
    # A name the header already holds exactly keeps its column; the other is an unknown column.
    _, both = _read(tmp_path, "\n".join(["time,roll_rate,Steer_Angle,speed", *_text().splitlines()[1:]]) + "\n")
    assert "steer_angle" in both.signals


def test_a_clock_restarted_for_each_trial_is_read_as_parts_with_a_gap(tmp_path):
    signals = _signals()
    lines = _text().splitlines()
    rows = []
    for k, line in enumerate(lines[1:]):
        time, rest = line.split(",", 1)
        rows.append(f"{float(time) - (1.5 if k >= 150 else 0.0)!r},{rest}")  # restarts at 0 after 1.5 s
    _, run = _read(tmp_path, "\n".join([lines[0], *rows]) + "\n")
    assert run.time.size == N and np.all(np.diff(run.time) > 0)
    np.testing.assert_allclose(run.time[150] - run.time[149], 1.0, atol=1e-9)  # a pause of 1 s
    np.testing.assert_array_equal(run.signals["roll_rate"], signals["roll_rate"])
    assert any(note.startswith("time goes back at data row(s) 150 (a clock restarted?)") for note in run.warnings)
    # A time that goes back by less than a second is disorder, not a restart: an error.
    path = tmp_path / "run.csv"
    path.write_text(_text().replace("\n0.5,", "\n0.3,", 1))
    with pytest.raises(RunFileError, match="time is not strictly increasing at data row 50"):
        read_run(path)


@pytest.mark.parametrize("text", ["run,start,stop\nrun,0.5,2.5\n", "run;start;stop\nrun;0,5;2,5\n",
                                  "run\tstart\tstop\nrun\t0.5\t2.5\n", '"run","start","stop"\n"run",0.5,2.5\n'])
def test_windows_files_separated_otherwise_are_read(tmp_path, text):
    _, run = _read(tmp_path, _text())
    windows = tmp_path / "windows.csv"
    windows.write_text(text)
    (window,) = read_windows(windows, [run])
    assert (window.start, window.stop) == (0.5, 2.5)


def test_a_last_line_cut_short_is_left_out_and_one_inside_the_file_is_refused(tmp_path):
    text = _text()
    path, run = _read(tmp_path, text + "2.99,0.01\n")  # a logger that lost power mid-line
    assert run.time.size == N
    assert f"the last line ({N + 2}) has 2 of the header's 4 fields (a file cut short?): left out" in run.warnings
    lines = text.splitlines()
    path.write_text("\n".join([*lines[:10], "0.095,0.01", *lines[10:]]) + "\n")
    with pytest.raises(RunFileError, match="line 11 has 2 fields, the header has 4"):
        read_run(path)


def test_numbers_in_a_time_column_are_never_read_as_times_of_day(tmp_path):
    """'1000' would be 10:00 and '20261207' a date as ISO 8601: a column with numbers is numbers."""
    lines = _text().splitlines()
    rows = [f"{1000 + 10 * k},{line.split(',', 1)[1]}" for k, line in enumerate(lines[1:])]
    rows[5] = "---," + rows[5].split(",", 1)[1]
    path = tmp_path / "run.csv"
    path.write_text("\n".join([lines[0], *rows]) + "\n")
    with pytest.raises(RunFileError, match="line 7, column 'time': non-numeric value '---'"):
        read_run(path)


def test_metadata_values_may_carry_their_unit(tmp_path):
    _, plain = _read(tmp_path, _text())
    _, run = _read(tmp_path, "# sample_rate: 100 Hz\n# speed: 4.5 m/s\n" + _text())
    np.testing.assert_array_equal(run.time, plain.time)
    path = tmp_path / "run.csv"
    path.write_text("# sample_rate: 100 kHz\n" + _text())
    with pytest.raises(RunFileError, match=r"metadata 'sample_rate' is not a number \(in Hz\): '100 kHz'"):
        read_run(path)


def test_a_roll_rate_in_degrees_per_second_without_a_steer_angle_is_named(tmp_path):
    plain = tmp_path / "plain.csv"
    assert main(["simulate", "--bicycle", "benchmark", "--speed", "5", "--seed", "2", "--no-steer-angle",
                 "--output", str(plain)]) == 0
    lines = plain.read_text().splitlines()
    header = next(k for k, line in enumerate(lines) if not line.startswith("#"))
    j = lines[header].split(",").index("roll_rate")
    degrees = [*lines[:header + 1]]
    for line in lines[header + 1:]:
        cells = line.split(",")
        cells[j] = repr(float(cells[j]) * 180 / math.pi)
        degrees.append(",".join(cells))
    path = tmp_path / "degrees.csv"
    path.write_text("\n".join(degrees) + "\n")
    assert measure_runs([read_run(plain)]).roll_units is None
    measured = measure_runs([read_run(path)])
    assert measured.roll_units is not None and "is the roll rate in deg/s?" in measured.describe()
