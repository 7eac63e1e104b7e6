"""The diagnosis as one library pipeline: the command and the library do the same analysis.

``whipple.diagnose`` is what ``whipple diagnose`` runs: its report's ``to_dict()`` is the
command's ``--json``; ``whipple fit`` and ``whipple diagnose`` measure a window one way and
report the same eigenvalue for it; the options are one object that the report records; tuning
is never done by assigning another module's constants; ``whipple sweep`` loads neither the
measurement nor the diagnosis.
"""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

import whipple
from whipple.cli import main
from whipple.diagnosis.options import DiagnosisOptions, PairRules, VerdictRules
from whipple.errors import InputError
from whipple.measurement.bundled import bundled_runs
from whipple.measurement.measure import MeasurementOptions, measure_runs
from whipple.measurement.runs import read_run

ROOT = Path(__file__).resolve().parents[1]
#: Two bundled runs (9 and 16.2 km/h): enough windows for a diagnosis at two speeds, quick.
SUBSET = [entry for entry in bundled_runs() if "_9kph" in entry.name or "_16.2kph" in entry.name]


def _paths(entries) -> list[str]:
    return [str(entry) for entry in entries]


@pytest.fixture(scope="module")
def command_json(tmp_path_factory) -> dict:
    out = tmp_path_factory.mktemp("diagnose") / "d.json"
    assert main(["diagnose", *_paths(SUBSET), "--bicycle", "sbw2024", "--json", str(out)]) == 0
    return json.loads(out.read_text())


def test_the_library_call_is_the_command(command_json):
    report = whipple.diagnose(SUBSET, "sbw2024")
    data = json.loads(json.dumps(report.to_dict()))
    assert data == command_json
    assert data["options"] == DiagnosisOptions().to_dict()
    assert data["measurement"]["signals"] == ["roll_rate", "steer_angle"]


@pytest.mark.slow
def test_the_library_call_is_the_command_on_every_bundled_run(tmp_path):
    out = tmp_path / "d.json"
    assert main(["diagnose", "--bundled", "--bicycle", "sbw2024", "--json", str(out)]) == 0
    data = json.loads(json.dumps(whipple.diagnose(bundled_runs(), "sbw2024").to_dict()))
    assert data == json.loads(out.read_text())


def test_fit_and_diagnose_report_the_same_eigenvalue(command_json, tmp_path):
    out = tmp_path / "fit.json"
    assert main(["fit", *_paths(SUBSET), "--bicycle", "sbw2024", "--json", str(out)]) == 0
    fitted = {(w["run"], w["start"]): w for w in json.loads(out.read_text())}
    used = [w for w in fitted.values() if w["eigenvalue"] is not None and w["skipped"] is None and not w["quality"]]
    assert len(used) == len(command_json["windows"]) >= 10
    for window in command_json["windows"]:
        fit = fitted[(window["run"], window["start"])]
        measured, diagnosed = complex(*fit["eigenvalue"]), complex(*window["eigenvalue"])
        assert abs(measured - diagnosed) <= 1e-6 * abs(diagnosed)


def test_the_seed_papers_fit_is_an_explicit_choice_named_in_the_output(tmp_path, capsys):
    out = tmp_path / "fit.json"
    assert main(["fit", _paths(SUBSET)[0], "--method", "seed-paper", "--json", str(out)]) == 0
    assert "the seed paper's fit" in capsys.readouterr().out
    windows = [w for w in json.loads(out.read_text()) if w["eigenvalue"] is not None]
    assert windows and all(w["signals"] == ["roll_rate"] and w["baseline"] == "constant" for w in windows)
    assert main(["fit", _paths(SUBSET)[0], "--method", "seed-paper", "--signals", "roll_rate,steer_angle"]) == 2
    assert "seed-paper" in capsys.readouterr().err


# Slow (a whole diagnosis of the bundled runs): run with `pytest -m slow`.
@pytest.mark.slow
def test_measured_runs_given_to_diagnose_skip_the_measurement():
    runs = [read_run(entry) for entry in SUBSET]
    options = DiagnosisOptions(comparison="eigenvalues", held_out_gain=False, amplitude_check=False)
    measured = measure_runs(runs, options.measurement, bicycle=whipple.load_bicycle("sbw2024"))
    stages = []
    report = whipple.diagnose(measured, "sbw2024", options, progress=lambda *step: stages.append(step))
    again = whipple.diagnose(runs, "sbw2024", options)
    assert report.diagnosis.ranking() == again.diagnosis.ranking()
    assert report.options is options and report.gain is None and report.amplitude is None
    assert {stage for stage, _, _ in stages} == {"candidates"}
    counts = [(done, total) for stage, done, total in stages]
    assert counts[-1][0] == counts[-1][1] == len(options.candidates(report.bicycle))


def test_the_measurement_reports_progress_per_run():
    stages = []
    measure_runs([read_run(entry) for entry in SUBSET], progress=lambda *step: stages.append(step))
    assert stages == [("runs", 1, 2), ("runs", 2, 2)]


@pytest.mark.parametrize("build, match", [
    (lambda: DiagnosisOptions(comparison="samplez"), "comparison must be one of"),
    (lambda: DiagnosisOptions(occam="aic"), "occam must be one of"),
    (lambda: DiagnosisOptions(verdict=VerdictRules(margin=float("nan"))), "margin"),
    (lambda: DiagnosisOptions(pairs=PairRules(leading=-1)), "leading"),
    (lambda: DiagnosisOptions(speed_range=(5.0, 1.0)), "speed_range"),
    (lambda: MeasurementOptions(signals="roll_rate"), "signals must be 'auto' or a tuple"),
    (lambda: MeasurementOptions(baseline="cubic"), "unknown baseline"),
    (lambda: MeasurementOptions(catch_passes=99), "catch passes"),
])
def test_bad_options_are_one_line_input_errors(build, match):
    with pytest.raises(InputError, match=match):
        build()


def test_an_unknown_option_is_an_error():
    with pytest.raises(TypeError):
        DiagnosisOptions(margin=3.0)  # type: ignore[call-arg]


def test_diagnose_refuses_a_mixture_and_nothing():
    measured = measure_runs([read_run(SUBSET[0])])
    with pytest.raises(InputError, match="not a mixture"):
        whipple.diagnose([*measured.windows[:1], SUBSET[1]], "sbw2024")
    with pytest.raises(InputError, match="no runs"):
        whipple.diagnose([], "sbw2024")


def _constant_assignments(path: Path) -> list[str]:
    """``module.NAME = ...`` and ``setattr(module, "NAME", ...)`` in a file (NAME in capitals)."""
    found = []
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(
            node, ast.AugAssign | ast.AnnAssign) else []
        for target in targets:
            if (isinstance(target, ast.Attribute) and target.attr.isupper() and len(target.attr) > 2
                    and not (isinstance(target.value, ast.Name) and target.value.id in ("self", "cls"))):
                found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {ast.unparse(target)} = ...")
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute | ast.Name)
                and (node.func.attr if isinstance(node.func, ast.Attribute) else node.func.id) == "setattr"
                and len(node.args) >= 2 and isinstance(node.args[1], ast.Constant)
                and isinstance(node.args[1].value, str) and node.args[1].value.isupper()):
            found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {ast.unparse(node)}")
    return found


def test_no_code_changes_behaviour_by_assigning_another_modules_constants():
    files = [path for folder in ("src", "tests", "benchmarks", "docs") for path in (ROOT / folder).rglob("*.py")]
    assert len(files) > 100
    problems = [line for path in files for line in _constant_assignments(path)]
    assert not problems, "\n".join(problems)


def test_the_constant_assignment_check_finds_what_it_looks_for(tmp_path):
    sample = ROOT / "tests" / "_sample_assignments.py"
    try:
        sample.write_text("import x\nx.MARGIN = 3\nmonkeypatch.setattr(x, 'OCCAM', 1)\nself.LIMIT = 2\n")
        assert len(_constant_assignments(sample)) == 2
    finally:
        sample.unlink()


def test_sweep_loads_neither_the_measurement_nor_the_diagnosis(tmp_path):
    table, out = tmp_path / "table.csv", tmp_path / "out.csv"
    table.write_text("c,mB\n0.08,85\n0.1,90\n")
    script = (
        "import sys\n"
        "from whipple.cli import main\n"
        f"status = main(['sweep', {str(table)!r}, '-o', {str(out)!r}, '--quiet'])\n"
        "loaded = [m for m in sys.modules if m.startswith(('whipple.measurement', 'whipple.diagnosis', "
        "'scipy.optimize'))]\n"
        "print(status, loaded)\n")
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    assert result.stdout.strip().splitlines()[-1] == "0 []", result.stdout + result.stderr
    assert len(out.read_text().splitlines()) == 3  # the header and a row per parameter set
