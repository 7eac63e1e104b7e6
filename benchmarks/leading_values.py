"""The leading cause's values in hidden-effect trials: how many the data determine.

For each trial listed (JSON lines ``[bicycle, family, seed]``, as ``bench_diagnosis.py
--trials`` takes them), diagnose it as ``bench_diagnosis.py`` does and write one JSON line: the
trial, the verdict, the leading cause, the outcome, and the leader's values with their
standard deviations (the jackknife's over speed groups included), physical bounds and whether
the data determine each (:func:`whipple.diagnosis.estimate_text.estimates`, as the report gives them).
Then it prints, for the trials led by a load (a value named ``..._mass``), how often the mass,
and any of the load's values, is not determined.

Run: ``python benchmarks/leading_values.py TRIALS.jsonl --log OUT.jsonl [--conditions C]
[--size-scale S] [--workers 2]`` (``--summary OUT.jsonl`` prints the counts of a log again).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from hidden_effects import CONDITIONS, field_conditions, measurement_options, run_trial  # noqa: E402

from whipple.diagnosis.estimate_text import estimates  # noqa: E402
from whipple.diagnosis.options import DiagnosisOptions  # noqa: E402
from whipple.distributed import map_ordered  # noqa: E402
from whipple.errors import InputError  # noqa: E402


def _leading_values(arguments: tuple) -> dict:
    bicycle, family, seed, scale, conditions = arguments
    trial_name = [bicycle, family, seed]
    try:
        trial = run_trial(family, seed, bicycle, scale=scale, conditions=conditions,
                          options=DiagnosisOptions(measurement=measurement_options("auto")))
    except InputError as error:
        return {"trial": trial_name, "error": error.problem}
    diagnosis = trial.diagnosis
    row: dict = {"trial": trial_name, "verdict": diagnosis.verdict, "cause": diagnosis.cause,
                 "outcome": trial.outcome}
    values = estimates(diagnosis)
    if values:
        row["values"] = [{"name": name, **{key: estimate[key] for key in ("value", "std", "bounds", "determined")}}
                         for name, estimate in values.items()]
    return row


def _summary(rows: list[dict]) -> str:
    loads = [r for r in rows if r.get("values") and r["values"][0]["name"].endswith("_mass")]
    mass = sum(not r["values"][0]["determined"] for r in loads)
    any_value = sum(not all(v["determined"] for v in r["values"]) for r in loads)
    return (f"{len(rows)} trials, {len(loads)} led by a load: its mass not determined in {mass}, some value of it "
            f"not determined in {any_value}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trials", type=Path, nargs="?", help="JSON lines [bicycle, family, seed]")
    parser.add_argument("--log", type=Path, help="append each trial's line to this JSON-lines file")
    parser.add_argument("--summary", type=Path, help="print the counts of this log instead of running trials")
    parser.add_argument("--conditions", choices=sorted(CONDITIONS), default="treadmill")
    parser.add_argument("--size-scale", type=float, default=1.0, help="multiply the hidden effect's size by this")
    parser.add_argument("--workers", type=int, default=2, help="local Dask worker processes")
    args = parser.parse_args()
    if args.summary is not None:
        print(_summary([json.loads(line) for line in args.summary.read_text().splitlines() if line.strip()]))
        return
    if args.trials is None or args.log is None:
        parser.error("give a trials file and --log (or --summary LOG)")
    conditions = field_conditions(args.conditions)
    jobs = [(*json.loads(line), args.size_scale, conditions)
            for line in args.trials.read_text().splitlines() if line.strip()]
    rows = []
    with map_ordered(_leading_values, jobs, workers=args.workers) as results, args.log.open("a") as log:
        for row in results:
            rows.append(row)
            log.write(json.dumps(row) + "\n")
            log.flush()
    print(_summary(rows))


if __name__ == "__main__":
    main()
