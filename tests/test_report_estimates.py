"""How the report says a fitted value: with its standard deviation, or as not determined by the data."""

from __future__ import annotations

import numpy as np

from whipple.diagnosis.estimate_text import determined, estimate_text


def test_a_spread_wider_than_its_bounds_allow_is_not_determined():
    # A front load's mass in 0-20 kg: a value spread evenly over it has a std of 5.77 kg.
    assert determined(1.6, (0.0, 20.0))
    assert not determined(6.0, (0.0, 20.0))
    assert not determined(255.0, (0.0, 20.0))
    assert not determined(np.inf, (0.0, 20.0))
    assert not determined(np.nan, (0.0, 20.0))
    # Without bounds any finite spread is an uncertainty.
    assert determined(1e6, (-np.inf, np.inf))


def test_the_text_gives_no_plus_minus_for_a_value_the_data_do_not_determine():
    sharp = {"value": 18.73, "std": 1.3, "unit": "kg", "bounds": [0.0, 36.0], "determined": True}
    broad = {"value": 20.0, "std": 254.9, "unit": "kg", "bounds": [0.0, 20.0], "determined": False}
    assert estimate_text(sharp) == "18.73 +/- 1.3 kg"
    text = estimate_text(broad)
    assert "+/-" not in text and "not determined" in text and "0 to 20 kg" in text
