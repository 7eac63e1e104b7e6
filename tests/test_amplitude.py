"""Linearity at the measured amplitude: the nonlinear weave against the linear one, window by window.

Independent references: the linear eigenvalue (at vanishing amplitude the nonlinear weave must
reproduce it), the amplitude scaling of a smooth nonlinearity (the first correction to an
eigenvalue is of second order in the amplitude, the motion being odd in it), the diagnosis'
own prediction of the linear eigenvalue compared with each window.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from whipple.cli import main
from whipple.diagnosis.amplitude import FLAG_DEFINITION, AmplitudeCheck, AmplitudeReport, check_amplitudes
from whipple.diagnosis.observations import Prediction, observations
from whipple.measurement.bundled import bundled_runs
from whipple.measurement.experiment import FitOptions, measure_run
from whipple.measurement.runs import read_run, run_from_simulation
from whipple.model.parameters import Payload, load_bicycle
from whipple.simulation.scenario import PERFECT_SENSORS, RunScenario
from whipple.simulation.simulator import simulate_run, write_run_csv


def _first_window(bicycle, speed: float, push: float, settle: float):
    scenario = RunScenario(speed=speed, n_pushes=1, push_roll_rate=push, hold_std=0.0, sensors=PERFECT_SENSORS)
    run = run_from_simulation(simulate_run(bicycle, scenario))
    return [m for m in measure_run(run, settle=settle, baseline="quadratic") if m.usable][:1]


@pytest.mark.parametrize("name, speed, settle", [("benchmark", 6.0, 0.5), ("sbw2024", 5.0, 0.8)])
def test_difference_vanishes_with_the_square_of_the_amplitude(name, speed, settle):
    bicycle = load_bicycle(name)
    tiny, small, large = (check_amplitudes(bicycle, _first_window(bicycle, speed, push, settle)).checks[0]
                          for push in (0.01, 0.03, 0.3))
    assert tiny.amplitude < 0.01 and large.amplitude == pytest.approx(10 * small.amplitude, rel=0.02)
    # The nonlinear weave reproduces the linear eigenvalue at small amplitude...
    assert abs(tiny.difference) < 1e-5
    # ...and departs from it as the amplitude squared (a second-order effect), not as noise would
    # (the integration, at rtol 1e-10, leaves a floor far below these differences).
    ratio = abs(large.difference) / abs(small.difference)
    assert ratio == pytest.approx((large.amplitude / small.amplitude) ** 2, rel=0.1)


def test_linear_eigenvalue_is_the_one_the_diagnosis_compares_with():
    bicycle = load_bicycle("sbw2024")
    used = [m for m in measure_run(read_run(bundled_runs()[3]), options=FitOptions(baseline="auto")) if m.usable]
    report = check_amplitudes(bicycle, used)
    predicted = Prediction.of(bicycle, observations(used)).eigenvalues
    np.testing.assert_allclose([c.linear for c in report.checks], predicted, rtol=1e-12)
    # At 4.7 m/s, 0.16-1.17 rad/s of roll rate: within 1 % of the eigenvalue, growing with the amplitude.
    relative = np.array([c.relative for c in report.checks])
    amplitude = np.array([c.amplitude for c in report.checks])
    assert relative.max() < 0.01
    # Only a large swing's departure can exceed what its window resolves: the window at 60.68 s,
    # cut before its residual leaves the noise, resolves 0.02 1/s and departs by 0.03 1/s at
    # 0.86 rad/s.
    assert report.flagged <= 1 and all(c.amplitude > 0.75 for c in report.checks if c.flagged)
    assert np.corrcoef(amplitude**2, relative)[0, 1] > 0.9
    assert all(c.nonlinear.real < c.linear.real for c in report.checks if c.amplitude > 0.5)


def test_flag_and_summary_from_the_checks():
    def check(speed, difference, std, fitted=True):
        linear = complex(-2.0, 9.0)
        nonlinear = linear + difference if fitted else complex(np.nan, np.nan)
        flagged = (not fitted) or abs(difference.real) > std or abs(difference.imag) > std
        return AmplitudeCheck("run", 0.0, 1.0, speed, 0.5, 0.1, np.nan, 1.0, linear, nonlinear, (std, std), flagged)

    report = AmplitudeReport((check(2.0, 0.2 + 0j, 0.1), check(2.1, 0.01j, 0.1), check(5.0, 0j, 0.1, False)))
    rows = report.by_speed()
    assert [row["windows"] for row in rows] == [2, 1] and [row["flagged"] for row in rows] == [1, 1]
    assert rows[1]["fitted"] == 0 and rows[1]["median_relative_difference"] is None
    assert "2 of 3 windows flagged" in report.summary() and "falls over" in report.summary()
    json.dumps(report.to_dict())
    assert report.checks[2].to_dict()["eigenvalue"] is None


def test_bicycle_the_nonlinear_model_cannot_hold_is_noted_not_fatal():
    bicycle = load_bicycle("benchmark").with_extensions(payload=Payload(5.0, 0.3, -0.9))
    report = check_amplitudes(bicycle, _first_window(bicycle, 6.0, 0.1, 0.5))
    assert report.checks == () and "payload" in report.note and "not checked" in report.summary()


def test_diagnose_reports_linearity_in_json_markdown_and_output(tmp_path, capsys):
    bicycle = load_bicycle("benchmark")
    files = []
    for k, speed in enumerate((4.5, 6.0)):
        run = simulate_run(bicycle, RunScenario(speed=speed, n_pushes=2, seed=k))
        files.append(write_run_csv(run, tmp_path / f"run{k}.csv"))
    out = tmp_path / "report.json"
    assert main(["diagnose", *map(str, files), "--bicycle", "benchmark", "--no-parameters", "--json", str(out),
                 "--report", str(tmp_path / "report")]) == 0
    printed = capsys.readouterr().out
    assert "linearity: nonlinear vs linear weave" in printed
    data = json.loads(out.read_text())
    summary = data["nonlinear_amplitude"]
    assert summary["flag_definition"] == FLAG_DEFINITION and summary["windows"] == len(data["windows"])
    for window in data["windows"]:
        nonlinear = window["nonlinear"]
        assert set(nonlinear) >= {"amplitude", "eigenvalue", "linear_eigenvalue", "difference", "flagged"}
        assert nonlinear["linear_eigenvalue"] == window["model_eigenvalue"]
        assert 0.05 < nonlinear["amplitude"] < 1.0
    assert "## 5. Linearity at the measured amplitude" in (tmp_path / "report" / "report.md").read_text()
