"""Time of ``whipple diagnose`` on 40 simulated runs, and of its parts.

Simulates 40 runs (benchmark bicycle, 2-8 m/s, three pushes each) with a hidden effect, writes
them as run files, and times the whole command (measurement, diagnosis, held-out gain with the
cause chosen again per left-out speed, the nonlinear amplitude check, the report's figures).
The baseline measured in the same run is the held-out gain that only refits the cause chosen
on all speeds (the earlier, faster and leakier form); the ratio says what choosing again costs.

Run: ``python benchmarks/bench_diagnose_time.py [--effect two|load] [--compare C] [--workers N]``
(``two``: steer damping and a rear-frame roll inertia 40% high together, so that no single cause
fits and pairs are tried; ``load``: a 15 kg load over the rear rack, 0.1 m behind the rear axle
and 0.55 m above the ground, so that a payload with its position leads and pairs are tried too;
``--compare``: how models are compared with the windows (``whipple diagnose --compare``; by
default with their samples);
``--workers N``: the gain, and the whole command, also with ``--workers N``, the held-out
speeds diagnosed on a local Dask cluster, its start included).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from contextlib import redirect_stdout
from io import StringIO
from pathlib import Path

from whipple.cli import main as whipple_main
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.fitting import COMPARISONS
from whipple.diagnosis.gain import held_out_gain
from whipple.diagnosis.observations import observations
from whipple.diagnosis.options import DiagnosisOptions
from whipple.measurement.experiment import measure_run
from whipple.measurement.runs import read_run
from whipple.model.parameters import Payload, load_bicycle
from whipple.simulation.run_writer import write_run_csv
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

SPEEDS = (2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0)
#: The ``load`` effect: mass [kg], x and z of its mass centre [m] (z down, from the rear contact).
RACK_LOAD = (15.0, -0.1, -0.55)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=40)
    parser.add_argument("--effect", choices=("one", "two", "load"), default="one")
    parser.add_argument("--workers", type=int, default=None, metavar="N")
    parser.add_argument("--compare", choices=COMPARISONS, default="samples",
                        help="how models are compared with the windows (default: with their samples)")
    args = parser.parse_args()
    base = load_bicycle("benchmark")
    truth = base.with_extensions(steer_damping=0.8)
    if args.effect == "two":
        truth = truth.with_parameters(IBxx=1.4 * base.parameters["IBxx"])
    if args.effect == "load":
        truth = base.with_extensions(payload=Payload(*RACK_LOAD))
    with tempfile.TemporaryDirectory() as folder:
        files = []
        for k in range(args.runs):
            scenario = RunScenario(speed=SPEEDS[k % len(SPEEDS)], seed=1000 + k, n_pushes=3)
            files.append(write_run_csv(simulate_run(truth, scenario, name=f"run{k}"), Path(folder) / f"run{k}.csv"))
        started = time.perf_counter()
        measurements = [m for f in files for m in measure_run(read_run(f), baseline="auto")]
        measured = time.perf_counter()
        seen = observations(measurements)
        options = DiagnosisOptions(comparison=args.compare)
        diagnosis = diagnose_observations(base, seen, options=options)
        diagnosed = time.perf_counter()
        gain = held_out_gain(base, seen, options=options)
        chosen_again = time.perf_counter()
        if diagnosis.chosen is not None:
            held_out_gain(base, seen, fixed=diagnosis.chosen)
        refitted = time.perf_counter()
        if args.workers is not None:
            spread = held_out_gain(base, seen, workers=args.workers, options=options)
            assert spread == gain, "the folds on a cluster must give the serial gain"
            gain_on_workers = time.perf_counter() - refitted
        command_started = time.perf_counter()
        command = ["diagnose", *map(str, files), "--bicycle", "benchmark", "--json", str(Path(folder) / "d.json"),
                   "--report", str(Path(folder) / "report"), "--compare", args.compare]
        cpu = time.process_time()
        with redirect_stdout(StringIO()):
            whipple_main(command)
        finished, cpu = time.perf_counter(), time.process_time() - cpu
        if args.workers is not None:
            with redirect_stdout(StringIO()):
                whipple_main([*command, "--workers", str(args.workers)])
            parallel = time.perf_counter() - finished
    hidden = {"one": "steer damping 0.8", "two": "steer damping 0.8 + IBxx x1.4",
              "load": "payload {} kg at x = {} m, z = {} m".format(*RACK_LOAD)}[args.effect]
    print(f"{args.runs} runs, {len(seen)} windows; hidden: {hidden}")
    print(f"verdict {diagnosis.verdict} ({diagnosis.cause}); pairs tried: "
          + (", ".join(diagnosis.combinations) or "none"))
    print(f"held-out RMS {gain.base_rms:.3f} -> {gain.extended_rms:.3f} 1/s ({100 * gain.cut:.0f}% cut)")
    for speed in gain.speeds:
        print(f"  {speed.speed:.1f} m/s, {speed.windows} windows, {speed.cause}: RMS {speed.base_rms:.3f} -> "
              f"{speed.extended_rms:.3f}, median {speed.base_median:.3f} -> {speed.extended_median:.3f} 1/s")
    again, refit = chosen_again - diagnosed, refitted - chosen_again
    print(f"measure {measured - started:.1f} s, diagnose {diagnosed - measured:.1f} s, gain (choice redone) "
          f"{again:.1f} s, gain (refit only, baseline) {refit:.1f} s: ratio {again / max(refit, 1e-9):.1f}")
    whole = finished - command_started
    print(f"whipple diagnose (whole command, with report): {whole:.1f} s wall, {cpu:.1f} s CPU")
    if args.workers is not None:
        print(f"gain (choice redone) on a local cluster of {args.workers} workers, its start included: "
              f"{gain_on_workers:.1f} s (ratio {gain_on_workers / again:.2f}; same gain)")
        print(f"whole command with --workers {args.workers}: {parallel:.1f} s wall "
              f"(ratio {parallel / whole:.2f})")


if __name__ == "__main__":
    main()
