"""A corpus of bad inputs across every command: exit 2, one line naming the file, no traceback.

Each case builds its inputs in a fresh folder, runs ``whipple`` in-process, and checks that the
exit status is 2, that stderr is exactly one line naming the file (or option) and the problem,
that no traceback was printed, and that every file in the folder is unchanged and no file was
added (no output, no temporary file). A few cases also run as a real subprocess.
"""

from __future__ import annotations

import gzip
import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from whipple.cli import main
from whipple.model.parameters import load_bicycle
from whipple.simulation.run_writer import write_run_csv
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

DATA = Path(__file__).parent / "data" / "bicycleparameters"
BENCHMARK_TEXT = (DATA / "bicycles" / "BenchmarkBenchmark.txt").read_text()


@pytest.fixture(scope="module")
def run_text(tmp_path_factory) -> str:
    """A simulated benchmark run (native CSV, 100 Hz, one push) as text."""
    folder = tmp_path_factory.mktemp("run")
    run = simulate_run(load_bicycle("benchmark"), RunScenario(speed=5.0, n_pushes=1, seed=2), name="run")
    return write_run_csv(run, folder / "run.csv").read_text()


@pytest.fixture(scope="module")
def toml_text() -> str:
    import importlib.resources

    return importlib.resources.files("whipple.data").joinpath("benchmark.toml").read_text()


def read_only_folder(base: Path) -> Path:
    """A folder nobody may write to: chmod 555, or /sys where the user ignores modes (root)."""
    folder = base / "locked"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        (folder / ".probe").write_text("")
    except OSError:
        return folder
    (folder / ".probe").unlink()
    return Path("/sys")


def _set(text: str, key: str, value: str) -> str:
    lines = [f"{key} = {value}" if line.split("=")[0].strip() == key else line for line in text.splitlines()]
    return "\n".join(lines) + "\n"


class Case:
    """Inputs to write, the command line, the file the error must name and the problem."""

    def __init__(self, files: dict[str, str | bytes], argv: list[str], named: str, problem: str):
        self.files, self.argv, self.named, self.problem = files, argv, named, problem


Builder = Callable[[Path, str, str], Case]


def _check(files: dict[str, str | bytes], argv: list[str], named: str, problem: str) -> Case:
    return Case(files, argv, named, problem)


def _runs(run: str, edit: Callable[[list[str]], list[str]]) -> str:
    lines = run.splitlines()
    return "\n".join(edit(lines)) + "\n"


def _header_index(lines: list[str]) -> int:
    return next(i for i, line in enumerate(lines) if not line.startswith("#"))


def _cell(lines: list[str], row: int, column: str, value: str) -> list[str]:
    h = _header_index(lines)
    j = lines[h].split(",").index(column)
    cells = lines[h + 1 + row].split(",")
    cells[j] = value
    return lines[:h + 1 + row] + [",".join(cells)] + lines[h + 2 + row:]


#: Command lines of the endless-input cases; DEV is the device.
def _column(lines: list[str], column: str, value: str) -> list[str]:
    h = _header_index(lines)
    j = lines[h].split(",").index(column)
    return lines[:h + 1] + [",".join(value if k == j else cell for k, cell in enumerate(line.split(",")))
                            for line in lines[h + 1:]]


def _drifting_roll_rate(lines: list[str]) -> list[str]:
    """The run with a roll rate that drifts slowly and never oscillates."""
    h = _header_index(lines)
    j = lines[h].split(",").index("roll_rate")
    return lines[:h + 1] + [",".join(f"{1e-4 * i:.6f}" if k == j else cell for k, cell in enumerate(line.split(",")))
                            for i, line in enumerate(lines[h + 1:])]


DEVICE_COMMANDS = {
    "fit": ["fit", "DEV"],
    "sweep": ["sweep", "DEV", "-o", "{d}/out.csv"],
    "diagnose": ["diagnose", "DEV", "--bicycle", "benchmark"],
    "check rider": ["check", "benchmark", "--rider", "DEV"],
    "fit layout": ["fit", "{d}/run.csv", "--layout", "DEV"],
    "fit windows": ["fit", "{d}/run.csv", "--windows", "DEV"],
    "stability rider": ["stability", "benchmark", "--rider", "DEV"],
    "simulate rider": ["simulate", "--bicycle", "benchmark", "--rider", "DEV", "--speed", "5", "--output",
                       "{d}/s.csv"],
    "diagnose bicycle": ["diagnose", "{d}/run.csv", "--bicycle", "DEV"],
}


def _device_case(command: str, device: str, words: str) -> Builder:
    """A command reading `device` (DEV in its line) where it expects a text file."""
    def build(d: Path, t: str, r: str) -> Case:
        return _check({"b.toml": t, "run.csv": r}, [arg.replace("DEV", device) for arg in DEVICE_COMMANDS[command]],
                      device, words)
    return build


CASES: dict[str, Builder] = {
    # --- check: bicycle files ---------------------------------------------------------------
    "check missing file": lambda d, t, r: _check({}, ["check", "{d}/absent.toml"], "absent.toml",
                                                 "no such file or built-in bicycle"),
    "check TOML syntax": lambda d, t, r: _check({"b.toml": t.replace("[parameters]", "[parameters")},
                                                ["check", "{d}/b.toml"], "b.toml", "TOML syntax error"),
    "check unknown key": lambda d, t, r: _check({"b.toml": t.replace("mB = ", "mb = ")},
                                                ["check", "{d}/b.toml"], "b.toml", "unknown key 'mb'"),
    "check missing key": lambda d, t, r: _check({"b.toml": "\n".join(x for x in t.splitlines()
                                                                     if not x.startswith("w "))},
                                                ["check", "{d}/b.toml"], "b.toml", "missing key in [parameters]: w"),
    "check negative mass": lambda d, t, r: _check({"b.toml": _set(t, "mH", "-4.0")}, ["check", "{d}/b.toml"],
                                                  "b.toml", "mH = -4 must not be negative"),
    "check NaN": lambda d, t, r: _check({"b.toml": _set(t, "c", "nan")}, ["check", "{d}/b.toml"], "b.toml",
                                        "c = nan is not finite"),
    "check absurd mass": lambda d, t, r: _check({"b.toml": _set(t, "mB", "1e300")}, ["check", "{d}/b.toml"],
                                                "b.toml", "mB = 1e+300 kg is beyond 100000 kg"),
    "check tilt": lambda d, t, r: _check({"b.toml": _set(t, "lam", "2.0")}, ["check", "{d}/b.toml"], "b.toml",
                                         "lam = 2 must be in (-pi/2, pi/2)"),
    "check string value": lambda d, t, r: _check({"b.toml": _set(t, "c", '"0.08"')}, ["check", "{d}/b.toml"],
                                                 "b.toml", "'c' in [parameters] must be a number"),
    "check not positive semi-definite": lambda d, t, r: _check(
        {"b.toml": _set(t, "IBxz", "20.0")}, ["check", "{d}/b.toml"], "b.toml", "is not positive semi-definite"),
    "check spinning point wheel": lambda d, t, r: _check(
        {"b.toml": _set(t, "rR", "0.0")}, ["check", "{d}/b.toml"], "b.toml", "needs IRyy = 0"),
    "check binary file": lambda d, t, r: _check({"b.toml": b"\xff\xfe\x00\x01"}, ["check", "{d}/b.toml"], "b.toml",
                                                "not a UTF-8 text file"),
    "check folder": lambda d, t, r: _check({"sub/x.txt": "x"}, ["check", "{d}/sub"], "sub",
                                           "not a regular file"),
    "check text bad line": lambda d, t, r: _check({"BBenchmark.txt": BENCHMARK_TEXT + "w: 3\n"},
                                                  ["check", "{d}/BBenchmark.txt"], "BBenchmark.txt",
                                                  "expected 'name = value'"),
    "check text asymmetric wheel": lambda d, t, r: _check({"BBenchmark.txt": BENCHMARK_TEXT + "IRzz = 0.09\n"},
                                                          ["check", "{d}/BBenchmark.txt"], "BBenchmark.txt",
                                                          "needs wheels symmetric about their axle"),
    "check text lateral offset": lambda d, t, r: _check({"BBenchmark.txt": BENCHMARK_TEXT + "yH = 0.05\n"},
                                                        ["check", "{d}/BBenchmark.txt"], "BBenchmark.txt",
                                                        "yH = 0.05 m is not zero"),
    "check text duplicate": lambda d, t, r: _check({"BBenchmark.txt": BENCHMARK_TEXT + "c = 0.09\n"},
                                                   ["check", "{d}/BBenchmark.txt"], "BBenchmark.txt",
                                                   "'c' given twice"),
    "check rider file": lambda d, t, r: _check(
        {"JasonBenchmark.txt": (DATA / "riders" / "JasonBrowserBenchmark.txt").read_text()},
        ["check", "{d}/JasonBenchmark.txt"], "JasonBenchmark.txt", "a rider file"),
    "check yeadon file": lambda d, t, r: _check(
        {"CFG.txt": (DATA / "riders" / "JasonBrowserYeadonCFG.txt").read_text()},
        ["check", "{d}/CFG.txt"], "CFG.txt", "a Yeadon configuration file"),
    "check front payload mass": lambda d, t, r: _check(
        {"b.toml": t + "\n[extensions.front_payload]\nmass = -2.0\nx = 1.0\nz = -0.8\n"},
        ["check", "{d}/b.toml"], "b.toml", "extension front_payload mass = -2 must be finite and > 0"),
    "check front payload missing z": lambda d, t, r: _check(
        {"b.toml": t + "\n[extensions.front_payload]\nmass = 2.0\nx = 1.0\n"},
        ["check", "{d}/b.toml"], "b.toml", "missing key in [extensions.front_payload]: z"),
    "check reflected inertia": lambda d, t, r: _check(
        {"b.toml": t + "\n[extensions]\nreflected_steer_inertia = -0.1\n"},
        ["check", "{d}/b.toml"], "b.toml", "extension reflected_steer_inertia = -0.1 must be finite and >= 0"),
    "check linear term unknown": lambda d, t, r: _check(
        {"b.toml": t + "\n[extensions.linear_terms]\nK1_steer_steer = 1.0\n"},
        ["check", "{d}/b.toml"], "b.toml", "unknown key 'K1_steer_steer' in [extensions.linear_terms]"),
    "check linear term NaN": lambda d, t, r: _check(
        {"b.toml": t + "\n[extensions.linear_terms]\nK0_steer_steer = nan\n"},
        ["check", "{d}/b.toml"], "b.toml", "linear term K0_steer_steer = nan is not a finite number"),
    "check controller delay": lambda d, t, r: _check(
        {"b.toml": t + "\n[controller]\ndelay = -0.05\n[controller.steer]\nroll_rate = [13.0, -2.0]\n"},
        ["check", "{d}/b.toml"], "b.toml", "controller delay = -0.05 must be finite and >= 0"),
    "check controller lag text": lambda d, t, r: _check(
        {"b.toml": t + "\n[controller]\nlag = \"fast\"\n[controller.steer]\nroll_rate = 13.0\n"},
        ["check", "{d}/b.toml"], "b.toml", "'lag' in [controller] must be a number"),
    "check controller gain without gains": lambda d, t, r: _check(
        {"b.toml": t + "\n[controller]\ngain_scale = 2.0\n"},
        ["check", "{d}/b.toml"], "b.toml", "gain_scale in [controller] acts on the controller's torque"),
    # Critical speeds have no grid, so `check --speeds 0:1e9` is fine; the eigenvalue table and
    # plot of `stability` track modes on a grid, bounded at 1e6 m/s.
    "stability speeds too high": lambda d, t, r: _check(
        {"b.toml": t}, ["stability", "{d}/b.toml", "--speeds", "0:1e9"],
        "speeds", "beyond 1e+06 m/s are not analysed"),
    # --- stability: outputs -------------------------------------------------------------------
    "stability plot is a folder": lambda d, t, r: _check({"b.toml": t, "out/keep": ""},
                                                         ["stability", "{d}/b.toml", "--plot", "{d}/out"], "out",
                                                         "--plot names a folder"),
    "stability plot format": lambda d, t, r: _check({"b.toml": t}, ["stability", "{d}/b.toml", "--plot", "{d}/f.txt"],
                                                    "f.txt", "cannot write a figure as .txt"),
    "stability csv read-only": lambda d, t, r: _check({"b.toml": t},
                                                      ["stability", "{d}/b.toml", "--csv", "{locked}/e.csv"],
                                                      "e.csv", "cannot write: Permission denied"),
    "stability same output": lambda d, t, r: _check({"b.toml": t},
                                                    ["stability", "{d}/b.toml", "--csv", "{d}/o.png",
                                                     "--plot", "{d}/o.png"],
                                                    "o.png", "--plot and --csv name the same file"),
    "stability over input": lambda d, t, r: _check({"b.toml": t}, ["stability", "{d}/b.toml", "--csv", "{d}/b.toml"],
                                                   "b.toml", "refusing to write output over input file"),
    "stability points": lambda d, t, r: _check({"b.toml": t}, ["stability", "{d}/b.toml", "--points", "100000000"],
                                               "--points", "must be between 2 and 100000"),
    "stability bad bicycle": lambda d, t, r: _check({"b.toml": _set(t, "w", "0.0")}, ["stability", "{d}/b.toml"],
                                                    "b.toml", "w = 0 must be positive"),
    # --- sweep --------------------------------------------------------------------------------
    "sweep missing table": lambda d, t, r: _check({}, ["sweep", "{d}/sets.csv", "-o", "{d}/o.csv"], "sets.csv",
                                                  "cannot read"),
    "sweep text cell": lambda d, t, r: _check({"sets.csv": "c,mB\n0.08,85\nfoo,80\n"},
                                              ["sweep", "{d}/sets.csv", "-o", "{d}/o.csv"], "sets.csv",
                                              "line 3, column c: not a number"),
    "sweep unknown column": lambda d, t, r: _check({"sets.csv": "trail\n0.08\n"},
                                                   ["sweep", "{d}/sets.csv", "-o", "{d}/o.csv"], "sets.csv",
                                                   "unknown column(s) trail"),
    "sweep output folder": lambda d, t, r: _check({"sets.csv": "c\n0.08\n", "out/keep": ""},
                                                  ["sweep", "{d}/sets.csv", "-o", "{d}/out"], "out",
                                                  "is a folder, not a file"),
    "sweep output read-only": lambda d, t, r: _check({"sets.csv": "c\n0.08\n"},
                                                     ["sweep", "{d}/sets.csv", "-o", "{locked}/o.csv"], "o.csv",
                                                     "cannot write: Permission denied"),
    "sweep over input": lambda d, t, r: _check({"sets.csv": "c\n0.08\n"},
                                               ["sweep", "{d}/sets.csv", "-o", "{d}/sets.csv"],
                                               "sets.csv", "refusing to write output over input file"),
    # --- regenerate ---------------------------------------------------------------------------
    "regenerate output is a file": lambda d, t, r: _check({"gen": "x"}, ["regenerate", "--output", "{d}/gen"], "gen",
                                                          "--output needs a folder; this is a file"),
    # --- fit: run files -------------------------------------------------------------------------
    "fit missing run": lambda d, t, r: _check({}, ["fit", "{d}/run.csv"], "run.csv", "cannot read file"),
    "fit empty run": lambda d, t, r: _check({"run.csv": ""}, ["fit", "{d}/run.csv"], "run.csv", "empty file"),
    "fit text roll rate": lambda d, t, r: _check({"run.csv": _runs(r, lambda x: _cell(x, 10, "roll_rate", "abc"))},
                                                 ["fit", "{d}/run.csv"], "run.csv",
                                                 "column 'roll_rate': non-numeric value 'abc'"),
    "fit infinite speed": lambda d, t, r: _check({"run.csv": _runs(r, lambda x: _cell(x, 3, "speed", "inf"))},
                                                 ["fit", "{d}/run.csv"], "run.csv", "column 'speed': inf value"),
    "fit time backwards": lambda d, t, r: _check({"run.csv": _runs(r, lambda x: _cell(x, 5, "time", "0.0"))},
                                                 ["fit", "{d}/run.csv"], "run.csv", "time is not strictly increasing"),
    "fit ragged row": lambda d, t, r: _check({"run.csv": _runs(r, lambda x: x[:-1] + [x[-1] + ",7"])},
                                             ["fit", "{d}/run.csv"], "run.csv", "fields, the header has"),
    "fit too short": lambda d, t, r: _check({"run.csv": _runs(r, lambda x: x[:_header_index(x) + 50])},
                                            ["fit", "{d}/run.csv"], "run.csv", "run too short"),
    "fit no roll rate": lambda d, t, r: _check({"run.csv": _runs(r, lambda x: [x[i].replace("roll_rate", "lean")
                                                                               if i == _header_index(x) else x[i]
                                                                               for i in range(len(x))])},
                                               ["fit", "{d}/run.csv"], "run.csv", "missing roll_rate column"),
    "fit corrupt gzip": lambda d, t, r: _check({"run.csv.gz": gzip.compress(r.encode())[:200]},
                                               ["fit", "{d}/run.csv.gz"], "run.csv.gz", "corrupt gzip data"),
    "fit bad layout": lambda d, t, r: _check({"run.csv": r, "layout.toml": "[columns\n"},
                                             ["fit", "{d}/run.csv", "--layout", "{d}/layout.toml"], "layout.toml",
                                             "bad layout file"),
    "fit bad windows file": lambda d, t, r: _check({"run.csv": r, "w.csv": "start;stop\n1;2\n"},
                                                   ["fit", "{d}/run.csv", "--windows", "{d}/w.csv"], "w.csv",
                                                   "windows file needs"),
    "fit windows of other runs": lambda d, t, r: _check({"run.csv": r, "w.csv": "run,start,stop\nother,1,2\n"},
                                                        ["fit", "{d}/run.csv", "--windows", "{d}/w.csv"], "w.csv",
                                                        "no window names one of the runs given"),
    "fit windows file empty": lambda d, t, r: _check({"run.csv": r, "w.csv": "run,start,stop\n"},
                                                     ["fit", "{d}/run.csv", "--windows", "{d}/w.csv"], "w.csv",
                                                     "the windows file has no windows"),
    "fit same outputs": lambda d, t, r: _check({"run.csv": r},
                                               ["fit", "{d}/run.csv", "--json", "{d}/o.json", "--csv", "{d}/o.json"],
                                               "o.json", "--json and --csv name the same file"),
    "fit json read-only": lambda d, t, r: _check({"run.csv": r}, ["fit", "{d}/run.csv", "--json", "{locked}/o.json"],
                                                 "o.json", "cannot write: Permission denied"),
    "fit plot is a file": lambda d, t, r: _check({"run.csv": r, "figs": "x"},
                                                 ["fit", "{d}/run.csv", "--plot", "{d}/figs"],
                                                 "figs", "--plot needs a folder; this is a file"),
    "fit json over run": lambda d, t, r: _check({"run.csv": r}, ["fit", "{d}/run.csv", "--json", "{d}/run.csv"],
                                                "run.csv", "refusing to write output over input file"),
    # --- simulate -----------------------------------------------------------------------------
    "simulate sample rate": lambda d, t, r: _check({"b.toml": t},
                                                   ["simulate", "--bicycle", "{d}/b.toml", "--speed", "5",
                                                    "--sample-rate", "1e9", "--output", "{d}/s.csv"],
                                                   "1e+09 Hz", "at most 2e+06 are simulated"),
    "simulate output is a file": lambda d, t, r: _check({"b.toml": t, "runs": "x"},
                                                        ["simulate", "--bicycle", "{d}/b.toml", "--speeds", "3,5",
                                                         "--output", "{d}/runs"], "runs",
                                                        "output exists and is not a folder"),
    "simulate read-only": lambda d, t, r: _check({"b.toml": t},
                                                 ["simulate", "--bicycle", "{d}/b.toml", "--speed", "5", "--output",
                                                  "{locked}/s.csv"], "s.csv", "cannot write: Permission denied"),
    "simulate bad bicycle": lambda d, t, r: _check({"b.toml": _set(t, "g", "-9.81")},
                                                   ["simulate", "--bicycle", "{d}/b.toml", "--speed", "5", "--output",
                                                    "{d}/s.csv"], "b.toml", "g = -9.81 must be positive"),
    # --- diagnose -----------------------------------------------------------------------------
    "diagnose windows of other runs": lambda d, t, r: _check({"run.csv": r, "b.toml": t,
                                                              "w.csv": "file,start,stop\nother.csv,1,2\n"},
                                                             ["diagnose", "{d}/run.csv", "--bicycle", "{d}/b.toml",
                                                              "--windows", "{d}/w.csv"], "w.csv",
                                                             "no window names one of the runs given"),
    "diagnose report is a file": lambda d, t, r: _check({"run.csv": r, "b.toml": t, "rep": "x"},
                                                        ["diagnose", "{d}/run.csv", "--bicycle", "{d}/b.toml",
                                                         "--report", "{d}/rep"], "rep",
                                                        "--report needs a folder; this is a file"),
    "diagnose json is a folder": lambda d, t, r: _check({"run.csv": r, "b.toml": t, "j/keep": ""},
                                                        ["diagnose", "{d}/run.csv", "--bicycle", "{d}/b.toml",
                                                         "--json", "{d}/j"], "j", "--json names a folder"),
    "diagnose model over bicycle": lambda d, t, r: _check({"run.csv": r, "b.toml": t},
                                                          ["diagnose", "{d}/run.csv", "--bicycle", "{d}/b.toml",
                                                           "--save-model", "{d}/b.toml"], "b.toml",
                                                          "refusing to write output over input file"),
    "diagnose report read-only": lambda d, t, r: _check({"run.csv": r, "b.toml": t},
                                                        ["diagnose", "{d}/run.csv", "--bicycle", "{d}/b.toml",
                                                         "--report", "{locked}/rep"], "rep",
                                                        "cannot write: Permission denied"),
    "diagnose rider as bicycle": lambda d, t, r: _check(
        {"run.csv": r, "RBenchmark.txt": (DATA / "riders" / "JasonBrowserBenchmark.txt").read_text()},
        ["diagnose", "{d}/run.csv", "--bicycle", "{d}/RBenchmark.txt"], "RBenchmark.txt", "a rider file"),
    "diagnose bad run": lambda d, t, r: _check({"run.csv": _runs(r, lambda x: _cell(x, 2, "time", "soon")),
                                                "b.toml": t},
                                               ["diagnose", "{d}/run.csv", "--bicycle", "{d}/b.toml"], "run.csv",
                                               "column 'time': non-numeric value 'soon'"),
    # --- endless and huge inputs (issue 53): exit 2 at once, whatever the command -------------
    **{f"{command} {device}": _device_case(command, device, words)
       for command in DEVICE_COMMANDS
       for device, words in (("/dev/zero", "not a regular file" if command == "diagnose bicycle"
                              else "not a text file (it holds NUL bytes)"),
                             ("/dev/urandom", "invalid UTF-8" if command in ("fit", "sweep", "diagnose") else ""))
       if words},
    "check /dev/zero": lambda d, t, r: _check({}, ["check", "/dev/zero"], "/dev/zero", "not a regular file"),
    "fit huge sparse file": lambda d, t, r: _check({"big.csv": b""}, ["fit", "{d}/big.csv"], "big.csv",
                                                   "not a text file (it holds NUL bytes)"),
    # --- contradictions (issue 53) --------------------------------------------------------------
    "fit sample rate contradicts time": lambda d, t, r: _check(
        {"run.csv": r.replace("# sample_rate: 100\n", "# sample_rate: 1000\n")}, ["fit", "{d}/run.csv"], "run.csv",
        "metadata sample_rate 1000 Hz contradicts the time column (100 Hz"),
    # (One such sample alone would be a glitch, left out: the whole run is that fast.)
    "fit speed beyond any": lambda d, t, r: _check({"run.csv": _runs(r, lambda x: _column(x, "speed", "2e6"))},
                                                   ["fit", "{d}/run.csv"], "run.csv",
                                                   "a speed of 2e+06 m/s: no bicycle rides faster than 100 m/s"),
    "diagnose runs of two bicycles": lambda d, t, r: _check(
        {"a.csv": r, "b.csv": r.replace("# bicycle: benchmark\n", "# bicycle: sbw2024\n")},
        ["diagnose", "{d}/a.csv", "{d}/b.csv", "--bicycle", "benchmark"], "b.csv",
        "runs of different bicycles"),
    "check radius of gyration": lambda d, t, r: _check({"b.toml": _set(t, "mB", "1e-3")}, ["check", "{d}/b.toml"],
                                                       "b.toml", "rear frame: a radius of gyration of 105 m"),
    "fit windows start NaN": lambda d, t, r: _check({"run.csv": r, "w.csv": "run,start,stop\nrun,nan,5\n"},
                                                    ["fit", "{d}/run.csv", "--windows", "{d}/w.csv"], "w.csv",
                                                    "line 2: start time is nan (not a finite number of seconds)"),
    "regenerate check of no folder": lambda d, t, r: _check({}, ["regenerate", "--check", "--output", "{d}/none"],
                                                            "none", "--check: no such folder"),
    # --- simulate writes nothing fit refuses (issue 53) -----------------------------------------
    "simulate 5 Hz": lambda d, t, r: _check({}, ["simulate", "--bicycle", "benchmark", "--speed", "5", "--sample-rate",
                                                 "5", "--output", "{d}/s.csv"], "5 Hz", "below 10 Hz"),
    "simulate 1e6 m/s": lambda d, t, r: _check({}, ["simulate", "--bicycle", "benchmark", "--speed", "1e6",
                                                    "--output", "{d}/s.csv"], "1000000.2 m/s",
                                               "a run is read up to 100 m/s"),
    "simulate 100 m/s": lambda d, t, r: _check({}, ["simulate", "--bicycle", "benchmark", "--speed", "100",
                                                    "--output", "{d}/s.csv"], "100.2 m/s",
                                               "a run is read up to 100 m/s, faster than any bicycle rides"),
    "simulate noise 1e300": lambda d, t, r: _check({}, ["simulate", "--bicycle", "benchmark", "--speed", "5",
                                                        "--noise", "1e300", "--output", "{d}/s.csv"], "2e+298 m/s",
                                                   "would write negative speeds"),
    # --- fuzzing of run, windows, layout and bicycle files -------------------------------------
    "fit one data row": lambda d, t, r: _check({"run.csv": _runs(r, lambda x: x[:_header_index(x) + 2])},
                                               ["fit", "{d}/run.csv"], "run.csv", "run too short (one sample"),
    "fit time column empty": lambda d, t, r: _check({"run.csv": _runs(r, lambda x: _column(x, "time", ""))},
                                                    ["fit", "{d}/run.csv"], "run.csv",
                                                    "column time has no values (every cell empty or NaN)"),
    "fit overflowing number": lambda d, t, r: _check({"run.csv": _runs(r, lambda x: _cell(x, 5, "roll_rate",
                                                                                          "1e99999"))},
                                                     ["fit", "{d}/run.csv"], "run.csv",
                                                     "column 'roll_rate': value 1e99999 is too large (infinite)"),
    "fit bars": lambda d, t, r: _check({"run.csv": r.replace(",", "|")}, ["fit", "{d}/run.csv"], "run.csv",
                                       "missing roll_rate column (the header is one column 'time|roll_rate|"),
    "fit UTF-16 run": lambda d, t, r: _check({"run.csv": r.encode("utf-16")}, ["fit", "{d}/run.csv"], "run.csv",
                                             "not UTF-8 text but UTF-16"),
    "evaluate roll rate never changes": lambda d, t, r: _check(
        {"run.csv": _runs(r, lambda x: _column(x, "roll_rate", "0"))},
        ["evaluate", "{d}/run.csv", "--bicycle", "benchmark", "--no-samples"], "run.csv",
        "roll_rate never changes (a sensor not connected?): nothing to fit"),
    "evaluate no usable window": lambda d, t, r: _check(
        {"run.csv": _runs(r, _drifting_roll_rate)},
        ["evaluate", "{d}/run.csv", "--bicycle", "benchmark", "--no-samples"], "run.csv",
        "no usable window with a fitted weave eigenvalue in "),
    "check tiny wheelbase": lambda d, t, r: _check({"b.toml": _set(t, "w", "1e-300")}, ["check", "{d}/b.toml"],
                                                   "b.toml", "w = 1e-300 m is below 0.001 m: not a bicycle"),
    "fit windows rows backwards": lambda d, t, r: _check(
        {"run.csv": r, "w.csv": "run,start_row,stop_row\nrun,400,100\n"},
        ["fit", "{d}/run.csv", "--windows", "{d}/w.csv"], "w.csv", "line 2: stop_row must be after start_row"),
    "fit windows two start columns": lambda d, t, r: _check(
        {"run.csv": r, "w.csv": "run,start,start,stop\nrun,1,2,3\n"},
        ["fit", "{d}/run.csv", "--windows", "{d}/w.csv"], "w.csv", "duplicate column names in the header"),
    "fit windows UTF-16": lambda d, t, r: _check(
        {"run.csv": r, "w.csv": "run,start,stop\nrun,1,3\n".encode("utf-16")},
        ["fit", "{d}/run.csv", "--windows", "{d}/w.csv"], "w.csv", "not a UTF-8 text file"),
    "fit layout delimiter line end": lambda d, t, r: _check(
        {"run.csv": r, "l.toml": 'delimiter = "\\n"\n[columns]\nroll_rate = "roll_rate"\n'},
        ["fit", "{d}/run.csv", "--layout", "{d}/l.toml"], "l.toml",
        "bad layout file: delimiter '\\n' cannot separate numbers"),
}

def _snapshot(folder: Path) -> dict[str, bytes | int]:
    # A huge (sparse) input is compared by size: reading it would take the test's memory.
    return {str(p.relative_to(folder)): p.read_bytes() if p.stat().st_size < 1 << 20 else p.stat().st_size
            for p in sorted(folder.rglob("*")) if p.is_file()}


def _prepare(name: str, tmp_path: Path, toml_text: str, run_text: str
             ) -> tuple[Case, list[str], dict[str, bytes | int]]:
    folder = tmp_path / "work"
    folder.mkdir()
    locked = read_only_folder(tmp_path)
    case = CASES[name](folder, toml_text, run_text)
    for relative, content in case.files.items():
        path = folder / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(content if isinstance(content, bytes) else content.encode())
        if relative == "big.csv":
            os.truncate(path, 10 << 30)  # 10 GiB of zeros, sparse: no disk space used
    argv = [arg.replace("{d}", str(folder)).replace("{locked}", str(locked)) for arg in case.argv]
    return case, argv, _snapshot(folder)


def test_the_corpus_is_large_and_covers_every_command_with_inputs(toml_text, run_text):
    commands = {CASES[name](Path("/x"), toml_text, run_text).argv[0] for name in CASES}
    assert len(CASES) >= 40
    assert commands >= {"check", "stability", "sweep", "regenerate", "fit", "simulate", "diagnose"}


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_input_exits_2_with_one_line(name, tmp_path, toml_text, run_text, capsys):
    case, argv, before = _prepare(name, tmp_path, toml_text, run_text)
    status = main(argv)
    err = capsys.readouterr().err
    assert status == 2, err
    assert err.endswith("\n") and err.count("\n") == 1, err
    assert "Traceback" not in err
    assert case.named in err and case.problem in err, err
    assert _snapshot(tmp_path / "work") == before  # inputs unchanged, nothing written


@pytest.mark.parametrize("name", ["check absurd mass", "stability plot format", "simulate read-only"])
def test_bad_input_in_a_real_process(name, tmp_path, toml_text, run_text):
    case, argv, before = _prepare(name, tmp_path, toml_text, run_text)
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    result = subprocess.run([sys.executable, "-m", "whipple", *argv], capture_output=True, text=True, env=env,
                            timeout=300)
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
    assert case.named in result.stderr and case.problem in result.stderr
    assert _snapshot(tmp_path / "work") == before
