"""Evaluate the generated CasADi code at the published parameter sets and compare.

For each published set (the Meijaard et al. 2007 benchmark and the seed paper's instrumented
bicycle) every entry of M, C1, K0 (with gravity) and K2 is listed with its published value,
the computed value and the error, against the tolerance the printed digits allow. The NumPy
code is cross-checked against the CasADi code. The nonlinear equations are checked against
Basu-Mandal et al. (2007), Table 1, and their Jacobian against the linear matrices
(whipple.model.nonlinear_verification). Exit status 0 only if everything passes.
"""

from __future__ import annotations

import argparse
import json

from whipple.model.nonlinear_verification import nonlinear_report
from whipple.model.verification import reference_sets, verify


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    parser.add_argument("--json", action="store_true", help="print the results as JSON")


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    results = [verify(reference) for reference in reference_sets()]
    nonlinear = nonlinear_report()
    passed = all(r.passed for r in results) and nonlinear["passed"]
    if args.json:
        print(json.dumps({"passed": passed, "references": [r.to_dict() for r in results],
                          "nonlinear": nonlinear}, indent=2))
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
        print(f"nonlinear: {nonlinear['basu_mandal']['citation']}: accelerations max error "
              f"{nonlinear['max_abs_error']:.1e}; Jacobian vs M, C1, K0, K2 max error "
              f"{nonlinear['linearization_max_error']:.1e}  {'PASS' if nonlinear['passed'] else 'FAIL'}")
        print("all references pass" if passed else "verification FAILED")
    return 0 if passed else 1
