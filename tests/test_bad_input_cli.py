"""Bad input found by fuzzing the command line: one line, a non-zero exit, inputs untouched."""

import gzip
import importlib.resources
import io
import os
import re
import stat
import threading
import time
from pathlib import Path

import pytest

from whipple.cli import main
from whipple.errors import InputError, RunFileError
from whipple.input_files import MAX_LINE_CHARACTERS, text_lines
from whipple.measurement.run_table import read_run_table
from whipple.measurement.runs import check_same_bicycle, read_run
from whipple.stability.sweep import table_chunks

DATA = Path(__file__).parent / "data" / "bicycleparameters" / "bicycles"
BENCHMARK_TOML = Path(__file__).parents[1] / "src" / "whipple" / "data" / "benchmark.toml"


def _one_line_error(capsys, code: int, rc: int, *words: str) -> str:
    assert rc == code
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "Traceback" not in err[0]
    for word in words:
        assert word in err[0]
    return err[0]


def _bicycle_with(tmp_path: Path, extra: str) -> Path:
    path = tmp_path / "bicycle.toml"
    path.write_text(BENCHMARK_TOML.read_text(encoding="utf-8") + "\n" + extra + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("extra, words", [
    ("[extensions]\nsteer_damping = 1e150", "steer_damping = 1e+150 is beyond"),
    ("[extensions]\nspeed_scale = 1e-300", "speed_scale = 1e-300 is below 0.01"),
    ("[extensions.payload]\nmass = 1\nx = 1e300\nz = 0", "payload x = 1e+300 is beyond"),
    ("[controller.steer]\nroll_rate = [1e300, 1e300]", "controller.steer.roll_rate has a coefficient beyond"),
    ("[controller]\ndelay = 1e300\n[controller.steer]\nroll_rate = 1.0", "controller delay = 1e+300 is beyond"),
])
def test_extension_and_controller_values_beyond_any_bicycle(tmp_path, capsys, extra, words):
    path = _bicycle_with(tmp_path, extra)
    _one_line_error(capsys, 2, main(["check", str(path)]), str(path), words)


def test_overflow_in_the_analysis_is_one_line(tmp_path, capsys):
    # A positive delay this small passes the checks (fitted delays come out at 1e-14) but its
    # Pade approximant overflows.
    path = _bicycle_with(tmp_path, "[controller]\ndelay = 1e-300\n[controller.steer]\nroll_rate = 1.0")
    _one_line_error(capsys, 1, main(["check", str(path)]), "analysis failed", "overflow", str(path))
    # A controller of a thousand terms passes each coefficient's check; its gain overflows.
    long = _bicycle_with(tmp_path, "[controller.steer]\nroll_rate = [" + ", ".join(["1.0"] * 1000) + "]")
    _one_line_error(capsys, 1, main(["stability", str(long), "--points", "5"]), "overflow", str(long))


def test_numbers_too_large_for_a_float(tmp_path, capsys):
    huge = "9" * 400
    toml = tmp_path / "huge.toml"
    toml.write_text(BENCHMARK_TOML.read_text(encoding="utf-8").replace("w = 1.02", f"w = {huge}", 1), encoding="utf-8")
    _one_line_error(capsys, 2, main(["check", str(toml)]), str(toml), "'w' in [parameters] is too large a number")
    silver = (DATA / "SilverBenchmark.txt").read_text(encoding="utf-8").splitlines()
    cases = (("1e400", "too large a number"), (huge, "too large a number"), ("١٢", "expected 'name = value'"))
    for value, words in cases:
        lines = [f"c = {value}" if line.startswith("c =") else line for line in silver]
        path = tmp_path / "OddBenchmark.txt"
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
        _one_line_error(capsys, 2, main(["check", str(path)]), str(path), words)


def test_speed_arguments(capsys):
    # check has no speed grid: any finite range is solved exactly, without warnings.
    assert main(["check", "benchmark", "--speeds", "0:1e300"]) == 0
    assert "weave speed:   4.29238" in capsys.readouterr().out
    for speeds, words in (("5,5", "given twice"), ("5,,6", "empty item"), ("٥", "expected speeds")):
        with pytest.raises(SystemExit) as raised:
            main(["simulate", "--bicycle", "benchmark", "--speeds", speeds, "--output", "unused"])
        assert raised.value.code == 2
        assert words in capsys.readouterr().err


def test_a_folder_given_as_the_bicycle(tmp_path, capsys):
    _one_line_error(capsys, 2, main(["check", str(tmp_path)]), "not a regular file")


def test_outputs_follow_symbolic_links_and_write_into_devices(tmp_path, capsys):
    target = tmp_path / "target.csv"
    target.write_text("old\n", encoding="utf-8")
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    assert main(["stability", "benchmark", "--points", "5", "--csv", str(link)]) == 0
    assert link.is_symlink() and target.read_text(encoding="utf-8").startswith("speed_m_per_s")
    null = Path(os.devnull)
    if not (null.exists() and stat.S_ISCHR(null.stat().st_mode) and os.access(null, os.W_OK)):
        pytest.skip("no writable null device")
    assert main(["stability", "benchmark", "--points", "5", "--csv", str(null)]) == 0
    assert stat.S_ISCHR(null.stat().st_mode)
    capsys.readouterr()


def test_sweep_rows(tmp_path, capsys):
    bom = tmp_path / "bom.csv"
    bom.write_bytes("\ufeffc\n0.09\n".encode())
    out = tmp_path / "out.csv"
    assert main(["sweep", "--quiet", "-o", str(out), str(bom)]) == 0
    assert out.read_text(encoding="utf-8").splitlines()[0].startswith("c,weave_speed")
    other_digits = tmp_path / "digits.csv"
    other_digits.write_text("c\n١\n", encoding="utf-8")
    capsys.readouterr()
    _one_line_error(capsys, 2, main(["sweep", "--quiet", "-o", str(out), str(other_digits)]), "not a number")
    tyre = _bicycle_with(tmp_path, "[extensions.tyre_compliance]\ncornering_stiffness = 10\n"
                                   "camber_stiffness = 0.5\nrelaxation_length = 0.1")
    rows = tmp_path / "rows.csv"
    rows.write_text("rF,IFyy\n0,0\n0.35,0.28\n", encoding="utf-8")
    assert main(["sweep", "--quiet", "-o", str(out), "--bicycle", str(tyre), str(rows)]) == 0
    lines = out.read_text(encoding="utf-8").splitlines()
    assert lines[1].endswith("tyre compliance needs wheels of positive radius (rF = 0)")
    assert lines[2].split(",")[2]  # the other row has a weave speed
    # A wheelbase of 1e-300 m overflowed the matrices: the whole sweep ended with an error naming
    # neither the file nor the row. Now that row is not physical and the others are analysed.
    rows.write_text("w\n1e-300\n1.02\n", encoding="utf-8")
    assert main(["sweep", "--quiet", "-o", str(out), str(rows)]) == 0
    lines = out.read_text(encoding="utf-8").splitlines()
    assert lines[1].endswith("w = 1e-300 m is below 0.001 m: not a bicycle (a unit or typing error?)")
    assert lines[2].split(",")[1]


@pytest.fixture(scope="module")
def run_file(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("run")
    path = folder / "run5.csv"
    assert main(["simulate", "--bicycle", "benchmark", "--speed", "5", "--seed", "1", "--output", str(path)]) == 0
    return path


def test_windows_reaching_beyond_the_run_and_poor_fits(run_file, tmp_path, capsys):
    windows = tmp_path / "w.csv"
    windows.write_text(f"run,start,stop\n{run_file.stem},0,1e300\n{run_file.stem},18.0,18.3\n", encoding="utf-8")
    capsys.readouterr()
    assert main(["fit", str(run_file), "--windows", str(windows)]) == 2  # neither window fitted
    out, err = capsys.readouterr()
    assert err.count("\n") == 1 and "no window fitted in" in err
    assert "reaches beyond the run" in out
    # Fitted jointly with the steer angle, 0.3 s of noise hold no oscillation to fit.
    assert "under half a period of oscillation in the window" in out
    # The seed paper's plain fit of the roll rate alone fits it, and says the fit is too poor.
    assert main(["fit", str(run_file), "--windows", str(windows), "--method", "seed-paper"]) == 0
    assert "not used: poor fit" in capsys.readouterr().out


def test_diagnose_never_writes_over_its_layout_and_saves_toml(run_file, tmp_path, capsys):
    layout = tmp_path / "layout.toml"
    layout.write_text('[columns]\nroll_rate = "roll_rate"\n', encoding="utf-8")
    before = layout.read_bytes()
    capsys.readouterr()
    for option in ("--json", "--save-model"):
        rc = main(["diagnose", str(run_file), "--bicycle", "benchmark", "--layout", str(layout), option, str(layout)])
        _one_line_error(capsys, 2, rc, "refusing to write output over input file")
        assert layout.read_bytes() == before
    rc = main(["diagnose", str(run_file), "--bicycle", "benchmark", "--save-model", str(tmp_path / "m.txt")])
    _one_line_error(capsys, 2, rc, "--save-model writes TOML")


def test_two_runs_of_one_name_are_named_with_their_files(run_file, tmp_path, capsys):
    other = tmp_path / "copy"
    other.mkdir()
    copy = other / run_file.name
    copy.write_bytes(run_file.read_bytes())
    capsys.readouterr()
    _one_line_error(capsys, 2, main(["fit", str(run_file), str(copy)]), str(run_file), str(copy))
    _one_line_error(capsys, 2, main(["diagnose", str(run_file), str(copy), "--bicycle", "benchmark"]),
                    str(run_file), str(copy))


@pytest.mark.parametrize("cycles", ["-1", "nan"])
def test_a_window_check_out_of_range(run_file, capsys, cycles):
    _one_line_error(capsys, 2, main(["fit", str(run_file), f"--min-cycles-above-noise={cycles}"]),
                    "cycles above the noise must be between 0 and 100")


def test_corrupt_gzip_low_sample_rates_empty_speed_and_huge_cells(run_file, tmp_path, capsys):
    # Found by fuzzing the command line (2026-11-27): each was a traceback.
    packed = bytearray(gzip.compress(run_file.read_bytes()))
    packed[len(packed) // 2] ^= 0xFF  # a flipped byte inside the compressed data
    cases = {"bitflip.csv.gz": bytes(packed), "garbage.csv.gz": b"\x1f\x8b\x08\x00" + bytes(range(256)) * 8}
    lines = run_file.read_text(encoding="utf-8").splitlines()
    header = next(k for k, line in enumerate(lines) if not line.startswith("#"))
    names = lines[header].split(",")
    rows = [line.split(",") for line in lines[header + 1:]]
    scaled = [[f"{float(row[0]) * 1e6:.6g}", *row[1:]] for row in rows]  # time in microseconds
    cases["microseconds.csv"] = "\n".join([*lines[:header + 1], *(",".join(row) for row in scaled)]).encode()
    speed = names.index("speed")
    empty = [[*row[:speed], "", *row[speed + 1:]] for row in rows]
    cases["no_speed.csv"] = "\n".join([*lines[:header + 1], *(",".join(row) for row in empty)]).encode()
    words = {"bitflip.csv.gz": "corrupt gzip data", "garbage.csv.gz": "corrupt gzip data",
             "microseconds.csv": "too slow to resolve the weave", "no_speed.csv": "column speed has no values"}
    for name, data in cases.items():
        path = tmp_path / name
        path.write_bytes(data)
        capsys.readouterr()
        _one_line_error(capsys, 2, main(["fit", str(path), "--json", str(tmp_path / "o.json")]), str(path), words[name])
        assert path.read_bytes() == data
    windows = tmp_path / "w.csv"
    windows.write_text(f"run,start,stop\n{run_file.stem},1,{'9' * 140000}\n", encoding="utf-8")
    _one_line_error(capsys, 2, main(["fit", str(run_file), "--windows", str(windows)]), str(windows),
                    "not a readable CSV table")
    table = tmp_path / "sets.csv"
    table.write_text("w,c" + "x" * 140000 + "\n1.02,0.08\n", encoding="utf-8")
    _one_line_error(capsys, 2, main(["sweep", str(table), "-o", str(tmp_path / "out.csv")]), str(table),
                    "not a readable CSV table")


def _endless_fifo(folder: Path, chunk: bytes, head: bytes = b"") -> tuple[Path, threading.Thread]:
    """A named pipe fed `head`, then `chunk` again and again until its reader goes away."""
    fifo = folder / "endless.csv"
    os.mkfifo(fifo)

    def feed() -> None:
        try:
            with fifo.open("wb") as pipe:
                pipe.write(head)
                while True:
                    pipe.write(chunk)
        except (BrokenPipeError, OSError):
            pass

    writer = threading.Thread(target=feed, daemon=True)
    writer.start()
    return fifo, writer


@pytest.mark.parametrize("command", ["fit", "sweep"])
def test_an_endless_pipe_without_line_ends_is_refused_at_once(tmp_path, capsys, command):
    fifo, writer = _endless_fifo(tmp_path, b"0.5," * 4096)
    argv = ["fit", str(fifo)] if command == "fit" else ["sweep", str(fifo), "-o", str(tmp_path / "o.csv")]
    started = time.perf_counter()
    _one_line_error(capsys, 2, main(argv), str(fifo), f"line 1 is longer than {MAX_LINE_CHARACTERS} characters")
    assert time.perf_counter() - started < 10
    writer.join(timeout=10)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["endless.csv"]


def test_an_endless_run_of_valid_rows_stops_at_its_cap(tmp_path):
    # The cap itself (10 million rows) is measured in benchmarks/bench_inputs.py; here a small one.
    fifo, writer = _endless_fifo(tmp_path, b"0.01,0.1,5\n" * 1000, head=b"time,roll_rate,speed\n")
    with pytest.raises(RunFileError, match="more than 5,000 data rows: too long a run"):
        read_run_table(fifo, None, str(fifo), max_samples=5000)
    writer.join(timeout=10)
    lines = tmp_path / "lines.csv"
    lines.write_text("time,roll_rate,speed\n" + "\n" * 20000)
    with pytest.raises(RunFileError, match="more than 10,000 lines: too long for a run file"):
        read_run_table(lines, None, str(lines), max_samples=5000)
    table = tmp_path / "sets.csv"
    table.write_text("c\n" + "0.08\n" * 3000)
    with pytest.raises(InputError, match="more than 2,000 lines: too long a parameter table"):
        list(table_chunks(table, rows=100, max_lines=2000)[1])


def test_lines_of_a_table_in_blocks():
    text = "a,b\r\nc\rd\n" + "x" * 50 + "\n\ufeff"
    blocks = list(text_lines(io.BytesIO(("\ufeff" + text).encode()), "t", block_bytes=7))
    assert [line for block in blocks for line in block] == ["a,b", "c", "d", "x" * 50, "\ufeff"]
    with pytest.raises(InputError, match="line 4 is longer than 40 characters"):
        list(text_lines(io.BytesIO(text.encode()), "t", max_line=40, block_bytes=7))
    with pytest.raises(InputError, match="invalid UTF-8"):
        list(text_lines(io.BytesIO(b"ok\n\xff\xfe"), "t"))


@pytest.mark.parametrize("speeds, words", [("-1:5", "need 0 <= LOW < HIGH (finite), got '-1:5'"),
                                           ("-.5:5", "need 0 <= LOW < HIGH (finite), got '-.5:5'")])
def test_a_negative_speed_range_is_named(capsys, speeds, words):
    for command in (["check", "benchmark"], ["stability", "benchmark"]):
        with pytest.raises(SystemExit) as raised:
            main([*command, "--speeds", speeds])
        assert raised.value.code == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and words in err and "expected one argument" not in err
    _one_line_error(capsys, 2, main(["simulate", "--bicycle", "benchmark", "--speeds", "-1,2", "--output", "x"]),
                    "speeds must be positive m/s, got -1")


def test_runs_of_different_bicycles(run_file, tmp_path):
    other = tmp_path / "other.csv"
    other.write_text(run_file.read_text().replace("# bicycle: benchmark\n", "# bicycle: sbw2024\n"))
    unnamed = tmp_path / "unnamed.csv"
    unnamed.write_text(run_file.read_text().replace("# bicycle: benchmark\n", ""))
    runs = [read_run(path) for path in (run_file, unnamed)]
    check_same_bicycle(runs)  # a run that names none is not contradicted
    with pytest.raises(InputError, match=f"runs of different bicycles: {run_file} names 'benchmark', {other} names "
                                         "'sbw2024'"):
        check_same_bicycle([*runs, read_run(other)])


def test_a_metadata_sample_rate_within_a_clock_drift_is_no_contradiction(run_file, tmp_path):
    close = tmp_path / "close.csv"
    close.write_text(run_file.read_text().replace("# sample_rate: 100\n", "# sample_rate: 100.5\n"))
    assert read_run(close).sample_rate == pytest.approx(100.0)
    far = tmp_path / "far.csv"
    far.write_text(run_file.read_text().replace("# sample_rate: 100\n", "# sample_rate: 1000\n"))
    with pytest.raises(RunFileError, match="metadata sample_rate 1000 Hz contradicts the time column"):
        read_run(far)


def test_evaluate_bad_inputs_are_one_line_and_leave_the_inputs(run_file, tmp_path, capsys):
    experiment = tmp_path / "exp.toml"
    experiment.write_text(f'[[group]]\nname = "g"\nbicycle = "benchmark"\nruns = "{run_file}"\n', encoding="utf-8")
    models = tmp_path / "models"
    models.mkdir()
    saved = tmp_path / "saved"  # models read with --models are inputs too
    saved.mkdir()
    model = saved / "g.toml"
    model.write_text(importlib.resources.files("whipple.data").joinpath("benchmark.toml").read_text(), encoding="utf-8")
    run, out = str(run_file), str(tmp_path / "o.json")
    linked = tmp_path / "linked.csv"  # the run under a second name (a hard link)
    os.link(run_file, linked)
    cases = [
        (["evaluate", "--bicycle", "benchmark"], "no runs"),
        (["evaluate", run], "no model to score: give --bicycle"),
        (["evaluate", run, "--bicycle", "benchmark", "--bicycle", "benchmark"], "--bicycle benchmark given twice"),
        (["evaluate", run, "--bicycle", "nobike.toml"], "nobike.toml: no such file or built-in bicycle"),
        (["evaluate", run, "--bicycle", "benchmark", "--models", str(models)], "--models gives one model per group"),
        (["evaluate", run, "--experiment", str(experiment)], "RUN files cannot be given with it"),
        (["evaluate", "--experiment", str(experiment), "--bicycle", "benchmark"], "--bicycle cannot be given"),
        (["evaluate", "--experiment", str(tmp_path / "none.toml")], "no such experiment file"),
        (["evaluate", "--experiment", str(experiment), "--models", str(models)], "no model for group 'g'"),
        (["evaluate", "--experiment", str(experiment), "--models", str(tmp_path / "nodir")], "no such folder"),
        (["evaluate", run, "--bicycle", "benchmark", "--json", run], "refusing to write output over input file"),
        (["evaluate", "--experiment", str(experiment), "--json", str(experiment)], "refusing to write output"),
        (["evaluate", "--experiment", str(experiment), "--csv", run], "refusing to write output"),
        (["evaluate", run, "--bicycle", "benchmark", "--json", out, "--csv", out], "--json"),
        (["evaluate", run, "--bicycle", "benchmark", "--windows", str(tmp_path / "w.csv")], "cannot read file"),
        (["evaluate", "--experiment", str(experiment), "--models", str(saved), "--csv", str(model), "--no-samples"],
         "refusing to write output over input file"),
        (["evaluate", run, "--bicycle", "benchmark", "--json", str(linked)], "refusing to write output over input"),
    ]
    before = {path: path.read_bytes() for path in (run_file, experiment, model)}
    for args, words in cases:
        capsys.readouterr()
        _one_line_error(capsys, 2, main(args), words)
        assert all(path.read_bytes() == data for path, data in before.items())
    assert not Path(out).exists()
    bad = tmp_path / "bad.toml"
    bad.write_text(f'[[group]]\nname = "g"\nbicycle = "benchmark"\nruns = "{tmp_path}/*.log"\n', encoding="utf-8")
    _one_line_error(capsys, 2, main(["evaluate", "--experiment", str(bad)]), str(bad), "group 1 ('g')",
                    "matches no file")
    for command in ("evaluate", "fit", "diagnose"):
        with pytest.raises(SystemExit) as raised:
            main([command, "--bundled", "model-matching", "--bicycle", "sbw2024"])
        assert raised.value.code == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "invalid choice: 'model-matching'" in err[0] and "model-matching-on" in err[0]


def test_samples_beyond_any_bicycle_are_gaps_and_a_roll_rate_of_them_is_refused(run_file, tmp_path, capsys):
    lines = run_file.read_text(encoding="utf-8").splitlines()
    header = next(k for k, line in enumerate(lines) if not line.startswith("#"))
    names = lines[header].split(",")
    rows = [line.split(",") for line in lines[header + 1:]]

    def written(name: str, column: str, value) -> Path:
        index = names.index(column)
        edited = [[*row[:index], value(row[index]), *row[index + 1:]] for row in rows]
        path = tmp_path / name
        path.write_text("\n".join([*lines[:header + 1], *(",".join(row) for row in edited)]) + "\n", encoding="utf-8")
        return path

    steer = written("steer.csv", "steer_angle", lambda cell: "1e300")
    before = steer.read_bytes()
    capsys.readouterr()
    assert main(["fit", str(steer)]) == 0
    out = capsys.readouterr().out
    assert f"{len(rows)} steer_angle sample(s) beyond 1e+06 rad (up to 1e+300) left out as gaps" in out
    assert "fitted roll_rate," in out  # the steer angle has no sample left: roll rate alone
    assert steer.read_bytes() == before
    roll = written("roll.csv", "roll_rate", lambda cell: f"{float(cell) * 1e300:.6g}" if float(cell) else "1e300")
    _one_line_error(capsys, 2, main(["fit", str(roll)]), str(roll), "every roll_rate sample is empty or beyond 1e+06")


def test_a_bicycle_without_mass_is_refused(tmp_path, capsys):
    text = BENCHMARK_TOML.read_text(encoding="utf-8")
    for mass in ("mR", "mB", "mH", "mF"):
        text = re.sub(rf"^{mass} = [0-9.]+", f"{mass} = 0.0", text, count=1, flags=re.MULTILINE)
    path = tmp_path / "massless.toml"
    path.write_text(text, encoding="utf-8")
    _one_line_error(capsys, 2, main(["check", str(path)]), str(path), "mR + mB + mH + mF = 0 kg")
