"""Bad layout files, run-file metadata and numbers: one line naming the file, never silent.

A layout's mistakes are blamed on the layout (not on the run read with it), a run file that
gives a metadata key twice is refused, and numbers are ASCII decimal text: Python's float()
also reads Unicode digits ('١٢' is 12.0), which no logger writes as a number. Valid layouts,
the documented example and the built-in one among them, still load.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from whipple.cli import main
from whipple.errors import InputError, RunFileError
from whipple.measurement.layouts import load_layout, parse_number
from whipple.measurement.reference_windows import read_windows
from whipple.measurement.runs import read_run
from whipple.model.parameters import load_bicycle
from whipple.simulation.run_writer import write_run_csv
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

DOCS = Path(__file__).resolve().parents[1] / "docs"

#: A valid layout for the native run files the simulator writes; the cases below edit it.
LAYOUT = """\
name = "native-again"
[columns]
time = "time"
roll_rate = "roll_rate"
yaw_rate = "yaw_rate"
steer_angle = "steer_angle"
speed = "speed"
"""

BIG = "9" * 400


@pytest.fixture(scope="module")
def run_text(tmp_path_factory) -> str:
    """A simulated benchmark run at 5 m/s (native CSV, 100 Hz, with a time column)."""
    folder = tmp_path_factory.mktemp("run")
    run = simulate_run(load_bicycle("benchmark"), RunScenario(speed=5.0, seed=1), name="run5")
    return write_run_csv(run, folder / "run5.csv").read_text()


def write(folder: Path, name: str, content: str | bytes) -> Path:
    path = folder / name
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8")
    return path


def cli_error(capsys, argv: list[str | Path]) -> str:
    """Run ``whipple`` on `argv`, check exit 2 and one stderr line without traceback; return it."""
    code = main([str(arg) for arg in argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err
    assert err.endswith("\n") and err.count("\n") == 1, err
    return err.rstrip("\n")


def without_time(run_text: str, extra_metadata: str) -> str:
    """The run without its time column, `extra_metadata` lines added before the header."""
    lines = run_text.splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    body = [line.split(",", 1)[1] for line in lines[header:]]
    return "\n".join([*lines[:header], *extra_metadata.splitlines(), *body]) + "\n"


def test_layout_that_is_not_utf8(tmp_path, run_text, capsys):
    layout = write(tmp_path, "bin.toml", b"\xff\xfe")
    run = write(tmp_path, "run5.csv", run_text)
    with pytest.raises(RunFileError, match="bad layout file: not a text file") as caught:
        load_layout(layout)
    assert caught.value.source == str(layout)
    line = cli_error(capsys, ["fit", run, "--layout", layout])
    assert line == f"whipple fit: error: {layout}: bad layout file: not a text file (invalid UTF-8)"


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (f"sample_rate = {BIG}\n" + LAYOUT, "sample_rate must be a positive number [Hz], got an integer of 400 digits"),
        (LAYOUT + f"[scale]\nroll_rate = {BIG}\n", "[scale] must map column names to finite non-zero numbers, "
                                                   "got 'roll_rate' = an integer of 400 digits"),
        (LAYOUT + f"[speed]\nwheel_radius = {BIG}\n", "[speed] wheel_radius must be a positive number"),
        # More digits than Python converts to an int: tomllib raises a plain ValueError.
        (f"sample_rate = {'9' * 5000}\n" + LAYOUT, "an integer with too many digits to read"),
    ],
    ids=["sample_rate", "scale", "wheel_radius", "5000 digits"],
)
def test_huge_integers_in_a_layout(tmp_path, run_text, capsys, text, message):
    layout = write(tmp_path, "big.toml", text)
    run = write(tmp_path, "run5.csv", run_text)
    line = cli_error(capsys, ["fit", run, "--layout", layout])
    assert line.startswith(f"whipple fit: error: {layout}: bad layout file: ")
    assert message in line
    assert len(line) < 300


BAD_LAYOUTS = {
    "two columns to roll_rate": (LAYOUT.replace('yaw_rate = "yaw_rate"', 'yaw_rate = "roll_rate"'),
                                 "[columns] maps file column 'yaw_rate' to 'roll_rate', which file column "
                                 "'roll_rate' already gives"),
    "extra replaces a column": (LAYOUT.replace('yaw_rate = "yaw_rate"\n', "") + '[extra]\nyaw_rate = "roll_rate"\n',
                                "[extra] maps file column 'yaw_rate' to 'roll_rate'"),
    "two extras, one name": (LAYOUT + '[extra]\na = "acc"\nb = "acc"\n', "[extra] maps file column 'b' to 'acc'"),
    "column in columns and extra": (LAYOUT + '[extra]\nyaw_rate = "yaw"\n',
                                    "file column 'yaw_rate' is in both [columns] and [extra]"),
    "scale inf": (LAYOUT + "[scale]\nroll_rate = inf\n", "got 'roll_rate' = inf"),
    "scale nan": (LAYOUT + "[scale]\nroll_rate = nan\n", "got 'roll_rate' = nan"),
    "scale zero": (LAYOUT + "[scale]\nroll_rate = 0\n", "got 'roll_rate' = 0"),
    "scale string": (LAYOUT + "[scale]\nroll_rate = \"2\"\n", "got 'roll_rate' = '2'"),
    "scale unknown column": (LAYOUT + "[scale]\nfoo = 2\n", "[scale] names 'foo', which is no column this layout maps"),
    "scale unmapped spec column": (LAYOUT + "[scale]\nbattery = 2\n", "[scale] names 'battery'"),
    "sample_rate nan": ("sample_rate = nan\n" + LAYOUT, "sample_rate must be a positive number [Hz], got nan"),
    "sample_rate inf": ("sample_rate = inf\n" + LAYOUT, "sample_rate must be a positive number [Hz], got inf"),
    "sample_rate zero": ("sample_rate = 0\n" + LAYOUT, "sample_rate must be a positive number [Hz], got 0"),
    "wheel_radius -1": (LAYOUT + "[speed]\nwheel_radius = -1\n",
                        "[speed] wheel_radius must be a positive number, got -1"),
    "wheel_radius 0": (LAYOUT + "[speed]\nwheel_radius = 0\n", "[speed] wheel_radius must be a positive number, got 0"),
    "wheel_radius nan": (LAYOUT + "[speed]\nwheel_radius = nan\n", "[speed] wheel_radius must be a positive number"),
    "pulses true": (LAYOUT + "[speed]\npulses_per_revolution = true\n", "[speed] pulses_per_revolution must be"),
    "speed value negative": (LAYOUT + "[speed]\nsource = \"constant\"\nvalue = -4\n", "[speed] value must be"),
    "constant without value": (LAYOUT + "[speed]\nsource = \"constant\"\n",
                               "[speed] source = \"constant\" needs value"),
    "speed unknown key": (LAYOUT + "[speed]\nradius = 0.3\n", "unknown key(s) in [speed]: radius"),
    "ignore a string": ('ignore = "yaw_rate"\n' + LAYOUT, "ignore must be a list of strings, got 'yaw_rate'"),
    "names a string": ('header = false\nnames = "time"\n' + LAYOUT, "names must be a list of strings"),
    "names twice": ('header = false\nnames = ["time", "time", "roll_rate", "yaw_rate", "steer_angle", "speed"]\n'
                    + LAYOUT, "names lists 'time' twice"),
    "column not in names": ('header = false\nnames = ["time", "roll_rate", "steer_angle", "speed"]\n' + LAYOUT,
                            "file column 'yaw_rate' of [columns]/[extra] is not in names"),
    "comment a number": ("comment = 5\n" + LAYOUT, "comment must be a string, got 5"),
    "metadata table": (LAYOUT + "[metadata.bicycle]\nname = 'x'\n",
                       "[metadata] 'bicycle' must be a string or a number"),
    "metadata sample_rate nan": (LAYOUT + "[metadata]\nsample_rate = nan\n",
                                 "[metadata] sample_rate must be a positive number, got nan"),
    "metadata speed text": (LAYOUT + "[metadata]\nspeed = \"fast\"\n", "[metadata] speed must be a positive number"),
    "delimiter a line end": ('delimiter = "\\n"\n' + LAYOUT, "delimiter '\\n' cannot separate numbers"),
    "delimiter a digit": ('delimiter = "1"\n' + LAYOUT, "delimiter '1' cannot separate numbers"),
    "delimiter a point": ('delimiter = "."\n' + LAYOUT, "delimiter '.' cannot separate numbers"),
}


@pytest.mark.parametrize(("text", "message"), BAD_LAYOUTS.values(), ids=BAD_LAYOUTS.keys())
def test_bad_layouts_are_refused_naming_the_layout(tmp_path, run_text, capsys, text, message):
    layout = write(tmp_path, "layout.toml", text)
    run = write(tmp_path, "run5.csv", run_text)
    with pytest.raises(RunFileError) as caught:
        read_run(run, layout=layout)
    assert caught.value.source == str(layout)
    assert "\n" not in str(caught.value)
    line = cli_error(capsys, ["fit", run, "--layout", layout])
    assert line.startswith(f"whipple fit: error: {layout}: bad layout file: ")
    assert message in line


def test_valid_layouts_still_load(tmp_path, run_text):
    native = read_run(write(tmp_path, "run5.csv", run_text))
    run = read_run(native.source, layout=write(tmp_path, "layout.toml", LAYOUT))
    assert run.warnings == ()
    # A byte-order mark (a Windows editor's UTF-8) is no TOML syntax error, as in bicycle files.
    with_bom = tmp_path / "bom.toml"
    with_bom.write_bytes(b"\xef\xbb\xbf" + LAYOUT.encode())
    assert load_layout(with_bom).columns == load_layout(tmp_path / "layout.toml").columns
    for name in ("roll_rate", "yaw_rate", "steer_angle", "speed"):
        np.testing.assert_array_equal(run.signals[name], native.signals[name])
    # Scale of an extra signal, numbers in [speed] and [metadata] (numbers as strings too), a
    # constant speed, and the sample rate: all within what is documented.
    fuller = "sample_rate = 100\n" + LAYOUT.replace('speed = "speed"\n', "") + """\
[extra]
speed = "belt_speed"
[scale]
belt_speed = -2
roll_rate = 2
[speed]
source = "constant"
value = 4.5
wheel_radius = 0.3
pulses_per_revolution = 20
[metadata]
speed = "4.5"
bicycle = "benchmark"
repeats = 3
"""
    run = read_run(native.source, layout=write(tmp_path, "fuller.toml", fuller))
    np.testing.assert_allclose(run.signals["belt_speed"], -2 * native.signals["speed"])
    np.testing.assert_allclose(run.signals["roll_rate"], 2 * native.signals["roll_rate"])
    assert run.speed() == pytest.approx(4.5)  # no speed column is mapped: the constant speed
    assert run.metadata["repeats"] == "3"
    builtin = load_layout("sbw-treadmill")
    assert builtin.sample_rate == 100.0 and builtin.extra["y_acceleration"] == "lateral_acceleration"
    example = load_layout(DOCS / "examples" / "layout-example.toml")
    assert example.scale["time"] == 0.001 and example.names[-1] == "checksum"
    assert example.ignore == ("checksum",)


def test_valid_layout_through_the_cli(tmp_path, run_text, capsys):
    run = write(tmp_path, "run5.csv", run_text)
    code = main(["fit", str(run), "--layout", str(write(tmp_path, "layout.toml", LAYOUT))])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert captured.out.splitlines()[1].startswith("run5: 3 window(s) fitted")


def test_metadata_key_given_twice(tmp_path, run_text, capsys):
    path = write(tmp_path, "twice.csv", without_time(run_text, "# sample_rate: 50"))
    with pytest.raises(RunFileError, match="metadata 'sample_rate' given twice") as caught:
        read_run(path)
    assert caught.value.source == str(path) and isinstance(caught.value, InputError)
    line = cli_error(capsys, ["fit", path])
    assert line == f"whipple fit: error: {path}: line 12: metadata 'sample_rate' given twice (first on line 1)"


def test_metadata_keys_that_differ_are_kept(tmp_path, run_text):
    # Keys differing in case are different keys; a '#' line after the header is no metadata.
    text = without_time(run_text, "# Sample_Rate: 50")
    lines = text.splitlines()
    lines.insert(20, "# sample_rate: 50")
    run = read_run(write(tmp_path, "ok.csv", "\n".join(lines) + "\n"))
    assert run.sample_rate == 100.0
    assert run.metadata["Sample_Rate"] == "50"


@pytest.mark.parametrize(
    "text", ["1.5", " -2e3 ", ".5", "5.", "+0.25E-2", "nan", "-inf", "Infinity"],
)
def test_ascii_numbers_are_read_as_float_reads_them(text):
    np.testing.assert_equal(parse_number(text), float(text))


@pytest.mark.parametrize("text", ["١٢", "１２", "1_000", "", "1.5.2", "0x10", "١.٥"])
def test_unicode_digits_and_other_text_are_no_number(text):
    with pytest.raises(ValueError, match="not a number"):
        parse_number(text)


def test_unicode_digits_in_a_run_file(tmp_path, run_text, capsys):
    lines = run_text.splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    cells = lines[header + 5].split(",")
    # In a column every analysis reads: an error, as for any text there.
    roll = lines.copy()
    roll[header + 5] = ",".join([cells[0], "١٢", *cells[2:]])
    path = write(tmp_path, "roll.csv", "\n".join(roll) + "\n")
    line = cli_error(capsys, ["fit", path])
    assert line == f"whipple fit: error: {path}: line {header + 6}, column 'roll_rate': non-numeric value '١٢'"
    # Elsewhere a gap, noted, and not the number 12.
    steer = lines.copy()
    steer[header + 5] = ",".join([*cells[:3], "١٢", cells[4]])
    steer_path = write(tmp_path, "steer.csv", "\n".join(steer) + "\n")
    run = read_run(steer_path, filled_gap=0.0)
    assert np.isnan(run.signals["steer_angle"][4])  # data row 4: the line after the header is row 0
    assert any("column 'steer_angle': 1 empty, NaN or non-numeric cell(s)" in note for note in run.warnings)
    # A one-sample gap is filled from its neighbours, never with 12.
    filled = read_run(steer_path).signals["steer_angle"]
    assert abs(filled[4] - (filled[3] + filled[5]) / 2) < 0.01
    # In metadata.
    path = write(tmp_path, "meta.csv", without_time(run_text, "").replace("# sample_rate: 100", "# sample_rate: ١٠٠"))
    line = cli_error(capsys, ["fit", path])
    assert line == f"whipple fit: error: {path}: metadata 'sample_rate' is not a number (in Hz): '١٠٠'"


def test_unicode_digits_in_a_layout_and_a_windows_file(tmp_path, run_text, capsys):
    run = write(tmp_path, "run5.csv", run_text)
    layout = write(tmp_path, "layout.toml", LAYOUT + '[metadata]\nwheel_radius = "٠.٣"\n')
    line = cli_error(capsys, ["fit", run, "--layout", layout])
    assert line == f"whipple fit: error: {layout}: bad layout file: [metadata] wheel_radius must be a positive " \
                   "number, got '٠.٣'"
    for header, row in (("run,start,stop", "run5,١,٣"), ("run,start_row,stop_row", "run5,١٠٠,٣٠٠")):
        windows = write(tmp_path, "windows.csv", f"{header}\n{row}\n")
        with pytest.raises(RunFileError, match="line 2: bad start/stop value"):
            read_windows(windows, [read_run(run)])
        line = cli_error(capsys, ["fit", run, "--windows", windows])
        assert line == f"whipple fit: error: {windows}: line 2: bad start/stop value"
    windows = write(tmp_path, "windows.csv", "run,start_row,stop_row\nrun5, 100 ,300\n")
    assert read_windows(windows, [read_run(run)])[0].start == pytest.approx(1.0)
