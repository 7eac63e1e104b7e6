"""Rows dropped at random from simulated runs: windows still fitted, with and without filling short gaps.

Each simulated run (three bicycles at a speed each, seeds 0 to N-1) is written as a run file,
then again with each data row dropped with probability 2, 5 and 10 %, and both are measured as
``whipple fit`` measures them. Each usable window of the complete run is matched to the window
of the run with drops that starts within 0.2 s of it. Printed per share: windows matched, how far
the matched windows' eigenvalues moved (the larger of the damping's and the frequency's shift,
in the complete window's standard errors; median and max) and their standard errors' ratio
(with drops / without; min and median), with the short gaps filled (``read_run``'s default) and
without (``filled_gap=0``).

Run: ``python benchmarks/bench_dropped_rows.py [--seeds 3]``
"""

from __future__ import annotations

import argparse
import contextlib
import io
import tempfile
from pathlib import Path

import numpy as np

from whipple.cli import main
from whipple.measurement.experiment import measure_run
from whipple.measurement.runs import read_run
from whipple.measurement.short_gaps import FILLED_GAP

CASES = (("benchmark", 5.0), ("kooijman2008", 4.0), ("sbw2024", 4.5))
SHARES = (0.02, 0.05, 0.10)


def _usable(path: Path, filled_gap: float) -> list:
    measured = measure_run(read_run(path, filled_gap=filled_gap))
    return [m.fit for m in measured if m.fit is not None and m.quality is None]


def _dropped(path: Path, target: Path, share: float, rng: np.random.Generator) -> Path:
    lines = path.read_text(encoding="utf-8").splitlines()
    header = next(k for k, line in enumerate(lines) if not line.startswith("#"))
    rows = [line for line in lines[header + 1:] if rng.random() >= share]
    target.write_text("\n".join([*lines[:header + 1], *rows]) + "\n", encoding="utf-8")
    return target


def main_bench() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    args = parser.parse_args()
    rng = np.random.default_rng(1)
    results: dict[tuple[float, float], list] = {(share, fill): [] for share in SHARES for fill in (FILLED_GAP, 0.0)}
    with tempfile.TemporaryDirectory() as folder:
        for seed in range(args.seeds):
            for bicycle, speed in CASES:
                path = Path(folder) / f"{bicycle}_{seed}.csv"
                with contextlib.redirect_stdout(io.StringIO()):
                    main(["simulate", "--bicycle", bicycle, "--speed", str(speed), "--seed", str(seed),
                          "--output", str(path)])
                clean = _usable(path, FILLED_GAP)
                for share in SHARES:
                    dropped = _dropped(path, Path(folder) / f"dropped_{share}.csv", share, rng)
                    for fill in (FILLED_GAP, 0.0):
                        fits = _usable(dropped, fill)
                        for fit in clean:
                            match = next((f for f in fits if abs(f.start - fit.start) < 0.2), None)
                            if match is None:
                                results[share, fill].append(None)
                                continue
                            std = np.sqrt(np.diag(fit.covariance))[:2]
                            moved = max(abs(fit.damping - match.damping) / std[0],
                                        abs(fit.frequency - match.frequency) / std[1])
                            ratio = np.sqrt(np.diag(match.covariance))[:2] / std
                            results[share, fill].append((moved, *ratio))
    for (share, fill), rows in results.items():
        found = np.array([row for row in rows if row is not None])
        text = f"rows dropped {share:.0%}, {'filled' if fill else 'not filled'}: {len(found)} of {len(rows)} windows"
        if found.size:
            text += (f"; moved (std errors) median {np.median(found[:, 0]):.2f}, max {found[:, 0].max():.2f}; "
                     f"std error ratio min {found[:, 1:].min():.2f}, median {np.median(found[:, 1:]):.2f}")
        print(text)


if __name__ == "__main__":
    main_bench()
