"""Memory and time of ``whipple fit`` on long runs: 1, 2 and 5 million samples in one run of the script.

A simulated benchmark run at 5 m/s (100 Hz, pushes every 7.4 s, the scenario's sensors) is
repeated end to end until the run holds the number of samples asked for, and written as a
native run file. Each file is fitted by ``whipple fit FILE --json OUT`` in a child process;
the child's peak resident memory (``os.wait4``'s ``ru_maxrss``) and wall time are printed,
with their ratios to the smallest run's and the ratio of the lengths: memory and time that
grow linearly with the run's length show ratios near the length ratio (or below it, where a
fixed cost dominates).

Run: ``python benchmarks/bench_long_runs.py [--millions 1 2 5] [--folder DIR]``
(``--folder`` keeps the run files, which take about 40 bytes per sample, for another run).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from whipple.model.parameters import load_bicycle
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

#: Samples of the simulated piece repeated to build a long run (100 Hz: 1,000 s).
PIECE_SAMPLES = 100_000
SAMPLE_RATE = 100.0


def piece() -> tuple[np.ndarray, np.ndarray]:
    """One simulated stretch of ``PIECE_SAMPLES`` samples: its columns (roll rate, yaw rate,
    steer angle, speed) and the header names."""
    scenario = RunScenario(speed=5.0, sample_rate=SAMPLE_RATE, duration=(PIECE_SAMPLES - 1) / SAMPLE_RATE)
    run = simulate_run(load_bicycle("benchmark"), scenario)
    names = np.array(scenario.columns)
    return np.column_stack([run.signals[name] for name in scenario.columns]), names


def write_long_run(path: Path, samples: int, columns: np.ndarray, names: np.ndarray) -> None:
    """Write a native run file of `samples` samples, `columns` repeated end to end."""
    header = "# sample_rate: 100\n# bicycle: benchmark\ntime," + ",".join(names) + "\n"
    with open(path, "w", encoding="ascii") as out:
        out.write(header)
        for first in range(0, samples, PIECE_SAMPLES):
            count = min(PIECE_SAMPLES, samples - first)
            block = np.column_stack([(first + np.arange(count)) / SAMPLE_RATE, columns[:count]])
            np.savetxt(out, block, fmt=["%.2f", "%.6g", "%.6g", "%.6g", "%.6g"], delimiter=",")


def measure(path: Path, output: Path) -> tuple[float, float, int]:
    """Peak resident memory [bytes] and wall time [s] of ``whipple fit`` on `path`, and its exit code."""
    command = [sys.executable, "-m", "whipple", "fit", str(path), "--json", str(output)]
    start = time.perf_counter()
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.perf_counter() - start
    child.returncode = os.waitstatus_to_exitcode(status)
    error = child.stderr.read().decode() if child.stderr else ""
    if child.returncode:
        print(f"  whipple fit exited {child.returncode}: {error.strip()}")
    # ru_maxrss is in kilobytes on Linux.
    return usage.ru_maxrss * 1024.0, seconds, child.returncode


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--millions", type=float, nargs="+", default=[1.0, 2.0, 5.0])
    parser.add_argument("--folder", type=Path, default=None)
    args = parser.parse_args()
    folder = args.folder or Path(tempfile.mkdtemp(prefix="whipple-long-runs-"))
    folder.mkdir(parents=True, exist_ok=True)
    columns, names = piece()
    rows = []
    try:
        for millions in sorted(args.millions):
            samples = int(round(millions * 1e6))
            path = folder / f"long_{samples}.csv"
            if not path.exists():
                write_long_run(path, samples, columns, names)
            memory, seconds, code = measure(path, folder / f"long_{samples}.json")
            rows.append((samples, memory, seconds, code))
            print(f"{samples:>10,d} samples: peak {memory / 2**30:6.3f} GiB, {seconds:7.1f} s"
                  f"{'' if code == 0 else f' (exit {code})'}", flush=True)
    finally:
        if args.folder is None:
            shutil.rmtree(folder, ignore_errors=True)
    base_samples, base_memory, base_seconds, _ = rows[0]
    print("\nratios to the smallest run (length, peak memory, time; linear growth keeps the last two at "
          "or below the first):")
    for samples, memory, seconds, _ in rows:
        print(f"  {samples / base_samples:5.2f}  {memory / base_memory:5.2f}  {seconds / base_seconds:5.2f}")
    if len(rows) > 1:
        # Past a fixed cost, time and memory per million samples of the two largest runs.
        (s1, m1, t1, _), (s2, m2, t2, _) = rows[-2], rows[-1]
        print(f"marginal cost between the two largest runs: {(m2 - m1) / 2**20 / ((s2 - s1) / 1e6):.0f} MiB and "
              f"{(t2 - t1) / ((s2 - s1) / 1e6):.1f} s per million samples")


if __name__ == "__main__":
    main()
