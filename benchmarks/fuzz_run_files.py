"""Random corruptions of a run file: every one is measured or refused in one line, none crashes.

A simulated run (the benchmark at 5 m/s on the treadmill, seed 3, cut to its first 7 s) is
written as a run file, and each trial corrupts a copy of it 1-6 times at random: a character
replaced (by a digit, a separator, a quote, a letter of ``nan``/``inf``, a bracket, ``#``...), a
line dropped, repeated elsewhere, cut short or replaced by noise, a separator changed, the file
cut short, a row sent again. The copy is read (``read_run``) and measured with the bicycle
(``measure_runs``). Counted: runs measured, one-line errors (``InputError``, by message), and
crashes (any other exception), each crash's file kept in the output folder.

Run: ``python benchmarks/fuzz_run_files.py [--seeds 0 1 2] [--trials 1000] [--keep DIR]``
"""

from __future__ import annotations

import argparse
import random
import tempfile
import traceback
from collections import Counter
from pathlib import Path

from whipple.errors import InputError
from whipple.measurement.measure import measure_runs
from whipple.measurement.runs import read_run
from whipple.model.parameters import load_bicycle
from whipple.simulation.procedure import cut_run
from whipple.simulation.run_writer import write_run_csv
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

#: Characters a corruption writes.
CHARACTERS = list(",;\t.-+eE0123456789 \"'#:nNaAiIfF/()[]°µ")


def corrupted(lines: list[str], rng: random.Random) -> list[str]:
    """Return a copy of a run file's lines corrupted 1-6 times."""
    lines = list(lines)
    for _ in range(rng.randint(1, 6)):
        if not lines:
            break
        i = rng.randrange(len(lines))
        kind = rng.randrange(8)
        if kind == 0 and lines[i]:
            j = rng.randrange(len(lines[i]))
            lines[i] = lines[i][:j] + rng.choice(CHARACTERS) + lines[i][j + 1:]
        elif kind == 1:
            del lines[i]
        elif kind == 2:
            lines.insert(i, lines[rng.randrange(len(lines))])
        elif kind == 3:
            lines[i] = lines[i][:rng.randrange(len(lines[i]) + 1)]
        elif kind == 4:
            lines.insert(i, "".join(rng.choice(CHARACTERS) for _ in range(rng.randint(0, 40))))
        elif kind == 5:
            lines[i] = lines[i].replace(",", rng.choice([",,", ";", "\t", ", "]), 1)
        elif kind == 6:
            lines = lines[:i]
        elif kind == 7:
            lines[i:i] = [lines[i]] * rng.randint(1, 3)
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--trials", type=int, default=1000, help="corrupted files per seed")
    parser.add_argument("--keep", type=Path, default=Path("fuzz_crashes"), help="folder for the files that crash")
    args = parser.parse_args()
    bicycle = load_bicycle("benchmark")
    with tempfile.TemporaryDirectory() as folder:
        plain = Path(folder) / "plain.csv"
        simulated = simulate_run(bicycle, RunScenario(speed=5.0, seed=3))
        write_run_csv(cut_run(simulated, 0.0, 7.0), plain)
        lines = plain.read_text(encoding="utf-8").splitlines()
        target = Path(folder) / "run.csv"
        for seed in args.seeds:
            rng = random.Random(seed)
            measured, crashes, errors = 0, 0, Counter[str]()
            for trial in range(args.trials):
                target.write_text("\n".join(corrupted(lines, rng)) + "\n", encoding="utf-8")
                try:
                    measure_runs([read_run(target)], bicycle=bicycle)
                    measured += 1
                except InputError as error:
                    errors[str(error).split(": ", 1)[-1][:40]] += 1
                except Exception:  # noqa: BLE001 - every other exception is what this looks for
                    crashes += 1
                    args.keep.mkdir(parents=True, exist_ok=True)
                    kept = args.keep / f"crash_seed{seed}_{trial}.csv"
                    kept.write_bytes(target.read_bytes())
                    print(f"crash (seed {seed}, trial {trial}, kept as {kept}): "
                          f"{traceback.format_exc().splitlines()[-1]}")
            common = ", ".join(f"{message!r} {count}" for message, count in errors.most_common(3))
            print(f"seed {seed}: {args.trials} files, {measured} measured, {sum(errors.values())} refused in one "
                  f"line (most often: {common}), {crashes} crashes", flush=True)


if __name__ == "__main__":
    main()
