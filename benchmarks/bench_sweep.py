"""``whipple sweep`` end to end against the bare polynomial solve, throughput, and Dask, in one run.

Run:  python benchmarks/bench_sweep.py [--bicycles 50000] [--sizes 100000 1000000]
                                       [--dask-rows 1000000] [--workers 2] [--source DIR]

1. A table of random bicycles (the benchmark bicycle with 8 parameters varied by
   ``exp(0.1 N(0, 1))``) is swept by the ``whipple sweep`` command as a subprocess, process start, reading,
   validation, analysis and writing included, and compared with two floors measured in this
   process: (a) the bare batched NumPy solve of the Whipple polynomial conditions
   (``benchmarks/bare_solve.py``, companion eigenvalues only) given the bicycles' matrices, and
   (b) the same solve from the bicycles' parameters (the generated matrix function, then (a)),
   which starts where the sweep's analysis starts. The issue's target: the sweep within 10
   times the bare solve per bicycle. The sweep (7 runs) and the floors (21 and 7 runs) are
   timed in interleaved rounds; the ratios are printed best to best and median to median
   (the floor's time alone moves by about 40 % from call to call), with the fixed costs measured in
   the same run (Python and NumPy starting; ``whipple sweep`` of a one-row table) and the cost
   of each added row.
   The sweep runs once untimed first, with Python's bytecode cache allowed (an installed
   package has its modules compiled; without the cache every run compiles ~30 modules again).
2. Sweep throughput (rows/s) for each of ``--sizes`` rows.
3. The ``--dask-rows`` table swept again on a local Dask cluster (``--workers N``); the output
   must be the serial output byte for byte.

``--source DIR`` runs the sweeps with another checkout's code (``PYTHONPATH=DIR/src:DIR``), e.g.
a branch with another critical-speed solver; every line printed says which code ran.
"""

from __future__ import annotations

import argparse
import filecmp
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bare_solve import bare_critical_roots  # noqa: E402
from whipple.generated import whipple_numpy  # noqa: E402

from whipple.model.parameters import load_bicycle  # noqa: E402

#: Parameters varied in the random tables.
VARIED = ("w", "c", "lam", "mB", "xB", "zB", "mH", "IBxx")
#: Bicycles written per block when making a table.
BLOCK = 100_000
#: Interleaved rounds of the sweep and the bare solves.
ROUNDS = 7


def random_columns(count: int, seed: int) -> dict[str, np.ndarray]:
    base = load_bicycle("benchmark").parameters
    rng = np.random.default_rng(seed)
    return {name: base[name] * np.exp(0.1 * rng.standard_normal(count)) for name in VARIED}


def write_table(path: Path, count: int, seed: int = 1) -> None:
    """A table of `count` random bicycles, written a block at a time."""
    rng_seeds = np.random.SeedSequence(seed).spawn((count + BLOCK - 1) // BLOCK)
    with path.open("w") as handle:
        handle.write(",".join(VARIED) + "\n")
        for block, block_seed in enumerate(rng_seeds):
            rows = min(BLOCK, count - block * BLOCK)
            columns = random_columns(rows, int(block_seed.generate_state(1)[0]))
            values = np.stack([columns[name] for name in VARIED], axis=-1)
            handle.write("".join(",".join(map(repr, row)) + "\n" for row in values.tolist()))


def read_columns(path: Path) -> dict[str, np.ndarray]:
    values = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: values[:, k] for k, name in enumerate(VARIED)}


def parameter_arrays(columns: dict[str, np.ndarray]) -> list[np.ndarray]:
    """The generated matrix function's arguments: the table's columns, the benchmark's other values."""
    parameters = {**load_bicycle("benchmark").parameters, **columns}
    return [np.asarray(parameters[name], dtype=float) for name in whipple_numpy.PARAMETERS]


def matrices(arguments: list[np.ndarray]) -> tuple[np.ndarray, ...]:
    """M, C1, K0 and K2 of every bicycle, shape (N, 2, 2) each."""
    return whipple_numpy.matrices(*arguments)


def whipple_command() -> list[str]:
    """The installed ``whipple`` command beside this Python (``python -m whipple`` if there is none).

    The command is what users run; ``python -m whipple`` measured 15-20 ms more per process here
    (cause not pinned down), which would be charged to every row of the table.
    """
    script = Path(sys.executable).parent / "whipple"
    return [str(script)] if script.is_file() else [sys.executable, "-m", "whipple"]


def run_sweep(table: Path, output: Path, source: str | None, extra: tuple[str, ...] = ()) -> float:
    """Wall time [s] of ``whipple sweep`` as a subprocess (process start included)."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    if source:
        env["PYTHONPATH"] = f"{source}/src:{source}"
    start = time.perf_counter()
    subprocess.run([*whipple_command(), "sweep", str(table), "-o", str(output), "--quiet", *extra],
                   check=True, env=env, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bicycles", type=int, default=50_000)
    parser.add_argument("--sizes", type=int, nargs="*", default=[100_000, 1_000_000])
    parser.add_argument("--dask-rows", type=int, default=1_000_000, help="0: skip the Dask run")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--source", help="checkout whose code runs the sweeps (default: the installed whipple)")
    parser.add_argument("--folder", type=Path, help="keep the tables and outputs here (default: temporary)")
    args = parser.parse_args()
    code = f"code from {args.source}" if args.source else "code of this checkout"
    print(f"whipple sweep ({code}); {os.cpu_count()} cores, load average "
          + " ".join(f"{x:.1f}" for x in os.getloadavg()))
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.folder or Path(scratch)
        folder.mkdir(parents=True, exist_ok=True)

        table = folder / f"bicycles_{args.bicycles}.csv"
        write_table(table, args.bicycles)
        arguments = parameter_arrays(read_columns(table))
        M, C1, K0, K2 = matrices(arguments)
        run_sweep(table, folder / "out_small.csv", args.source)  # compiles and caches the modules
        # Interleaved, so that both sample the same states of the machine: the bare solve's time
        # alone moves by +/- 40% from call to call here (numpy.linalg.eigvals).
        sweeps, bares, from_parameters_times = [], [], []
        for _ in range(ROUNDS):
            sweeps.append(run_sweep(table, folder / "out_small.csv", args.source) / args.bicycles)
            bares += [_timed(lambda: bare_critical_roots(M, C1, K0, K2)) / args.bicycles for _ in range(3)]
            from_parameters_times.append(_timed(lambda: bare_critical_roots(*matrices(arguments))) / args.bicycles)
        sweep, bare, from_parameters = min(sweeps), min(bares), min(from_parameters_times)
        print(f"1. {args.bicycles} random bicycles: whipple sweep end to end {sweep * 1e6:8.2f} us per bicycle "
              f"(best of {ROUNDS}; median {statistics.median(sweeps) * 1e6:.2f})")
        print(f"   (a) bare polynomial solve from the matrices   {bare * 1e6:6.2f} us per bicycle (best of "
              f"{len(bares)}; median {statistics.median(bares) * 1e6:.2f}); ratio {sweep / bare:7.1f} best to best, "
              f"{statistics.median(sweeps) / statistics.median(bares):.1f} median to median (target <= 10)")
        print(f"   (b) bare polynomial solve from the parameters {from_parameters * 1e6:6.2f} us per bicycle; "
              f"ratio {sweep / from_parameters:7.1f} (target <= 10)")
        # The fixed costs in the same run: what no per-row work can remove.
        one_row = folder / "one_row.csv"
        one_row.write_text("".join(table.open().readlines()[:2]))
        fixed = min(run_sweep(one_row, folder / "out_one.csv", args.source) for _ in range(5))
        numpy_start = min(_timed_process([sys.executable, "-c", "import numpy"]) for _ in range(5))
        per_row = (sweep * args.bicycles - fixed) / (args.bicycles - 1)
        print(f"   fixed: Python + NumPy start {numpy_start:.3f} s, whipple sweep of one row {fixed:.3f} s "
              f"({fixed / args.bicycles * 1e6:.2f} us per bicycle here, ratio {fixed / args.bicycles / bare:.1f}"
              f" to (a)); per added row {per_row * 1e6:.2f} us (ratio {per_row / bare:.1f} to (a), "
              f"{per_row / from_parameters:.1f} to (b))")

        print("2. throughput")
        tables = {}
        for size in args.sizes:
            tables[size] = folder / f"bicycles_{size}.csv"
            write_table(tables[size], size, seed=2)
            elapsed = run_sweep(tables[size], folder / f"out_{size}.csv", args.source)
            print(f"   {size:>9} bicycles: {elapsed:7.1f} s, {size / elapsed:9.0f} rows/s ({code})")

        if args.dask_rows:
            size = args.dask_rows
            if size not in tables:
                tables[size] = folder / f"bicycles_{size}.csv"
                write_table(tables[size], size, seed=2)
                run_sweep(tables[size], folder / f"out_{size}.csv", args.source)
            on_cluster = folder / f"out_{size}_dask.csv"
            elapsed = run_sweep(tables[size], on_cluster, args.source, ("--workers", str(args.workers)))
            same = filecmp.cmp(folder / f"out_{size}.csv", on_cluster, shallow=False)
            print(f"3. {size} bicycles on a local Dask cluster of {args.workers} workers: {elapsed:7.1f} s, "
                  f"{size / elapsed:9.0f} rows/s; output identical to the serial run: {'yes' if same else 'NO'}")


def _timed_process(command: list[str]) -> float:
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return _timed(lambda: subprocess.run(command, check=True, env=env))


def _timed(function) -> float:  # type: ignore[no-untyped-def]
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


if __name__ == "__main__":
    main()
