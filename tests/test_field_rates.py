"""Runs sampled faster than 100 Hz: a quiet sensor, and a held bicycle's wobble clear of its noise."""

import numpy as np
import pytest
from scipy.signal import butter, sosfilt
from window_procedures import BICYCLES, coasts, scenario, weave

from whipple.measurement.catches import ONSET_MARGIN, TAIL_VARIANCE, catch_onset
from whipple.measurement.rejections import no_oscillation
from whipple.measurement.swings import ANALYSIS_RATE
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle
from whipple.simulation.simulator import simulate_run

FAST = 1000.0


def _wobbling(n, onset, seed, rate=FAST, noise=0.015, wobble=0.025):
    """White noise per sample, and from ``onset`` on a held bicycle's wobble: noise low-passed at 4 Hz."""
    rng = np.random.default_rng(seed)
    time = np.arange(n) / rate
    residual = noise * rng.standard_normal((1, n))
    if onset is not None:
        slow = sosfilt(butter(2, 4.0, fs=rate, output="sos"), rng.standard_normal(n))
        residual[0, onset:] += wobble * slow[onset:] / np.std(slow[onset:])
    return time, residual


def _coasts(name, procedure, speed, seed, rate):
    """The records of the coasts holding a weave cycle of one simulated run (window_procedures.coasts)."""
    bicycle = load_bicycle(BICYCLES[name])
    model = linear_model(bicycle)
    return coasts(simulate_run(bicycle, scenario(procedure, speed, seed, rate), model), weave(model, speed), model)


def _crossings(records):
    """Windows fitted across a catch or a push, over the records."""
    return sum(record["across_catch"] + record["across_push"] for record in records)


def test_a_wobble_within_each_samples_noise_is_found_averaged():
    # Per sample the wobble adds less than TAIL_VARIANCE times the noise's variance (the test
    # on raw samples cannot see it); averaged to ANALYSIS_RATE its variance stands far out.
    assert (0.015**2 + 0.025**2) / 0.015**2 < TAIL_VARIANCE
    for seed in range(5):
        time, residual = _wobbling(4000, 3000, seed)
        found = catch_onset(time, residual)
        assert found is not None, seed
        # Found in whole bins, the margin before where the wobble stands out.
        margin = int(np.ceil(ONSET_MARGIN * FAST))
        assert 3000 - margin - 2 * FAST / ANALYSIS_RATE <= found <= 3000 + 4 * FAST / ANALYSIS_RATE, (seed, found)


def test_fast_white_noise_alone_holds_no_catch():
    # 100 windows of white noise at 1000 Hz (1-4 s): averaging finds no tail in any.
    found = [catch_onset(*_wobbling(n, None, seed)) for seed, n in enumerate(np.linspace(1000, 4000, 100).astype(int))]
    assert found == [None] * 100


def test_up_to_the_catch_rate_every_sample_is_its_own_bin():
    # At ANALYSIS_RATE the samples are tested as they are: the index found is that of the samples.
    time, residual = _wobbling(600, 450, 0, rate=ANALYSIS_RATE, noise=0.01, wobble=0.1)
    found = catch_onset(time, residual)
    assert found is not None and 450 - int(np.ceil(ONSET_MARGIN * ANALYSIS_RATE)) - 1 <= found <= 452


@pytest.mark.parametrize("rate", [500.0, 1000.0])
def test_a_coast_caught_in_the_wobble_ends_at_its_catch(rate):
    # kooijman2008 at 4.5 m/s, simulated with the default sensors, whose noise per sample
    # leaves the held bicycle's wobble (about 0.025 rad/s) clear of the noise once low-passed.
    # Each coast lasts 5 s and is caught where its weave has decayed to the wobble's size: the
    # test of the residual on raw samples found no change, and two windows ran on through the
    # hold to the next push (their eigenvalues 1.3-1.8 standard errors off).
    records = _coasts("kooijman2008", "seed", 4.5, 0, rate)
    assert len(records) == 3
    assert all(record["fitted"] for record in records)
    assert _crossings(records) == 0


def test_a_wobble_in_the_hold_is_no_push_from_rest():
    # The benchmark at 6 m/s and 500 Hz: in the hold before the second push a wobble of
    # 0.054 rad/s (the hold's own swings reached 0.047) left the still stretch, and the hand's
    # push after it gave a swing ten times higher, more than any free swing back. Read as a
    # push from rest and its swing back, the push fell inside the window (from 7.09 s, the
    # push ending at 7.38 s); the window now starts after the push.
    records = _coasts("benchmark", "sharp", 6.0, 0, 500.0)
    assert all(record["fitted"] and record["usable"] for record in records)
    assert _crossings(records) == 0


def test_a_decay_into_a_wobbling_hold_ends_where_the_hand_takes_over():
    # kooijman2008 at 4.5 m/s and 200 Hz, seed 1: a coast caught after 5 s, its weave decayed to
    # the size of the held bicycle's wobble, which stands out of the noise at this rate. The
    # window's tail (a period after the last clear extreme) ran on through the hold to the next
    # push, 1.2 s past the catch (its eigenvalue 1.0 standard error off); the wobble's swings are
    # quick, and the tail now ends where the first of them starts.
    records = _coasts("kooijman2008", "seed", 4.5, 1, 200.0)
    assert len(records) == 3
    assert all(record["fitted"] and record["usable"] for record in records)
    assert _crossings(records) == 0


def test_a_stretch_ended_by_the_hand_says_so():
    # The reason a push gave no window names the hand's hold where the quick swing ended it.
    assert (no_oscillation(0, "quick swing at 57.40 s (a hand?)", False)
            == "no free swing before a hand holds the bicycle from 57.40 s")


def test_a_growth_does_not_reach_back_into_the_push_from_rest():
    # The Browser at 3.5 m/s (weave +0.64 1/s) and 200 Hz, seed 1: each coast is a weave growing
    # out of a 0.1 s push from rest until the catch. The swing out of the still stretch (the
    # push, 0.10 rad/s) is followed by one 4.6 times higher, where the growth's next swing grows
    # 2.3 times: the push's swing outgrows the growth's own trend, and the window reached back
    # into the push (from 1.04 s, the push ending at 1.10 s). It now starts after it.
    records = _coasts("browser", "seed", 3.5, 1, 200.0)
    assert len(records) == 3
    assert all(record["fitted"] for record in records)
    assert _crossings(records) == 0
