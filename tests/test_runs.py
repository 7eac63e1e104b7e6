"""Reading run files: the native CSV, layouts, the bundled treadmill logs, and bad input."""

from __future__ import annotations

import gzip
import hashlib

import numpy as np
import pytest

from whipple.errors import InputError, RunFileError
from whipple.measurement.bundled import (
    bundled_experiment_bicycle,
    bundled_folder,
    bundled_reference_windows,
    bundled_runs,
)
from whipple.measurement.layouts import builtin_layouts, load_layout
from whipple.measurement.reference_windows import read_windows
from whipple.measurement.runs import read_run

HEADER = "# sample_rate: 100\n# wheel_radius: 0.35\n# pulses_per_revolution: 20\n"


def native_text(n=300, fs=100.0, time_column=True, extra="", speed=True):
    t = np.arange(n) / fs
    columns = {"roll_rate": 0.1 * np.sin(6 * t), "steer_angle": 0.01 * np.cos(6 * t)}
    if speed:
        columns["speed"] = 4.5 - 0.01 * t
    if time_column:
        columns = {"time": t, **columns}
    names = list(columns) + ([extra] if extra else [])
    rows = [",".join(f"{columns[c][i]:.6f}" if c in columns else "1" for c in names)
            for i in range(n)]
    return "\n".join([",".join(names), *rows]) + "\n"


def write(tmp_path, text, name="run.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_native_file_with_time_column(tmp_path):
    path = write(tmp_path, "# bicycle: kooijman2008\n# note: first try\n" + native_text())
    run = read_run(path)
    assert run.name == "run" and run.source == str(path)
    assert run.sample_rate == pytest.approx(100.0)
    assert run.duration == pytest.approx(2.99)
    assert set(run.signals) == {"roll_rate", "steer_angle", "speed"}
    assert run.metadata == {"bicycle": "kooijman2008", "note": "first try"}
    assert run.warnings == ()
    np.testing.assert_allclose(run.speed(), 4.5 - 0.01 * run.time, atol=1e-6)
    with pytest.raises(ValueError):
        run.signals["roll_rate"][0] = 1.0  # arrays are read-only


def test_sample_rate_instead_of_time_and_unknown_columns(tmp_path):
    path = write(tmp_path, HEADER + native_text(time_column=False, extra="humidity"))
    run = read_run(path)
    np.testing.assert_allclose(run.time[:3], [0.0, 0.01, 0.02])
    assert "humidity" not in run.signals
    assert run.warnings == ("ignored unknown column(s): humidity",)


def test_gzip_is_read_transparently(tmp_path):
    path = tmp_path / "run.csv.gz"
    path.write_bytes(gzip.compress(native_text().encode()))
    run = read_run(path)
    assert run.name == "run" and run.time.size == 300


def test_speed_from_speedometer_and_from_metadata(tmp_path):
    fs = 500
    t = np.arange(0, 3, 1 / fs)
    signal = np.sin(20 * 4.0 * t / (2 * 0.35))
    rows = "\n".join(f"{a:.5f},{b:.5f}" for a, b in zip(0.1 * np.sin(5 * t), signal, strict=True))
    run = read_run(write(tmp_path, HEADER.replace("100", str(fs))
                         + "roll_rate,speedometer\n" + rows + "\n"))
    assert run.speed()[fs:-fs].mean() == pytest.approx(4.0, rel=1e-3)
    text = "# sample_rate: 100\n# speed: 3.2\n" + native_text(time_column=False, speed=False)
    assert read_run(write(tmp_path, text, "c.csv")).speed() == pytest.approx(3.2)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty file"),
        ("\n\n", "empty file"),
        ("time,steer_angle,speed\n0,1,2\n", "missing roll_rate column (the header has 'time', 'steer_angle', 'speed'; "
                                             "a layout's [columns] maps another name)"),
        ("time,gyro_x (deg/s),speed\n0,1,2\n", "missing roll_rate column (the header has 'time', 'gyro_x (deg/s)', "
                                               "'speed'; a layout's [columns] maps another name)"),
        (native_text().replace("0.020000,", "0.005000,", 1), "not strictly increasing at data row 2"),
        (native_text(n=90), "too short"),
        (native_text(speed=False), "missing speed information"),
        ("time,roll_rate,speed\n" + "".join(f"{i / 100},0.1,4\n" for i in range(300)).replace(
            "0.1,4\n", "inf,4\n", 1), "line 2, column 'roll_rate': inf value"),
        ("time,roll_rate,speed\n" + "".join(f"{i / 100},,4\n" for i in range(300)), "column roll_rate has no values"),
        (native_text().replace("4.500000", "fast", 1), "column 'speed': non-numeric value 'fast'"),
        (native_text().replace("4.500000\n", "4.500000,9\n", 1), "line 2 has 5 fields, the header has 4"),
        (native_text(time_column=False), "no time column and no sample_rate"),
        (native_text().replace("time,", "timestamp,", 1),
         "no time column and no sample_rate (the header has 'timestamp': the exact name is time"),
        ("# sample_rate: quick\n" + native_text(time_column=False), "'sample_rate' is not a number"),
        ("# speed: 3\n# sample_rate: 100\nroll_rate,speedometer\n" + "0,1\n" * 300,
         "missing metadata 'wheel_radius'"),
    ],
)
def test_bad_run_files(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(RunFileError) as caught:
        read_run(path)
    assert message in str(caught.value)
    assert str(path) in str(caught.value)
    assert "\n" not in str(caught.value)
    assert isinstance(caught.value, InputError)


def test_missing_file(tmp_path):
    with pytest.raises(RunFileError, match="cannot read file"):
        read_run(tmp_path / "nowhere.csv")


LAYOUT = """
name = "lab-logger"
delimiter = "whitespace"
header = false
names = ["t_ms", "gyro", "checksum", "wheel"]
comment = "%"
ignore = ["checksum"]

[columns]
t_ms = "time"
gyro = "roll_rate"

[scale]
time = 0.001
roll_rate = -0.017453292519943295

[speed]
source = "constant"
value = 4.2

[metadata]
bicycle = "lab bike"
"""


def test_custom_layout_describes_foreign_files(tmp_path):
    layout = write(tmp_path, LAYOUT, "lab.toml")
    rows = "\n".join(f"{10 * i} {10.0 * np.sin(0.05 * i):.4f} 77 1.0" for i in range(400))
    path = write(tmp_path, "% lab logger v2\n" + rows + "\n", "log.txt")
    run = read_run(path, layout=layout)
    assert run.time[1] == pytest.approx(0.01)
    # Degrees per second to radians per second, and a sign flip.
    assert run.signals["roll_rate"][10] == pytest.approx(-np.radians(10.0 * np.sin(0.5)), abs=1e-5)
    assert run.speed() == pytest.approx(4.2)
    assert run.metadata["bicycle"] == "lab bike"
    assert run.warnings == ("ignored unknown column(s): wheel",)


def test_a_column_named_time_is_the_time_without_a_columns_entry(tmp_path):
    # A logger that writes "time" in ms, its rates in deg/s: the layout maps the rates only.
    t = np.arange(250) * 10.0
    rows = "\n".join(f"{a:.1f},{b:.4f},4.5" for a, b in zip(t, 5.0 * np.sin(t / 200), strict=True))
    path = write(tmp_path, "time,gyro_x,v\n" + rows + "\n")
    mapped = 'name = "lab"\n[columns]\ngyro_x = "roll_rate"\nv = "speed"\n'
    run = read_run(path, layout=write(tmp_path, mapped + "[scale]\ntime = 0.001\n", "lab.toml"))
    assert run.sample_rate == pytest.approx(100.0) and run.time[-1] == pytest.approx(2.49)
    assert run.warnings == ()
    # A column mapped to time wins; one the layout ignores stays ignored.
    other = read_run(path, layout=write(tmp_path, 'sample_rate = 50\nignore = ["time"]\n' + mapped, "b.toml"))
    assert other.sample_rate == 50.0 and other.time[-1] == pytest.approx(4.98)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("gyro = \"roll_rate\"", "gyro = \"lean\""), "'lean' is not a run-file column"),
        (("gyro = \"roll_rate\"", "gyro = \"yaw_rate\""), "no column maps to roll_rate"),
        (("roll_rate = -0.0174", "roll_rate = 0 #"), r"\[scale\] must map"),
        (("header = false", "header = false\ncolour = 3"), "unknown key"),
        (("source = \"constant\"", "source = \"psychic\""), "source must be one of"),
        (("delimiter = \"whitespace\"", "delimiter = \";;\""), "delimiter must be"),
        (("[columns]", "[columns"), "bad layout file"),
    ],
)
def test_bad_layout_files(tmp_path, change, message):
    layout = write(tmp_path, LAYOUT.replace(*change), "lab.toml")
    with pytest.raises(RunFileError, match=message):
        read_run(write(tmp_path, "1 2 3 4\n"), layout=layout)


def test_unknown_layout_name(tmp_path):
    with pytest.raises(RunFileError, match="built-in layouts: sbw-treadmill"):
        read_run(write(tmp_path, native_text()), layout="no-such-layout")


def test_bundled_treadmill_logs_are_recognised_and_mapped():
    files = bundled_runs()
    assert [f.name for f in files] == [
        f"eigen_normal_sil6.5n2_{speed}kph.log.gz" for speed in ("5.4", "9", "12.6", "16.2", "18")
    ]
    assert "sbw-treadmill" in builtin_layouts()
    run = read_run(files[2])
    assert run.name == "eigen_normal_sil6.5n2_12.6kph"
    assert run.sample_rate == 100.0 and run.time.size == 12892
    assert run.warnings == ()
    assert {"roll_rate", "roll_angle", "steer_angle", "steer_rate", "speed", "steer_torque",
            "lateral_acceleration", "controller_torque"} <= set(run.signals)
    # Meijaard signs: the logged controller torque is K(v) * roll rate with K = 2 (6.5 - v) > 0,
    speed, roll_rate = run.speed(), run.signals["roll_rate"]
    np.testing.assert_allclose(run.signals["controller_torque"], 2 * (6.5 - speed) * roll_rate,
                               atol=2e-3)
    # the roll rate is the derivative of the roll angle, and the bicycle steers into its lean.
    derivative = np.gradient(run.signals["roll_angle"], run.time)
    assert np.corrcoef(derivative, roll_rate)[0, 1] > 0.95
    assert np.corrcoef(run.signals["roll_angle"], run.signals["steer_angle"])[0, 1] > 0.5
    assert 3.4 < np.median(speed) < 3.7
    explicit = read_run(files[2], layout="sbw-treadmill")
    np.testing.assert_array_equal(explicit.signals["roll_rate"], roll_rate)


def test_bundled_runs_of_both_experiments():
    speeds = ("5.4", "9", "12.6", "16.2", "18")
    assert bundled_runs() == bundled_runs("model-matching-off")
    on = bundled_runs("model-matching-on")
    assert [f.name for f in on] == [f"eigen_mm_sil6.5n2_{speed}kph.log.gz" for speed in speeds]
    assert bundled_experiment_bicycle("model-matching-on") == "sbw2024-mm"
    assert bundled_experiment_bicycle("model-matching-off") == "sbw2024"
    with pytest.raises(InputError, match="no bundled experiment 'mm'.*model-matching-on"):
        bundled_runs("mm")
    run = read_run(on[1])
    assert run.name == "eigen_mm_sil6.5n2_9kph" and run.sample_rate == 100.0
    assert 2.4 < np.median(run.speed()) < 2.6
    # The logs as the repository holds them, read by the built-in layout.
    with gzip.open(on[1], "rt") as log:
        assert log.readline().startswith("sil_command,speed,lean_angle,lean_rate")
    # The reference windows hold both experiments; each set of runs keeps its own.
    on_runs = [read_run(entry) for entry in on[2:4]]
    windows = read_windows(bundled_reference_windows(), on_runs)
    assert len(windows) == 14 and {w.run for w in windows} == {r.name for r in on_runs}


def test_bundled_data_carries_licence_and_provenance():
    folder = bundled_folder()
    assert folder.joinpath("LICENCE").read_text().startswith("MIT License")
    readme = folder.joinpath("README.md").read_text()
    assert "2e7bb2451997fa821b5e90bf6ca5d2acbb7948a8" in readme
    assert "mechmotum/sbw_bicycle_with_model_matching" in readme
    assert bundled_reference_windows().read_text().startswith("file,treadmill_speed_kph,")
    assert load_layout("sbw-treadmill").sample_rate == 100.0


def test_reading_never_changes_the_file(tmp_path):
    path = write(tmp_path, HEADER + native_text(time_column=False))
    before = hashlib.sha256(path.read_bytes()).hexdigest()
    read_run(path)
    assert hashlib.sha256(path.read_bytes()).hexdigest() == before
