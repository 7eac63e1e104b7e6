"""Scoring models on measured runs (whipple evaluate) and the held-out gain scored the same way."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from synthetic_windows import synthetic_observations

from whipple.cli import main
from whipple.diagnosis.causes import with_cause
from whipple.diagnosis.evaluation import evaluate, evaluate_experiment
from whipple.diagnosis.gain import held_out_gain
from whipple.diagnosis.observations import observations, predicted_weave, speed_groups
from whipple.diagnosis.registry import cause_by_name
from whipple.diagnosis.samples import SampleComparison
from whipple.errors import InputError
from whipple.measurement.experiment_file import read_experiment, read_group_models
from whipple.measurement.measure import measure_runs
from whipple.measurement.runs import read_run
from whipple.model.parameters import Controller, load_bicycle, write_bicycle_toml
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run, write_run_csv

SPEEDS = np.repeat([3.5, 4.5, 5.5, 6.5], 4)


@pytest.mark.parametrize("choose", ["fixed", "evidence"])
def test_the_held_out_gain_is_what_evaluate_gives_on_the_left_out_speeds(choose):
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name) for name in ("steer_damping", "speed_scale", "parameter:IFyy")]
    windows = synthetic_observations(bicycle.with_extensions(steer_damping=0.6), 3, SPEEDS)
    gain = (held_out_gain(bicycle, windows, fixed=causes[0]) if choose == "fixed"
            else held_out_gain(bicycle, windows, causes))
    by_speed = {round(s.speed, 9): s for s in gain.speeds}
    assert len(by_speed) == 4
    for group in speed_groups(windows):
        held = [windows[i] for i in group]
        speed = by_speed[round(float(np.mean([o.speed for o in held])), 9)]
        extended = with_cause(bicycle, cause_by_name(bicycle, speed.cause), speed.values)
        result = evaluate(held, {"base": bicycle, "extended": extended}, samples=False)
        (group_result,) = result.groups
        base, ext = (scores.overall for scores in group_result.scores)
        assert (base.rms, base.median, ext.rms, ext.median) == (
            speed.base_rms, speed.base_median, speed.extended_rms, speed.extended_median)
        assert base.windows == ext.windows == speed.windows == 4
        assert ext.rms < 0.5 * base.rms  # the hidden damping, refitted without this speed, predicts it
    # The overall figures: every held-out window of the base model.
    whole = evaluate(windows, {"base": bicycle}, samples=False)
    assert whole.overall[0].rms == pytest.approx(gain.base_rms, rel=1e-12)
    assert whole.overall[0].median == pytest.approx(gain.base, rel=1e-12)


@pytest.fixture(scope="module")
def damped(tmp_path_factory):
    """Runs of the benchmark with hidden steer damping 0.8 N m s/rad at 5 and 6 m/s, and the truth's file."""
    folder = tmp_path_factory.mktemp("evaluate")
    truth = load_bicycle("benchmark").with_extensions(steer_damping=0.8)
    paths = [write_run_csv(simulate_run(truth, RunScenario(speed=speed, seed=11 + k), name=f"run{k}"),
                           folder / f"run{k}.csv") for k, speed in enumerate((5.0, 6.0))]
    write_bicycle_toml(truth, folder / "truth.toml")
    measured = measure_runs([read_run(path) for path in paths], bicycle=load_bicycle("benchmark"))
    return folder, paths, truth, measured


def test_the_true_model_leaves_the_noise_and_the_base_model_does_not(damped):
    _, _, truth, measured = damped
    base = load_bicycle("benchmark")
    result = evaluate(measured, {"benchmark": base, "truth": truth})
    assert result.models == ("benchmark", "truth") and result.measurement == measured.options.to_dict()
    (group,) = result.groups
    assert group.name is None and group.runs == ("run0", "run1")
    windows = observations(measured.windows)
    assert group.windows == len(windows) >= 4
    base_scores, truth_scores = group.scores
    assert [round(s.speed) for s in truth_scores.speeds] == [5, 6]
    assert sum(s.windows for s in truth_scores.speeds) == truth_scores.overall.windows
    # Independent figures: each window's error from the model's nearest mode, and every sample's residual.
    for model, scores in ((base, base_scores), (truth, truth_scores)):
        errors = np.abs(np.array([o.eigenvalue for o in windows]) - predicted_weave(model, windows))
        assert scores.overall.rms == pytest.approx(np.sqrt(np.mean(errors**2)), rel=1e-12)
        assert scores.overall.median == pytest.approx(np.median(errors), rel=1e-12)
        assert scores.overall.chi2_per_sample == pytest.approx(
            SampleComparison.of(windows).chi2_per_sample(model), rel=1e-9)
    assert 0.8 < truth_scores.overall.chi2_per_sample < 1.3 and truth_scores.overall.rms < 0.15
    assert base_scores.overall.chi2_per_sample > 5 and base_scores.overall.rms > 0.5
    assert result.overall == (base_scores.overall, truth_scores.overall)
    assert [row["scope"] for row in result.rows()] == ["speed"] * 4 + ["group"] * 2
    without = evaluate(measured, {"truth": truth}, samples=False)
    assert without.overall[0].chi2_per_sample is None and without.overall[0].rms == truth_scores.overall.rms
    with pytest.raises(InputError, match="no models"):
        evaluate(measured, {})
    with pytest.raises(InputError, match="gives a bicycle per group"):
        evaluate(measured, {"truth": {"g": truth}})


def test_evaluate_command_prints_and_writes_what_the_library_gives(damped, tmp_path, capsys):
    folder, paths, truth, measured = damped
    out, table = tmp_path / "e.json", tmp_path / "e.csv"
    args = ["evaluate", *map(str, paths), "--bicycle", "benchmark", "--bicycle", str(folder / "truth.toml"),
            "--json", str(out), "--csv", str(table)]
    capsys.readouterr()
    assert main(args) == 0
    printed = capsys.readouterr().out
    expected = evaluate(measured, {"benchmark": load_bicycle("benchmark"), str(folder / "truth.toml"): truth})
    assert json.loads(out.read_text()) == json.loads(json.dumps(expected.to_dict()))
    rows = list(csv.DictReader(table.open()))
    assert len(rows) == len(expected.rows()) == 6 and rows[-1]["scope"] == "group"
    assert float(rows[-1]["rms"]) == pytest.approx(expected.overall[1].rms, rel=1e-3)
    assert "measured against benchmark" in printed and "2 runs" in printed
    last = printed.splitlines()[-4]  # the truth over all windows
    assert last.split()[:3] == ["all", str(expected.overall[1].windows), str(folder / "truth.toml")]


def test_an_experiment_of_two_controllers_is_scored_per_group(tmp_path, capsys):
    # One bicycle with hidden steer damping, measured without and with a steer-into-lean controller.
    plain = load_bicycle("benchmark")
    controlled = plain.with_controller(Controller(steer={"roll_rate": (2.0,)}))
    truths = {"off": plain.with_extensions(steer_damping=0.8), "on": controlled.with_extensions(steer_damping=0.8)}
    (tmp_path / "runs").mkdir()
    (tmp_path / "truth").mkdir()
    for k, (name, truth) in enumerate(truths.items()):
        run = simulate_run(truth, RunScenario(speed=5.5, seed=20 + k), name=f"{name}_run")
        write_run_csv(run, tmp_path / "runs" / f"{name}_run.csv")
        write_bicycle_toml(truth, tmp_path / "truth" / f"{name}.toml")
    write_bicycle_toml(controlled, tmp_path / "controlled.toml")
    experiment_file = tmp_path / "exp.toml"
    experiment_file.write_text('[[group]]\nname = "off"\nbicycle = "benchmark"\nruns = "runs/off_*.csv"\n'
                               '[[group]]\nname = "on"\nbicycle = "controlled.toml"\nruns = ["runs/on_*.csv"]\n',
                               encoding="utf-8")
    experiment = read_experiment(experiment_file)
    models = {"experiment": experiment.bicycles(), "truth": read_group_models(tmp_path / "truth", experiment)}
    result = evaluate_experiment(experiment, models)
    assert [g.name for g in result.groups] == ["off", "on"] and result.models == ("experiment", "truth")
    for group in result.groups:
        base, truth = group.scores
        assert truth.overall.rms < 0.5 * base.overall.rms, group.name
        assert truth.overall.chi2_per_sample < base.overall.chi2_per_sample
    total = sum(g.windows for g in result.groups)
    assert result.overall[1].windows == total
    assert [row["scope"] for row in result.rows()][-2:] == ["all", "all"]
    # The command gives the same figures.
    out = tmp_path / "e.json"
    capsys.readouterr()
    assert main(["evaluate", "--experiment", str(experiment_file), "--models", str(tmp_path / "truth"),
                 "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["models"] == ["experiment", str(tmp_path / "truth")]
    assert [g["name"] for g in data["groups"]] == ["off", "on"]
    assert data["overall"][str(tmp_path / "truth")]["windows"] == total
    assert data["overall"][str(tmp_path / "truth")]["rms"] == pytest.approx(result.overall[1].rms, rel=1e-12)
    printed = capsys.readouterr().out
    assert "groups off, on; each measured against its own bicycle" in printed
    assert any(line.split()[:2] == ["all", "all"] for line in printed.splitlines())


def test_a_models_folder_needs_a_file_per_group(tmp_path):
    experiment = read_experiment("bundled")
    (tmp_path / "mm_off.toml").write_text(Path(load_bicycle("sbw2024").source).name, encoding="utf-8")
    with pytest.raises(InputError, match="mm_off.toml"):
        read_group_models(tmp_path, experiment)  # not a bicycle file
    write_bicycle_toml(load_bicycle("sbw2024"), tmp_path / "mm_off.toml")
    with pytest.raises(InputError, match="mm_on.toml: no model for group 'mm_on'"):
        read_group_models(tmp_path, experiment)
    write_bicycle_toml(load_bicycle("sbw2024-mm"), tmp_path / "mm_on.toml")
    assert read_group_models(tmp_path, experiment) == experiment.bicycles()
    with pytest.raises(InputError, match="no such folder"):
        read_group_models(tmp_path / "none", experiment)


@pytest.mark.slow
def test_the_model_matching_controller_fits_the_model_matching_runs(tmp_path, capsys):
    # Real data: both bundled experiments measured on their own bicycles. On the model-matching-on
    # runs the bicycle with the firmware's state feedback predicts the weave better at every speed
    # with windows from 2.5 m/s up than the same bicycle with the steer-into-lean law alone.
    out = tmp_path / "e.json"
    assert main(["evaluate", "--bundled", "model-matching-on", "--bicycle", "sbw2024-mm", "--bicycle", "sbw2024",
                 "--no-samples", "--json", str(out)]) == 0
    (group,) = json.loads(out.read_text())["groups"]
    assert group["windows"] >= 30 and len(group["runs"]) == 5
    matching, plain = (group["models"][name]["speeds"] for name in ("sbw2024-mm", "sbw2024"))
    faster = [(m, p) for m, p in zip(matching, plain, strict=True) if m["speed"] > 2.0]
    assert len(faster) == 4
    assert all(m["rms"] < p["rms"] for m, p in faster)
    capsys.readouterr()
    out = tmp_path / "fit.json"
    assert main(["fit", "--bundled", "model-matching-on", "--bicycle", "sbw2024-mm", "--json", str(out)]) == 0
    printed = capsys.readouterr().out
    matched = next(line for line in printed.splitlines() if line.startswith("automatic windows vs"))
    found, total = (int(word) for word in matched.split(": ")[1].split(" matched")[0].split(" of "))
    assert total == 33 and found >= 30  # the hand-picked windows of these runs, in the shared reference file
