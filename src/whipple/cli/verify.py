"""Evaluate the generated CasADi code at the published parameter sets and compare.

For each published set (the Meijaard et al. 2007 benchmark and the seed paper's instrumented
bicycle) every entry of M, C1, K0 (with gravity) and K2 is listed with its published value,
the computed value and the error, against the tolerance the printed digits allow. The NumPy
code is cross-checked against the CasADi code. Exit status 0 only if everything passes.
"""

from __future__ import annotations

import argparse
import json

from whipple.model.verification import reference_sets, verify


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    parser.add_argument("--json", action="store_true", help="print the results as JSON")


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    results = [verify(reference) for reference in reference_sets()]
    if args.json:
        print(json.dumps({"passed": all(r.passed for r in results),
                          "references": [r.to_dict() for r in results]}, indent=2))
    else:
        for result in results:
            reference = result.reference
            print(f"{reference.name}: {reference.citation}")
            print(f"  tolerance {reference.tolerance:.1e} ({reference.tolerance_reason})")
            print(f"  {'entry':<9}{'published':>22}{'computed':>22}{'error':>10}  ok")
            for entry in result.entries:
                label = f"{entry.matrix}[{entry.row},{entry.column}]"
                print(f"  {label:<9}{entry.published:>22.15g}{entry.computed:>22.15g}"
                      f"{entry.error:>10.1e}  {'yes' if entry.passed else 'NO'}")
            print(f"  NumPy vs CasADi: max difference {result.numpy_casadi_difference:.1e}")
            print(f"  {'PASS' if result.passed else 'FAIL'}")
        print("all references pass" if all(r.passed for r in results) else "verification FAILED")
    return 0 if all(result.passed for result in results) else 1
