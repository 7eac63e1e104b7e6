"""Compare two hidden-effect logs trial by trial (same seeds): what a change of the diagnosis did.

Run: ``python benchmarks/compare_logs.py BEFORE.jsonl AFTER.jsonl [--merged OUT.jsonl]``. Both
logs are read under the current verdict rules (``bench_diagnosis._reclassified``); only trials
present in both are compared. Prints the outcome counts of each log per family and every trial
whose verdict, cause or outcome changed. ``--merged`` writes BEFORE with AFTER's trials in
place of its own (AFTER a rerun of only the trials a change touched); ``--twins LOG ...`` then
gives each merged trial the outcome of its noise-free twin (ninth column) from these ``--twin``
logs (a later log's in place of an earlier's), where that log's own outcome of the trial is the
merged one: a twin diagnosed beside another outcome says nothing about this one.
``--replace-from LOG ...`` reads BEFORE with the trials of these logs in place of its own (the
rates of record are a log with reruns, as in ``bench_diagnosis.py --replace-from``).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_diagnosis import _reclassified  # noqa: E402


def _read(path: Path) -> dict[tuple, tuple]:
    rows = (_reclassified(tuple(json.loads(line))) for line in path.read_text().splitlines() if line.strip())
    return {tuple(row[:3]): row for row in rows}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--replace-from", type=Path, nargs="+", default=[],
                        help="read BEFORE with each of its trials found in these logs in its place (a later "
                             "log's over an earlier's), as bench_diagnosis.py --replace-from")
    parser.add_argument("--merged", type=Path, help="write BEFORE with AFTER's trials replacing its own")
    parser.add_argument("--twins", type=Path, nargs="+", default=[],
                        help="with --merged: take each trial's twin outcome from these --twin logs where they agree")
    args = parser.parse_args()
    before, after = _read(args.before), _read(args.after)
    for path in args.replace_from:
        before.update({key: row for key, row in _read(path).items() if key in before})
    common = sorted(set(before) & set(after))
    print(f"{len(common)} trials in both logs")
    families = list(dict.fromkeys(key[1] for key in common))
    print(f"{'family':<18}{'trials':>7}  outcomes before -> after")
    for family in families:
        keys = [key for key in common if key[1] == family]
        old = Counter(before[key][5] for key in keys)
        new = Counter(after[key][5] for key in keys)
        print(f"{family:<18}{len(keys):>7}  {dict(old)} -> {dict(new)}")
    total_old = Counter(before[key][5] for key in common)
    total_new = Counter(after[key][5] for key in common)
    print(f"{'all':<18}{len(common):>7}  {dict(total_old)} -> {dict(total_new)}")
    print("\nchanged trials (bicycle, family, seed): verdict cause outcome, before -> after")
    for key in common:
        old, new = before[key], after[key]
        if old[3:6] != new[3:6]:
            print(f"  {key}: {old[3]} {old[4]} {old[5]} -> {new[3]} {new[4]} {new[5]}")
    if args.merged is not None:
        merged = {**before, **after}
        for path in args.twins:
            for key, twin in _read(path).items():
                if key in merged and len(twin) > 8 and twin[5] == merged[key][5]:
                    merged[key] = (*merged[key][:8], twin[8])
        keys = list(before) + [key for key in after if key not in before]
        args.merged.write_text("".join(json.dumps(merged[key]) + "\n" for key in keys))
        print(f"\n{len(keys)} trials written to {args.merged}")


if __name__ == "__main__":
    main()
