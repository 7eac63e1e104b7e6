"""``whipple check``, ``whipple verify`` and ``whipple regenerate --check`` from the command line.

Reference values: weave and capsize speeds of the benchmark, Meijaard et al. (2007) Table 2(a)
(shared reference file, also in whipple/data/reference); the seed bicycle's approximate
speeds, Kooijman & Schwab (2009) Figure 6 caption (about 4.0 and 7.9 m/s).
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from whipple.cli import main

BENCHMARK_TOML = """\
name = "bad"
[parameters]
w = 1.02
c = 0.08
lam = 0.3141592653589793
g = 9.81
rR = 0.3
mR = 2.0
IRxx = 0.0603
IRyy = 0.12
xB = 0.3
zB = -0.9
mB = 85.0
IBxx = 9.2
IByy = 11.0
IBzz = 2.8
IBxz = 2.4
xH = 0.9
zH = -0.7
mH = 4.0
IHxx = 0.05892
IHyy = 0.06
IHzz = 0.00708
IHxz = -0.00756
rF = 0.35
mF = 3.0
IFxx = 0.1405
IFyy = 0.28
"""


def test_check_benchmark_json(capsys):
    assert main(["check", "benchmark", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert set(report["matrices"]) >= {"M", "C1", "K0", "K2"}
    assert abs(report["weave_speed"] - 4.29238253634111) < 1e-12
    assert abs(report["capsize_speed"] - 6.02426201538837) < 1e-12
    low, high = report["stable_speed_ranges"][0]
    assert abs(low - 4.29238253634111) < 1e-12 and abs(high - 6.02426201538837) < 1e-12
    assert abs(report["matrices"]["K0"][0][0] - (-80.95 * 9.81)) < 1e-10


def test_check_seed_bicycle_stable_between_weave_and_capsize(capsys):
    assert main(["check", "kooijman2008", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert abs(report["weave_speed"] - 4.0) < 0.1
    assert abs(report["capsize_speed"] - 7.9) < 0.1
    assert report["stable_speed_ranges"] == [[report["weave_speed"], report["capsize_speed"]]]


def test_check_any_speed_range_width(capsys):
    # The critical speeds have no speed grid: a range to 1e9 m/s gives the same crossings.
    assert main(["check", "benchmark", "--json", "--speeds", "0:1e9"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert abs(report["weave_speed"] - 4.29238253634111) < 1e-12
    assert report["stable_speed_ranges"] == [[report["weave_speed"], report["capsize_speed"]]]


def test_check_speed_range_without_crossings(capsys):
    assert main(["check", "benchmark", "--json", "--speeds", "7:9"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["weave_speed"] is None and report["capsize_speed"] is None
    assert report["stable_speed_ranges"] == []


def test_check_text_output(capsys):
    assert main(["check", "benchmark"]) == 0
    out = capsys.readouterr().out
    assert "weave speed:   4.29238253634" in out and "capsize speed: 6.02426201539" in out


@pytest.mark.parametrize("edit, message", [
    (lambda t: t.replace("w = 1.02", "w = 1.02 ="), "TOML"),
    (lambda t: t + "foo = 1.0\n", "foo"),
    (lambda t: t.replace("mB = 85.0\n", ""), "mB"),
    (lambda t: t.replace("mB = 85.0", "mB = -85.0"), "mB"),
    (lambda t: t.replace("IBxz = 2.4", "IBxz = 20.4"), "positive semi-definite"),
    (lambda t: t.replace("c = 0.08", "c = nan"), "c"),
])
def test_bad_bicycle_files_give_one_line_and_exit_2(tmp_path, capsys, edit, message):
    path = tmp_path / "bicycle.toml"
    text = edit(BENCHMARK_TOML)
    path.write_text(text)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert str(path) in err and message in err
    assert path.read_text() == text  # the input is never changed


def test_console_script_has_no_traceback(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("[parameters\nw = 1")
    result = subprocess.run([sys.executable, "-m", "whipple", "check", str(path)],
                            capture_output=True, text=True, check=False)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr and str(path) in result.stderr


def test_unknown_builtin_name(capsys):
    assert main(["check", "no-such-bicycle"]) == 2
    assert "benchmark" in capsys.readouterr().err


def test_verify_passes_and_reports_json(capsys):
    assert main(["verify", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["passed"] and len(report["references"]) == 2
    for reference in report["references"]:
        assert all(entry["error"] <= entry["tolerance"] for entry in reference["entries"])
