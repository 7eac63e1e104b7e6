"""whipple: the Whipple bicycle, derived, checked and confronted with data.

The main entry points are available from the top level; each lives in the sub-package of its
concept (see docs/architecture.md)::

    model        parameters, bicycle files, linear models, the generated code
    stability    eigenvalues and modes over speed, critical speeds, sweeps
    simulation   synthetic measured runs
    measurement  run files, free-coasting windows, weave fits
    diagnosis    causes, evidence, the report

Examples
--------
>>> import whipple
>>> bicycle = whipple.load_bicycle("benchmark")
>>> critical = whipple.critical_speeds(whipple.linear_model(bicycle))
>>> round(critical.weave_speed, 6), round(critical.capsize_speed, 6)
(4.292383, 6.024262)

Names are imported on first use, so that ``import whipple`` stays cheap.
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

#: Public names by the module that defines them.
_EXPORTS: dict[str, tuple[str, ...]] = {
    "whipple.errors": ("WhippleError", "InputError", "ParameterError", "BicycleFileError", "RunFileError",
                       "ExperimentFileError", "AnalysisError"),
    "whipple.model.parameters": ("Bicycle", "Controller", "Extensions", "Payload", "Rider", "TyreCompliance",
                                 "ValidationReport", "PARAMETER_NAMES", "PARAMETER_DESCRIPTIONS", "PARAMETER_UNITS",
                                 "builtin_names", "check_physical", "load_bicycle", "read_benchmark_txt",
                                 "read_bicycle_toml", "read_rider_txt", "add_rider", "validate", "write_bicycle_toml"),
    "whipple.model.linear": ("LinearModel", "second_order_model"),
    "whipple.model.assembly": ("Matrices", "build_linear_model", "extended_matrices", "linear_model",
                               "whipple_matrices"),
    "whipple.model.verification": ("reference_sets", "verify"),
    "whipple.stability.eigen": ("EigenResult", "eigen_analysis", "eigenvalue_table", "weave_eigenvalue"),
    "whipple.stability.critical": ("Crossing", "CriticalSpeeds", "critical_speeds", "critical_speeds_batch",
                                   "critical_speed_table"),
    "whipple.stability.uncertainty": ("critical_speed_uncertainty",),
    "whipple.stability.report": ("analyse_bicycle",),
    "whipple.stability.sweep": ("read_parameter_table", "sweep"),
    "whipple.simulation.scenario": ("RunScenario", "Push", "Sensor", "Sensors"),
    "whipple.simulation.simulator": ("SimulatedRun", "simulate_run", "write_run_csv"),
    "whipple.measurement.runs": ("Run", "check_distinct_names", "read_run", "run_from_simulation"),
    "whipple.measurement.window_search": ("Window",),
    "whipple.measurement.windows": ("find_windows",),
    "whipple.measurement.weavefit": ("WeaveFit", "fit_weave", "fit_window"),
    "whipple.measurement.experiment": ("FitOptions", "RunMeasurement", "WindowMeasurement", "measure_run"),
    "whipple.measurement.measure": ("MeasurementOptions", "MeasuredRuns", "measure_runs"),
    "whipple.measurement.reference_windows": ("compare_windows", "read_windows", "write_windows"),
    "whipple.measurement.bundled": ("bundled_runs", "bundled_reference_windows", "bundled_experiment"),
    "whipple.measurement.experiment_file": ("Experiment", "Group", "read_experiment"),
    "whipple.diagnosis.observations": ("Observation", "observations"),
    "whipple.diagnosis.causes": ("Cause",),
    "whipple.diagnosis.registry": ("CauseDeclaration", "Family", "Value", "candidate_causes", "declare"),
    "whipple.diagnosis.options": ("DiagnosisOptions", "PairRules", "VerdictRules"),
    "whipple.diagnosis.pipeline": ("diagnose",),
    "whipple.diagnosis.evidence": ("Diagnosis", "diagnose_observations"),
    "whipple.diagnosis.gain": ("CauseGain", "Gain", "cause_gains", "held_out_gain"),
    "whipple.diagnosis.evaluation": ("Evaluation", "evaluate", "evaluate_experiment"),
    "whipple.diagnosis.report": ("DiagnosisReport", "assemble", "report_json"),
}
_HOME = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = ["__version__", *_HOME]


def __getattr__(name: str) -> Any:
    """Import a public name from its home module on first use."""
    if name not in _HOME:
        raise AttributeError(f"module 'whipple' has no attribute {name!r}")
    value = getattr(importlib.import_module(_HOME[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *_HOME])
