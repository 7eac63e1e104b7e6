"""Windows of real procedures: pushes from rest, either sign, catch and hold, growing weave, cut segments.

Simulated runs know their free coasting (``segments``); each coast that holds a weave cycle
must give a fitted window inside it that ends at its catch at the latest. The slow test counts
the rate over four bicycles and four procedures (benchmarks/bench_window_finder.py prints it
for more seeds).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from window_procedures import BICYCLES, PROCEDURES, coasts, growing_speeds, pieces, procedure_tally, scenario, weave

from whipple.cli import main
from whipple.measurement.experiment import measure_run
from whipple.measurement.runs import read_run, run_from_simulation
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle
from whipple.simulation.procedure import cut_run
from whipple.simulation.run_writer import write_run_csv
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run


def _bicycle(name):
    bicycle = load_bicycle(BICYCLES[name])
    return bicycle, linear_model(bicycle)


def _every_coast_fitted(name, procedure, speed, seeds, tolerance=0.05):
    """Each coast of a weave cycle gets a usable window ending by its catch, near the model's weave."""
    bicycle, model = _bicycle(name)
    eigenvalue = weave(model, speed)
    checked = 0
    for seed in seeds:
        simulated = simulate_run(bicycle, scenario(procedure, speed, seed), model)
        for piece in pieces(simulated, procedure, seed):
            for record in coasts(piece, eigenvalue, model):
                checked += 1
                assert record["usable"] and record["across_catch"] == 0 and record["across_push"] == 0, (
                    name, procedure, speed, seed, record)
                assert max(record["errors"]) < tolerance
    return checked


@pytest.mark.parametrize(("name", "speed", "tolerance"), [("sbw2024", 2.0, 0.12), ("benchmark", 4.0, 0.05),
                                                       ("browser", 5.0, 0.05)])
def test_sharp_pushes_from_rest_of_either_sign_each_give_a_window(name, speed, tolerance):
    # The swing back after a sharp push from rest is twice the push's own (low-passed) swing or
    # more; it was read as growth and the next swing as a catch ("no oscillation after ..."),
    # or the push was too small beside the catches to count (sbw2024 at 2 m/s, seed 1; the
    # benchmark at 4 m/s). sbw2024 at 2 m/s: a weave of -2.8 1/s beside a castering root of
    # -4.2 1/s, which the seed's function has no term for, in windows of about a cycle: the
    # fitting function's bias, not the window's, is up to 10 % there.
    assert _every_coast_fitted(name, "sharp", speed, seeds=(0, 1), tolerance=tolerance) >= 4


def test_pushes_of_either_sign_and_hand_caught_coasts_are_drawn_as_asked():
    bicycle, model = _bicycle("benchmark")
    runs = [simulate_run(bicycle, scenario("sharp", 5.0, seed), model) for seed in range(4)]
    signs = [np.sign(push.roll_impulse) for run in runs for push in run.pushes]
    assert signs.count(1.0) >= 3 and signs.count(-1.0) >= 3
    coasting = [stop - start for run in runs for start, stop in run.segments]
    assert all(0.3 * 5.0 - 0.01 <= length <= 5.0 + 0.01 for length in coasting)
    assert len(set(np.round(coasting, 2))) == len(coasting)  # each caught when the hand chose


def test_growing_weave_is_fitted_until_the_catch_never_across_it():
    # Below the weave speed, at +1 1/s and +0.5 1/s: small pushes, growth, caught at the limits.
    for name in ("benchmark", "kooijman2008"):
        _, model = _bicycle(name)
        fast, slow = growing_speeds(model)[-1], growing_speeds(model)[1]
        assert weave(model, fast).real == pytest.approx(1.0, abs=0.02)
        assert _every_coast_fitted(name, "growing", fast, seeds=(0,)) + \
            _every_coast_fitted(name, "growing", slow, seeds=(0,)) >= 3


@pytest.mark.parametrize(("name", "speed"), [("sbw2024", 3.0), ("kooijman2008", 5.0)])
def test_segments_cut_after_their_push_get_a_window_from_their_first_sample(name, speed):
    assert _every_coast_fitted(name, "cut", speed, seeds=(0,)) >= 2
    bicycle, model = _bicycle(name)
    simulated = simulate_run(bicycle, scenario("sharp", speed, 0), model)
    start, stop = simulated.segments[0]
    piece = cut_run(simulated, start + 0.1, stop)
    assert piece.time[0] == pytest.approx(start + 0.1) and piece.segments == ((piece.time[0], stop),)
    first = next(m for m in measure_run(run_from_simulation(piece)) if m.fit is not None)
    assert first.window.start_index == 0 and "record's first sample" in first.window.reason


def test_a_segment_of_little_over_a_second_loads_and_fits(tmp_path, capsys):
    # sbw2024 with its controller at 4 m/s: a weave period of 0.65 s, so 1.2 s hold about two.
    bicycle, model = _bicycle("sbw2024")
    simulated = simulate_run(bicycle, RunScenario(speed=4.0, seed=5, n_pushes=1), model)
    start, _ = simulated.segments[0]
    path = write_run_csv(cut_run(simulated, start + 0.05, start + 1.25), tmp_path / "segment.csv")
    assert 1.0 < read_run(path).duration < 1.3
    out = tmp_path / "fit.json"
    assert main(["fit", str(path), "--json", str(out)]) == 0
    fitted = [w for w in json.loads(out.read_text()) if w["skipped"] is None]
    assert len(fitted) == 1
    eigenvalue = weave(model, 4.0)
    assert abs(complex(*fitted[0]["eigenvalue"]) - eigenvalue) < 0.05 * abs(eigenvalue)
    assert "1 window(s) fitted" in capsys.readouterr().out


def test_a_push_caught_at_once_is_rejected_in_words():
    # At 2 m/s the benchmark falls within a swing of each push and is caught: nothing to fit,
    # and each rejected stretch says what was seen and how it ended.
    bicycle, model = _bicycle("benchmark")
    measured = measure_run(run_from_simulation(simulate_run(bicycle, RunScenario(speed=2.0, seed=1), model)))
    reasons = [m.rejected for m in measured if m.rejected and m.rejected.startswith("no oscillation after")]
    assert reasons
    for reason in reasons:
        assert any(words in reason for words in ("no free swing before", "a single swing back before",
                                                 "fewer than 3 samples before")), reason
        assert any(ending in reason for ending in ("the bicycle", "the motion", "the record", "the next push",
                                                   "the signal")), reason


def _windows_and_catches(name, procedure, speed, seed, piece=0):
    """The fitted windows of one simulated run (or cut segment), and its coasts and catches."""
    bicycle, model = _bicycle(name)
    run = pieces(simulate_run(bicycle, scenario(procedure, speed, seed), model), procedure, seed)[piece]
    return [m for m in measure_run(run_from_simulation(run)) if m.fit is not None], run


def test_a_catch_just_before_a_window_end_is_seen_in_the_samples_after_it():
    # The benchmark at 4.5 m/s, a segment cut after its push (seed 2): the hand caught the
    # bicycle at 5.41 s, 0.03 s before the swing the finder ends the window at; inside the
    # window the catch held two samples, too few to stand out, and the window was fitted to
    # 5.43 s. Right after it the hand holds the bicycle while the fit's continuation swings on.
    fitted, run = _windows_and_catches("benchmark", "cut", 4.5, 2)
    (start, catch), = run.segments
    assert catch in run.catches
    inside = [m for m in fitted if start - 0.01 <= m.fit.start < catch]
    assert len(inside) == 1 and inside[0].usable
    assert inside[0].fit.stop < catch
    assert "cut before a catch" in inside[0].window.notes[-1]


@pytest.mark.parametrize(("seed", "ending"), [(1, "decayed into the background (the record ends at 5.65 s: its last "
                                                "swing left out)"),
                                             (5, "decayed into the noise")])
def test_a_segment_cut_just_after_its_catch_is_fitted_up_to_the_catch(seed, ending):
    # kooijman2008 at 4.5 m/s, where the weave barely decays: segments cut 0.10 s (seed 1) and
    # 0.03 s (seed 5) after the hand's catch, while the motion had sunk near the background.
    # The hand's mark on those samples is 3-5 noise standard deviations, which no swing rule
    # and no test of the residual can tell; the windows ran to the record's end, across the
    # catch. The record's last margin of samples (seed 5), and an unfinished last swing in the
    # tail after the last clear extreme (seed 1), are left out.
    fitted, run = _windows_and_catches("kooijman2008", "cut", 4.5, seed)
    (start, catch), = run.segments
    assert catch in run.catches and 0.0 < run.time[-1] - catch < 0.11
    inside = [m for m in fitted if start - 0.01 <= m.fit.start < catch]
    assert len(inside) == 1 and inside[0].usable
    assert inside[0].fit.stop < catch
    assert inside[0].window.reason.endswith(ending)


def test_a_free_motion_to_the_record_end_keeps_all_but_the_filter_margin():
    # A segment cut in free motion, 1.6 s before the catch, as the motion sinks into the
    # noise: the window keeps the record's last swing and leaves out only the last samples
    # that the low-pass filter spreads a hand's mark over.
    bicycle, model = _bicycle("benchmark")
    simulated = simulate_run(bicycle, scenario("sharp", 6.0, 0), model)
    start, stop = simulated.segments[0]
    piece = run_from_simulation(cut_run(simulated, start + 0.1, start + 1.8))
    assert stop - piece.time[-1] > 1.5
    measured = next(m for m in measure_run(piece) if m.fit is not None)
    assert measured.usable and measured.window.reason.endswith("decayed into the noise")
    assert 0.0 < piece.time[-1] - measured.window.stop < 0.1


def test_a_catch_and_its_return_are_no_window_and_the_growth_before_them_is():
    # The Browser at +0.75 1/s (seed 2): a small push at 7.38 s grows until the hand catches
    # the bicycle at 12.38 s. The catch and the hand's return are two swings of 0.4 s where the
    # weave's last half 1.3 s, and the bicycle is then held: they were fitted as a window
    # (-1.2+11.7i 1/s) that ran 0.36 s past the catch, and the growth gave none.
    _, model = _bicycle("browser")
    speed = growing_speeds(model)[2]
    eigenvalue = weave(model, speed)
    fitted, run = _windows_and_catches("browser", "growing", speed, 2)
    start, catch = run.segments[1]
    inside = [m for m in fitted if start <= m.fit.start < catch]
    assert len(inside) == 1 and inside[0].usable
    assert inside[0].fit.stop < catch
    assert abs(inside[0].fit.eigenvalue - eigenvalue) < 0.05 * abs(eigenvalue)


def test_a_catch_out_of_a_still_stretch_starts_no_growth():
    # sbw2024 at 5 m/s (seed 2): the bicycle leans slowly in a still stretch until the hand
    # catches it at 17.09 s; the catch's quick swing out of the stillness, and the hand's slow
    # return, were read as a weave growing and caught (-16.7+11.9i 1/s, from 17.08 s).
    fitted, run = _windows_and_catches("sbw2024", "sharp", 5.0, 2)
    catch = run.catches[-1]
    assert catch == pytest.approx(17.09)
    assert not [m for m in fitted if m.fit.start < catch + 1.0 and m.fit.stop > catch]


@pytest.mark.slow
def test_most_coasts_of_a_weave_cycle_give_a_window_on_four_bicycles():
    """At least 85 % of the coasts that hold a weave cycle give a fitted window, over four
    bicycles, speeds of decaying and growing weave (up to +1 1/s) and the four procedures.

    Windows fitted across a catch: the aim is none. Measured (2026-12-07,
    benchmarks/bench_window_finder.py, with the catch test's two looks, the hold test and the
    record-end rule): none of 1,056 coasts of seeds 0-3, 3 of 2,108 of seeds 0-7 (kooijman2008
    at 4.5 m/s, 2-9 samples past the catch; see docs/measured-runs.md, "Known
    limitations"). Here at most 1 % of the coasts.
    """
    total = fitted = across = before_push = 0
    for name in BICYCLES:
        for procedure in PROCEDURES:
            tally = procedure_tally(name, procedure, seeds=(0,))
            total += tally.count["coasts"]
            fitted += tally.count["fitted"]
            across += tally.count["across_catch"]
            before_push += tally.count["across_push"]
    assert total > 200
    assert fitted >= 0.85 * total
    assert across <= 0.01 * total
    assert before_push == 0  # no window starts before its push has ended
