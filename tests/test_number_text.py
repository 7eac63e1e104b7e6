"""One rule for numbers written as text, shared by every reader (whipple.number_text)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from whipple.cli import main
from whipple.number_text import may_hold_other_numbers, parse_integer, parse_number


@pytest.mark.parametrize("text", ["1.5", "-2e3", ".5", "5.", "+0.25", " 7 ", "1E-9", "-0", "inf", "-Infinity", "nan"])
def test_decimal_text_reads_as_float_reads_it(text):
    value, expected = parse_number(text), float(text)
    assert value == expected or (math.isnan(value) and math.isnan(expected))


def test_random_decimal_texts_read_exactly_as_float():
    rng = np.random.default_rng(3)
    for value in rng.standard_normal(2000) * 10.0 ** rng.integers(-300, 300, 2000):
        for text in (repr(float(value)), f"{value:.17e}", f"{value:.6g}"):
            assert parse_number(text) == float(text)


@pytest.mark.parametrize("text", ["1_0", "\u0661\u0662", "\uff11\uff12", "0x10", "1.5.2", "", "e5", "1e", "--1",
                                  "1,5", "nan(1)", "١.٥"])
def test_other_texts_are_not_numbers(text):
    with pytest.raises(ValueError, match="not a number"):
        parse_number(text)


def test_integers_are_ascii_digits():
    assert parse_integer(" -12 ") == -12 and parse_integer("+7") == 7
    for text in ("1_2", "\uff11\uff12", "1.0", "", "1e3"):
        with pytest.raises(ValueError, match="not an integer"):
            parse_integer(text)


def test_fast_paths_know_which_text_may_differ():
    assert not may_hold_other_numbers("0.08,85,1e-3")
    assert may_hold_other_numbers("1_0") and may_hold_other_numbers("\uff11")


@pytest.mark.parametrize("argv", [["stability", "benchmark", "--speeds", "0:1_0"],
                                  ["stability", "benchmark", "--points", "\uff11\uff10"],
                                  ["simulate", "benchmark", "--speed", "1_0", "-o", "unused"]])
def test_command_line_numbers_follow_the_same_rule(argv, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and "expected" in error
