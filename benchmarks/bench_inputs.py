"""Endless and huge inputs: time and peak memory of every command, against a baseline in the same run.

Run:  python benchmarks/bench_inputs.py [--samples 1000000 2000000 5000000] [--endless-seconds 20]

Each case runs ``whipple`` as a child process; its wall time and peak resident memory (the
child's own ``ru_maxrss`` from ``os.wait4``) are printed, and their ratios to the baseline
measured first in the same run: ``whipple check benchmark`` (process start, imports, one small
bicycle file). The issue's targets: every endless input refused with exit 2 within seconds and
under 1 GB.

1. Endless inputs as every file a command reads: ``/dev/zero``, ``/dev/urandom``, a 10 GiB
   sparse file (zeros, no disk space used), a named pipe fed without line ends
   (``tr '\\0' 1 < /dev/zero``), and a named pipe of valid run rows without end (``yes``): the run
   reader stops at its row cap.
2. A sweep of an endless pipe of valid parameter rows, ended by SIGTERM after
   ``--endless-seconds``: its memory stays bounded (chunks), the old output stays, no temporary
   file is left.
3. Reading long run files (``--samples``): time and peak memory of ``read_run`` alone, which should
   grow linearly with the length (the window finder is measured elsewhere).
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ENV = {**os.environ, "PYTHONWARNINGS": "ignore"}
#: Commands and the file each reads; DEV is replaced by the endless input.
COMMANDS = {
    "fit RUN": ["fit", "DEV"],
    "diagnose RUN": ["diagnose", "DEV", "--bicycle", "benchmark"],
    "sweep TABLE": ["sweep", "DEV", "-o", "OUT/out.csv"],
    "check --rider": ["check", "benchmark", "--rider", "DEV"],
    "stability --rider": ["stability", "benchmark", "--rider", "DEV"],
    "simulate --rider": ["simulate", "--bicycle", "benchmark", "--rider", "DEV", "--speed", "5", "--output",
                         "OUT/s.csv"],
    "fit --layout": ["fit", "RUNFILE", "--layout", "DEV"],
    "fit --windows": ["fit", "RUNFILE", "--windows", "DEV"],
    "check BICYCLE": ["check", "DEV"],
}


def measure(argv: list[str], stdin: int | None = None) -> tuple[int, float, float, str]:
    """Run a child; return (exit status, seconds, peak RSS [MB], last line of stderr)."""
    started = time.perf_counter()
    with tempfile.TemporaryFile() as err:
        process = subprocess.Popen(argv, stdin=stdin, stdout=subprocess.DEVNULL, stderr=err, env=ENV)
        _, status, usage = os.wait4(process.pid, 0)
        process.returncode = os.waitstatus_to_exitcode(status)
        elapsed = time.perf_counter() - started
        err.seek(0)
        lines = err.read().decode(errors="replace").strip().splitlines()
    return process.returncode, elapsed, usage.ru_maxrss / 1024, lines[-1] if lines else ""


def whipple(*args: str) -> list[str]:
    return [sys.executable, "-m", "whipple", *args]


class Feeder:
    """A named pipe fed by a shell command (started when the pipe is used, stopped after)."""

    def __init__(self, folder: Path, name: str, command: str) -> None:
        self.path = folder / name
        self.command = command

    def __enter__(self) -> Path:
        if self.path.exists():
            self.path.unlink()
        os.mkfifo(self.path)
        self.process = subprocess.Popen(["sh", "-c", f"{self.command} > '{self.path}' 2>/dev/null"],
                                        start_new_session=True)
        return self.path

    def __exit__(self, *exc: object) -> None:
        try:
            os.killpg(self.process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.process.wait()
        self.path.unlink()


def endless_inputs(folder: Path, baseline: tuple[float, float]) -> None:
    run = folder / "run.csv"
    subprocess.run(whipple("simulate", "--bicycle", "benchmark", "--speed", "5", "--output", str(run)), env=ENV,
                   check=True, capture_output=True)
    sparse = folder / "sparse.csv"
    with sparse.open("wb") as handle:
        handle.truncate(10 << 30)
    feeders = {
        "pipe without line ends": "tr '\\0' 1 < /dev/zero",
        "pipe of valid run rows": "{ echo time,roll_rate,speed; yes 0.01,0.1,5; }",
    }
    print(f"{'command':<20} {'input':<24} {'exit':>4} {'time [s]':>9} {'x base':>7} {'peak [MB]':>10} "
          f"{'x base':>7}  message")
    for label, template in COMMANDS.items():
        inputs: list[tuple[str, object]] = [("/dev/zero", "/dev/zero"), ("/dev/urandom", "/dev/urandom"),
                                            ("10 GiB sparse file", sparse)]
        inputs += [(name, Feeder(folder, "fifo.csv", command)) for name, command in feeders.items()
                   if label in ("fit RUN", "sweep TABLE") or name == "pipe without line ends"]
        for name, source in inputs:
            if isinstance(source, Feeder):
                with source as path:
                    result = measure(whipple(*_argv(template, path, folder, run)))
            else:
                result = measure(whipple(*_argv(template, source, folder, run)))
            _row(label, name, result, baseline)


def _argv(template: list[str], device: object, folder: Path, run: Path) -> list[str]:
    return [str(device) if a == "DEV" else str(run) if a == "RUNFILE" else a.replace("OUT", str(folder))
            for a in template]


def _row(label: str, name: str, result: tuple[int, float, float, str], baseline: tuple[float, float]) -> None:
    status, seconds, peak, message = result
    print(f"{label:<20} {name:<24} {status:>4} {seconds:>9.2f} {seconds / baseline[0]:>7.2f} {peak:>10.0f} "
          f"{peak / baseline[1]:>7.2f}  {message[:110]}", flush=True)


def endless_sweep(folder: Path, seconds: float, baseline: tuple[float, float]) -> None:
    output = folder / "sweep_out.csv"
    output.write_text("old\n")
    with Feeder(folder, "rows.csv", "{ echo c,mB; yes 0.08,85; }") as path:
        started = time.perf_counter()
        process = subprocess.Popen(whipple("sweep", str(path), "-o", str(output)), stdout=subprocess.DEVNULL,
                                   stderr=subprocess.PIPE, env=ENV)
        time.sleep(seconds)
        partial = [p for p in folder.iterdir() if p.name.startswith(".sweep_out.csv.")]
        rows = sum(1 for _ in partial[0].open("rb")) - 1 if partial else 0
        process.send_signal(signal.SIGTERM)
        _, status, usage = os.wait4(process.pid, 0)
        elapsed = time.perf_counter() - started
        message = process.stderr.read().decode().strip() if process.stderr else ""
    left = sorted(p.name for p in folder.iterdir() if p.name.startswith(".sweep_out"))
    intact = "intact" if output.read_text() == "old\n" else "CHANGED"
    print(f"\nsweep of an endless pipe of valid rows, SIGTERM after {seconds:g} s: exit "
          f"{os.waitstatus_to_exitcode(status)}, {rows} rows written by then ({rows / seconds:.0f}/s), peak "
          f"{usage.ru_maxrss / 1024:.0f} MB ({usage.ru_maxrss / 1024 / baseline[1]:.2f} x base) in {elapsed:.1f} s; "
          f"old output {intact}; temporary files left: "
          f"{left or 'none'}; {message!r}")


def long_runs(folder: Path, sizes: list[int], baseline: tuple[float, float]) -> None:
    print(f"\n{'samples':>10} {'file [MB]':>10} {'read [s]':>9} {'x base':>7} {'peak [MB]':>10} {'x base':>7} "
          f"{'s per M':>8} {'MB per M':>9}")
    for size in sizes:
        path = folder / f"long_{size}.csv"
        _write_long_run(path, size)
        code = (f"from whipple.measurement.runs import read_run; run = read_run({str(path)!r}); "
                f"assert run.time.size == {size}")
        status, seconds, peak, message = measure([sys.executable, "-c", code])
        megabytes = path.stat().st_size / 1e6
        print(f"{size:>10} {megabytes:>10.0f} {seconds:>9.2f} {seconds / baseline[0]:>7.2f} {peak:>10.0f} "
              f"{peak / baseline[1]:>7.2f} {seconds / size * 1e6:>8.2f} {peak / size * 1e6:>9.0f}"
              + (f"  exit {status}: {message}" if status else ""), flush=True)
        path.unlink()


def _write_long_run(path: Path, size: int) -> None:
    """A native run file of `size` samples at 100 Hz: a decaying weave every 20 s, with noise."""
    rng = np.random.default_rng(0)
    with path.open("w") as handle:
        handle.write("# sample_rate: 100\ntime,roll_rate,yaw_rate,steer_angle,speed\n")
        for start in range(0, size, 1_000_000):
            k = np.arange(start, min(start + 1_000_000, size))
            t = k / 100
            phase = t % 20
            weave = np.exp(-0.5 * phase) * np.sin(2 * np.pi * 0.7 * phase)
            table = np.column_stack([t, weave + 0.015 * rng.standard_normal(k.size), 0.3 * weave,
                                     0.1 * weave, 5 + 0.02 * rng.standard_normal(k.size)])
            np.savetxt(handle, table, fmt=["%.2f", "%.5f", "%.5f", "%.5f", "%.4f"], delimiter=",")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, nargs="*", default=[1_000_000, 2_000_000, 5_000_000])
    parser.add_argument("--endless-seconds", type=float, default=20.0)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        measure(whipple("check", "benchmark"))  # bytecode compiled once, untimed
        status, seconds, peak, _ = measure(whipple("check", "benchmark"))
        assert status == 0
        baseline = (seconds, peak)
        print(f"baseline: whipple check benchmark: {seconds:.2f} s, peak {peak:.0f} MB\n")
        endless_inputs(folder, baseline)
        endless_sweep(folder, args.endless_seconds, baseline)
        if args.samples:
            long_runs(folder, args.samples, baseline)


if __name__ == "__main__":
    main()
