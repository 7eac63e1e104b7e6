"""BicycleParameters' own files: every bicycle of the data set loads, riders are named.

The files in tests/data/bicycleparameters/ are unmodified copies from the BicycleParameters
repository (BSD licence; provenance in the folder's README). Stable speed ranges are checked
against an independent closed form: the Routh-Hurwitz conditions of the characteristic
polynomial of Meijaard et al.'s (2007) closed-form matrices (tests/meijaard_oracle.py), whose
roots in v^2 are solved directly (capsize: det(K0 + v^2 K2) = 0, linear in v^2; weave: the
Hurwitz determinant, quadratic in v^2).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from meijaard_oracle import meijaard_matrices

from whipple.cli import main
from whipple.errors import BicycleFileError, ParameterError
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle, validate
from whipple.stability.critical import critical_speeds

DATA = Path(__file__).parent / "data" / "bicycleparameters"
#: The data set's twelve bicycles with a benchmark parameter file.
BICYCLES = ("Balanceassistv1", "Benchmark", "Browser", "Browserins", "Crescendo", "Fisher", "Pista",
            "Rigid", "Silver", "Tms", "Yellow", "Yellowrev")
RIDERS = ("JasonBrowserBenchmark.txt", "JasonBalanceassistv1Benchmark.txt", "ChrisYeadonCFG.txt",
          "JasonBrowserYeadonCFG.txt", "MontYeadonMeas.txt")
SPEEDS = (0.0, 10.0)


def _path(name: str) -> Path:
    return DATA / "bicycles" / f"{name}Benchmark.txt"


def _polynomial(*coefficients: float) -> np.polynomial.Polynomial:
    return np.polynomial.Polynomial(coefficients)


def closed_form_stable_ranges(parameters: dict[str, float], low: float, high: float) -> list[tuple[float, float]]:
    """Stable speed ranges in [low, high] from the Routh-Hurwitz conditions, solved in closed form.

    With M, C1, K0, K2 of the closed form, det(M s^2 + v C1 s + K0 + v^2 K2) = a4 s^4 + ... + a0
    has a4 = det M, a3 = v b3, a2 = c2 + v^2 d2, a1 = v (c1 + v^2 d1), a0 = c0 + v^2 d0 (K2 has
    a zero first column), and the Hurwitz determinant a3 a2 a1 - a4 a1^2 - a3^2 a0 is v^2 times
    a quadratic in u = v^2. All boundaries are roots in u of these polynomials; stability is
    then decided between them.
    """
    M, C1, K0, K2 = (np.asarray(x) for x in meijaard_matrices(parameters))
    assert K2[0, 0] == 0 and K2[1, 0] == 0

    def cross(a: np.ndarray, b: np.ndarray) -> float:  # a11 b22 + b11 a22 - a12 b21 - b12 a21
        return float(a[0, 0] * b[1, 1] + b[0, 0] * a[1, 1] - a[0, 1] * b[1, 0] - b[0, 1] * a[1, 0])

    a4 = float(np.linalg.det(M))
    b3 = cross(M, C1)
    c2, d2 = cross(M, K0), cross(M, K2) + float(np.linalg.det(C1))
    c1, d1 = cross(C1, K0), cross(C1, K2)
    c0 = float(np.linalg.det(K0))
    d0 = cross(K0, K2)  # det(K0 + u K2) = c0 + u d0 + u^2 det K2, and det K2 = 0
    u = np.polynomial.Polynomial([0.0, 1.0])
    a2, a1_v, a0 = c2 + d2 * u, c1 + d1 * u, c0 + d0 * u
    hurwitz = b3 * a2 * a1_v - a4 * a1_v**2 - b3**2 * a0  # divided by v^2

    roots = [low, high]
    for poly in (a2, a1_v, a0, hurwitz):
        for root in np.atleast_1d(poly.roots()):
            if abs(root.imag) < 1e-12 and root.real > 0 and low < np.sqrt(root.real) < high:
                roots.append(float(np.sqrt(root.real)))
    roots = sorted(roots)

    def stable(v: float) -> bool:
        w = v * v
        return bool(a4 > 0 and v * b3 > 0 and a2(w) > 0 and v * a1_v(w) > 0 and a0(w) > 0 and hurwitz(w) > 0)

    ranges: list[tuple[float, float]] = []
    for left, right in zip(roots[:-1], roots[1:], strict=True):
        if right - left > 1e-12 and stable((left + right) / 2):
            if ranges and ranges[-1][1] == left:
                ranges[-1] = (ranges[-1][0], right)
            else:
                ranges.append((left, right))
    return ranges


@pytest.mark.parametrize("name", [*BICYCLES, "Rigidfakeyeadon"])
def test_every_bicycle_of_the_data_set_loads_and_matches_the_closed_form(name):
    bicycle = load_bicycle(_path(name))
    assert validate(bicycle).ok
    found = critical_speeds(linear_model(bicycle), *SPEEDS).stable_speed_ranges
    expected = closed_form_stable_ranges(bicycle.parameters, *SPEEDS)
    assert len(found) == len(expected) >= 1
    difference = max(abs(a - b) for pair in zip(found, expected, strict=True) for a, b in zip(*pair, strict=True))
    assert difference < 1e-6, (name, found, expected)


def test_the_closed_form_reproduces_the_published_benchmark_speeds():
    # Meijaard et al. (2007), Table 2: weave 4.292382538 m/s, capsize 6.024262015 m/s.
    (low, high), = closed_form_stable_ranges(load_bicycle("benchmark").parameters, 0.0, 10.0)
    assert abs(low - 4.292382538) < 1e-8 and abs(high - 6.024262015) < 1e-8


def test_measured_inertias_that_break_the_triangle_inequality_are_warnings():
    browser = validate(load_bicycle(_path("Browser")))
    (warning,) = browser.warnings
    assert "rear frame inertia" in warning and "by 0.03 kg m^2" in warning
    assert "more than the stated uncertainties explain" in warning
    assert "IByy does not enter the linear equations" in warning
    (warning,) = validate(load_bicycle(_path("Yellow"))).warnings
    assert "front frame inertia" in warning and "within measurement error" in warning
    assert "IHyy 0.00227 kg m^2 larger would satisfy it" in warning


def test_the_split_front_frame_of_the_rigid_bicycle_adds_up():
    # mG + mS = mH, and the joined inertia equals IH within the stated uncertainties: no note.
    bicycle = load_bicycle(_path("Rigid"))
    assert bicycle.notes == ()
    assert bicycle.parameters["mH"] == 5.4


@pytest.mark.parametrize("file_name", RIDERS)
def test_rider_files_get_one_line_saying_what_they_are(file_name, capsys):
    path = DATA / "riders" / file_name
    before = path.read_bytes()
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(path) in err
    assert "not a bicycle" in err
    if "Benchmark" in file_name:
        assert "a rider file" in err and "missing the other 18 benchmark parameters (w, c, lam" in err
    else:
        assert "Yeadon" in err
    assert path.read_bytes() == before


# --- fixtures written here: the same features, one at a time --------------------------------

_BASE = (DATA / "bicycles" / "BenchmarkBenchmark.txt").read_text()


def _write(tmp_path: Path, text: str, name: str = "TestBenchmark.txt") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_extra_keys_that_agree_are_accepted(tmp_path):
    text = _BASE + "IRzz = 0.0603+/-0.0\nIFzz = 0.1405\nyB = 0.0+/-0.001\nyH = 0.0\n"
    bicycle = load_bicycle(_write(tmp_path, text))
    assert bicycle.parameters == load_bicycle("benchmark").parameters
    assert bicycle.notes == ()


@pytest.mark.parametrize(("extra", "pattern"), [
    ("IRzz = 0.07+/-0.001\n", r"IRzz = 0.07 differs from IRxx = 0.0603 kg m\^2 \(9.7 std\): the Whipple model "
                              r"needs wheels symmetric about their axle"),
    ("IFzz = 0.15\n", r"IFzz = 0.15 differs from IFxx = 0.1405 kg m\^2 \(no uncertainty stated\)"),
    ("yB = 0.02+/-0.001\n", r"yB = 0.02 m is not zero \(20.0 std\): the Whipple model needs a laterally symmetric"),
])
def test_extra_keys_that_break_the_symmetric_model_are_refused(tmp_path, extra, pattern):
    path = _write(tmp_path, _BASE + extra)
    with pytest.raises(ParameterError, match=pattern) as caught:
        load_bicycle(path)
    assert str(caught.value).startswith(f"{path}: ") and "\n" not in str(caught.value)


def test_extra_keys_within_their_uncertainty_are_accepted(tmp_path):
    # 0.0612 - 0.0603 = 0.0009 is within 3 standard deviations of 0.0004.
    load_bicycle(_write(tmp_path, _BASE + "IRzz = 0.0612+/-0.0004\nyH = 0.001+/-0.0005\n"))


def _split(mass_g: float = 1.5) -> str:
    """Benchmark with its front frame H split into a fork G and a handlebar S that add up to H."""
    # Two point-like parts along a line through H's mass centre, with inertias making up IH.
    mH, xH, zH = 4.0, 0.9, -0.7
    mS = mH - mass_g
    dx, dz = 0.06, -0.08  # G at H + (dx, dz) * mS / mH, S at H - (dx, dz) * mG / mH
    xG, zG = xH + dx * mS / mH, zH + dz * mS / mH
    xS, zS = xH - dx * mass_g / mH, zH - dz * mass_g / mH
    shift = {"xx": mass_g * (zG - zH) ** 2 + mS * (zS - zH) ** 2,
             "zz": mass_g * (xG - xH) ** 2 + mS * (xS - xH) ** 2,
             "xz": -(mass_g * (xG - xH) * (zG - zH) + mS * (xS - xH) * (zS - zH))}
    own = {"xx": 0.05892 - shift["xx"], "zz": 0.00708 - shift["zz"], "xz": -0.00756 - shift["xz"]}
    lines = [f"mG = {mass_g!r}", f"xG = {xG!r}", f"zG = {zG!r}", f"mS = {mS!r}", f"xS = {xS!r}", f"zS = {zS!r}"]
    for axes in ("xx", "zz", "xz"):
        lines += [f"IG{axes} = {own[axes] / 2!r}", f"IS{axes} = {own[axes] / 2!r}"]
    return "\n".join(lines) + "\n"


def test_a_split_front_frame_that_adds_up_is_accepted(tmp_path):
    bicycle = load_bicycle(_write(tmp_path, _BASE + _split()))
    assert bicycle.notes == ()


def test_a_split_front_frame_that_does_not_add_up_is_a_warning(tmp_path):
    text = _BASE + _split().replace("mS = 2.5", "mS = 2.8")
    bicycle = load_bicycle(_write(tmp_path, text))
    (note,) = bicycle.notes
    assert "the fork (G) and handlebar (S) joined do not give the front frame H" in note
    assert "mH 4 vs 4.3 kg" in note and "the model uses the H values" in note
    assert note in validate(bicycle).warnings
    assert bicycle.parameters["mH"] == 4.0


def test_front_frame_computed_from_its_split_when_absent(tmp_path):
    keep = [line for line in _BASE.splitlines() if not line.split("=")[0].strip().startswith(("mH", "xH", "zH", "IH"))]
    bicycle = load_bicycle(_write(tmp_path, "\n".join(keep) + "\n" + _split()))
    reference = load_bicycle("benchmark").parameters
    for key in ("mH", "xH", "zH", "IHxx", "IHzz", "IHxz"):
        assert bicycle.parameters[key] == pytest.approx(reference[key], rel=1e-12, abs=1e-15)
    assert bicycle.notes == ("front frame H computed from the fork (G) and handlebar (S) given in the file",)


@pytest.mark.parametrize(("text", "pattern"), [
    (_BASE + "mG = 1.0\n", r"incomplete split front frame: missing xG, zG, IGxx"),
    (_BASE + "gravity = 9.81\n", r"unknown key 'gravity' in the file"),
    (_BASE + "IRzx = 0.0\n", r"unknown key 'IRzx' in the file \(did you mean"),
])
def test_keys_that_mean_nothing_are_still_refused(tmp_path, text, pattern):
    with pytest.raises(BicycleFileError, match=pattern):
        load_bicycle(_write(tmp_path, text))


def test_a_raw_measurement_file_is_named(tmp_path):
    path = _write(tmp_path, "mB = 3.0\nlF = 0.5\nTcB1 = 1.2\n", "BikeMeasured.txt")
    with pytest.raises(BicycleFileError, match="raw measurement file; whipple reads the benchmark parameters"):
        load_bicycle(path)
