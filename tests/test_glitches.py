"""Glitches: isolated wild samples are found, named and left out; clean runs lose no sample.

The rule (whipple.measurement.glitches) is checked both ways: on runs without glitches (the
simulator's, over speeds, settings and sample rates, and the bundled measured runs, whose pushes
shake the sensors) it flags nothing; on runs with a wild sample added it finds exactly that one,
and the run keeps every window but the one that holds it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from whipple.cli import main
from whipple.measurement.bundled import bundled_runs
from whipple.measurement.experiment import measure_run
from whipple.measurement.glitches import GlitchRule, find_glitches
from whipple.measurement.runs import read_run, run_from_simulation
from whipple.model.parameters import load_bicycle
from whipple.simulation.run_writer import write_run_csv
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

COLUMNS = ("roll_rate", "yaw_rate", "steer_angle", "steer_rate", "roll_angle", "speed")


@pytest.mark.parametrize("speed, setting, rate, seed", [
    (2.0, "treadmill", 100.0, 0), (4.5, "ground", 100.0, 1), (5.0, "treadmill", 1000.0, 2),
    (7.0, "treadmill", 50.0, 3), (6.0, "ground", 20.0, 4),
])
def test_no_glitch_in_simulated_runs(speed, setting, rate, seed):
    scenario = RunScenario(speed=speed, setting=setting, sample_rate=rate, seed=seed, deceleration=0.02,
                           columns=COLUMNS)
    run = run_from_simulation(simulate_run(load_bicycle("benchmark"), scenario, name="clean"))
    for name, values in run.signals.items():
        assert find_glitches(values).size == 0, name


def test_no_glitch_in_the_bundled_measured_runs():
    # Their pushes shake the IMU: single roll-rate samples at an impact stand out by up to about
    # 20 noise scales, below the rule's 25; nothing else comes near.
    for entry in bundled_runs():
        run = read_run(entry)
        assert not [w for w in run.warnings if w.startswith("glitch")], run.name


def test_a_wild_sample_in_noise_is_found_and_steps_kinks_and_peaks_are_not():
    rng = np.random.default_rng(5)
    time = np.arange(4000) / 100
    clean = np.sin(2 * np.pi * 1.5 * time) * np.exp(-0.2 * time) + 0.015 * rng.standard_normal(time.size)
    clean[2000:] += 0.8  # a step, as a catch makes
    clean[3000:] += 0.05 * (time[3000:] - time[3000]) * 100  # a kink
    assert find_glitches(clean).size == 0
    for value in (1e6, 50.0, -3.0):
        spiked = clean.copy()
        spiked[1234] = value
        assert find_glitches(spiked).tolist() == [1234]
    quantised = np.round(clean / 0.0767) * 0.0767 + 1e-9 * rng.standard_normal(time.size)
    assert find_glitches(quantised).size == 0


def test_an_impact_that_rings_over_several_samples_is_no_glitch():
    rng = np.random.default_rng(6)
    values = 0.01 * rng.standard_normal(1000)
    values[500:506] += 0.4 * np.array([1.0, -0.8, 0.6, -0.5, 0.3, -0.2])  # a push's shock, ringing
    assert find_glitches(values).size == 0
    values[700] = 0.4
    assert find_glitches(values).tolist() == [700]


def test_a_rule_is_checked():
    with pytest.raises(ValueError, match="threshold"):
        GlitchRule(threshold=0.0)
    with pytest.raises(ValueError, match="block"):
        GlitchRule(block=2)


@pytest.fixture(scope="module")
def run_file(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("glitch")
    run = simulate_run(load_bicycle("benchmark"), RunScenario(speed=5.0, seed=1), name="run")
    return write_run_csv(run, folder / "run.csv")


def _with_cell(source: Path, target: Path, time: float, value: str) -> Path:
    lines = source.read_text().splitlines()
    header = next(k for k, line in enumerate(lines) if not line.startswith("#"))
    column = lines[header].split(",").index("roll_rate")
    row = header + 1 + int(round(time * 100))
    cells = lines[row].split(",")
    cells[column] = value
    lines[row] = ",".join(cells)
    target.write_text("\n".join(lines) + "\n")
    return target


def _fit_of(path: Path, **options) -> list:
    return [m.fit for m in measure_run(read_run(path, **options)) if m.fit is not None]


@pytest.mark.parametrize("value", ["1e6", "50"])
def test_a_wild_sample_costs_no_window(run_file, tmp_path, value):
    clean = _fit_of(run_file)
    assert len(clean) == 3
    glitch_time = 9.0  # inside the second window
    holding = [k for k, fit in enumerate(clean) if fit.start < glitch_time < fit.stop]
    assert len(holding) == 1
    spiked = _with_cell(run_file, tmp_path / "spiked.csv", glitch_time, value)
    run = read_run(spiked)
    assert run.warnings == (f"glitch: 1 isolated wild roll_rate sample(s) left out as gaps ({float(value):.6g} "
                            f"rad/s at 9 s)",
                            "roll_rate: 1 missing sample(s) in gaps of up to 2 sample(s) filled by interpolation")
    # Filled from its neighbours: within the sensor's noise of the sample it replaced.
    measured = read_run(run_file).signals["roll_rate"][900]
    assert abs(run.signals["roll_rate"][900] - measured) < 4 * 0.0179
    fitted = _fit_of(spiked)
    assert [(f.start, f.stop) for f in fitted] == [(f.start, f.stop) for f in clean]
    for k, (before, after) in enumerate(zip(clean, fitted, strict=True)):
        if k not in holding:
            assert after.eigenvalue == before.eigenvalue  # the same windows, the same eigenvalues
        else:  # one sample of ~300 replaced by its neighbours' cubic: well within the fit's error
            std = np.sqrt(np.diag(before.covariance))[:2]
            assert abs(after.damping - before.damping) < 0.2 * std[0]
            assert abs(after.frequency - before.frequency) < 0.2 * std[1]
    # Not filled, the gap costs the window that holds it: none spans it.
    unfilled = _fit_of(spiked, filled_gap=0.0)
    assert all(f.stop <= glitch_time or f.start > glitch_time for f in unfilled)
    others = [f.eigenvalue for k, f in enumerate(clean) if k not in holding]
    assert all(e in [f.eigenvalue for f in unfilled] for e in others)
    # Kept as data, the wild sample costs other windows too (the finding).
    kept = [f.eigenvalue for f in _fit_of(spiked, glitches=None)]
    assert [e for e in kept if e in others] != others


def test_fit_names_the_glitch(run_file, tmp_path, capsys):
    spiked = _with_cell(run_file, tmp_path / "spiked.csv", 9.0, "1e6")
    before = spiked.read_bytes()
    assert main(["fit", str(spiked)]) == 0
    out = capsys.readouterr().out
    assert "spiked: " in out and "note: glitch: 1 isolated wild roll_rate sample(s) left out as gaps (1e+06 rad/s " \
                                 "at 9 s)" in out
    assert spiked.read_bytes() == before
