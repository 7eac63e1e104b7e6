"""Standard streams and signals: '-' and /dev/stdout as outputs, '-' as a table, SIGTERM/SIGHUP.

Real processes: what a shell sees (the bytes on standard output, the lines on standard error,
the exit status, the files left in the folder).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from whipple.cli import main
from whipple.measurement.runs import read_run

ENV = {**os.environ, "PYTHONWARNINGS": "ignore"}


def _whipple(*args: str, stdin: bytes | None = None, cwd: Path | None = None) -> subprocess.CompletedProcess[bytes]:
    return subprocess.run([sys.executable, "-m", "whipple", *args], input=stdin, capture_output=True, env=ENV,
                          cwd=cwd, timeout=300)


def test_a_table_to_standard_output_through_head():
    shell = subprocess.run(f"{sys.executable} -m whipple stability benchmark --csv - | head -2", shell=True,
                           capture_output=True, env=ENV, timeout=300)
    lines = shell.stdout.decode().splitlines()
    assert len(lines) == 2 and lines[0].startswith("speed_m_per_s,") and lines[1].startswith("0.0,")
    assert b"Traceback" not in shell.stderr and b"Exception" not in shell.stderr


@pytest.mark.parametrize("name", ["-", "/dev/stdout"])
def test_standard_output_holds_the_data_and_the_messages_go_to_standard_error(name):
    result = _whipple("stability", "benchmark", "--points", "3", "--csv", name)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.decode().splitlines()
    assert len(lines) == 4 and lines[0].startswith("speed_m_per_s,")
    assert b"weave speed:" in result.stderr and f"wrote {name}".encode() in result.stderr


def test_sweep_from_standard_input_to_standard_output(tmp_path):
    result = _whipple("sweep", "-", "-o", "-", stdin=b"c,mB\n0.08,85\n0.09,80\n", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.decode().splitlines()
    assert lines[0] == "c,mB,weave_speed,capsize_speed,stable_speed_ranges,problem"
    assert lines[1].startswith("0.08,85,4.29238") and len(lines) == 3
    assert b"analysed 2 of 2 parameter sets" in result.stderr
    assert list(tmp_path.iterdir()) == []  # no file named '-'


def test_a_sweep_error_is_one_line_of_its_own(tmp_path):
    # Without a terminal there is no progress counter: the error is the only line.
    table = tmp_path / "sets.csv"
    table.write_text("c\n" + "0.08\n" * 5000 + "oops\n")
    result = _whipple("sweep", str(table), "-o", str(tmp_path / "out.csv"), "--chunk", "1000")
    assert result.returncode == 2
    assert result.stderr.decode().splitlines() == [f"whipple sweep: error: {table}: line 5002, column c: not a "
                                                   "number: 'oops'"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sets.csv"]


def test_json_and_csv_to_standard_output_in_process(tmp_path, capsys):
    assert main(["sweep", "--quiet", "-o", "-", str(_table(tmp_path))]) == 0
    captured = capsys.readouterr()
    assert captured.out.startswith("c,weave_speed,")
    assert "wrote -" in captured.err
    assert main(["stability", "benchmark", "--points", "2", "--csv", "-", "--plot", "-"]) == 2
    assert "--plot and --csv name the same file" in capsys.readouterr().err


def _table(folder: Path) -> Path:
    path = folder / "sets.csv"
    path.write_text("c\n0.08\n0.09\n")
    return path


@pytest.mark.parametrize("name", ["SIGTERM", "SIGHUP"])
def test_a_signal_during_a_sweep_leaves_the_old_output_and_no_temporary_file(tmp_path, name):
    table = tmp_path / "sets.csv"
    rows = "\n".join(f"{0.06 + 0.04 * (k % 1000) / 1000:.6f},{80 + k % 13}" for k in range(400_000))
    table.write_text("c,mB\n" + rows + "\n")
    output = tmp_path / "out.csv"
    output.write_text("old results\n")
    process = subprocess.Popen([sys.executable, "-m", "whipple", "sweep", str(table), "-o", str(output),
                                "--chunk", "1000"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=ENV)
    deadline = time.monotonic() + 120
    while not [p for p in tmp_path.iterdir() if p.name.startswith(".out.csv.")]:
        assert process.poll() is None and time.monotonic() < deadline, "the sweep ended before it wrote anything"
        time.sleep(0.05)
    process.send_signal(getattr(signal, name))
    _, err = process.communicate(timeout=120)
    assert process.returncode == 128 + getattr(signal, name)
    assert err.decode().splitlines() == [f"whipple sweep: ended by {name}"]
    assert output.read_text() == "old results\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv", "sets.csv"]


def test_progress_is_drawn_only_on_a_terminal(tmp_path, capsys):
    # capsys' stderr is no terminal: nothing but the result line.
    table = tmp_path / "sets.csv"
    table.write_text("c\n" + "0.08\n" * 3000)
    assert main(["sweep", str(table), "-o", str(tmp_path / "o.csv")]) == 0
    captured = capsys.readouterr()
    assert captured.err == "" and captured.out.startswith("analysed 3000 of 3000")


def test_a_simulated_run_to_standard_output_reads_back(tmp_path):
    result = _whipple("simulate", "--bicycle", "benchmark", "--speed", "5", "--output", "-", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(b"# sample_rate: 100\n") and b"samples at 100 Hz" in result.stderr
    saved = tmp_path / "run.csv"
    saved.write_bytes(result.stdout)
    assert read_run(saved).time.size == 1971
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.csv"]


def test_a_figure_to_standard_output():
    result = _whipple("stability", "benchmark", "--points", "5", "--plot", "-")
    assert result.returncode == 0 and result.stdout[:8] == b"\x89PNG\r\n\x1a\n"
