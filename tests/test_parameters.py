"""Bicycle parameter sets: built-in bicycles, file reading and writing, physical checks."""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest

from whipple.errors import BicycleFileError, InputError, ParameterError
from whipple.model.parameters import (
    OPTIONAL_PARAMETERS,
    PARAMETER_DESCRIPTIONS,
    PARAMETER_NAMES,
    PARAMETER_UNITS,
    Bicycle,
    Controller,
    Extensions,
    Payload,
    TyreCompliance,
    builtin_names,
    check_physical,
    load_bicycle,
    read_benchmark_txt,
    read_bicycle_toml,
    validate,
    validate_rows,
    write_bicycle_toml,
)


def test_parameter_names_follow_the_benchmark_order():
    # Meijaard et al. (2007), Table 1, in the order of the parameter-file specification.
    assert PARAMETER_NAMES == tuple(
        "w c lam g rR mR IRxx IRyy xB zB mB IBxx IByy IBzz IBxz "
        "xH zH mH IHxx IHyy IHzz IHxz rF mF IFxx IFyy".split()
    )
    assert set(OPTIONAL_PARAMETERS) == {"IByy", "IHyy"}


def test_every_parameter_has_a_unit_and_a_description_with_it():
    assert set(PARAMETER_UNITS) == set(PARAMETER_DESCRIPTIONS) == set(PARAMETER_NAMES)
    assert PARAMETER_DESCRIPTIONS["c"] == "trail [m]"
    for name in PARAMETER_NAMES:
        assert PARAMETER_DESCRIPTIONS[name].endswith(f"[{PARAMETER_UNITS[name]}]")


# --- built-in bicycles --------------------------------------------------------------------


@pytest.mark.parametrize("name", builtin_names())
def test_builtin_bicycles_load_and_are_physical(name):
    bicycle = load_bicycle(name)
    assert bicycle.name == name
    assert validate(bicycle).ok
    assert bicycle.source == name


def test_builtin_benchmark_is_table_1(meijaard2007):
    assert load_bicycle("benchmark").parameters == meijaard2007["parameters"]
    assert load_bicycle("benchmark").parameters["lam"] == math.pi / 10  # exact in the paper


def test_builtin_kooijman2008_is_the_published_set(kooijman2008):
    assert load_bicycle("kooijman2008").parameters == kooijman2008["parameters"]


def test_builtin_sbw2024_is_the_authors_model():
    bicycle = load_bicycle("sbw2024")
    # Values listed in data/sbw-treadmill/README.md (mechmotum/sbw_bicycle_with_model_matching).
    assert bicycle.parameters["w"] == 1.036
    assert bicycle.parameters["mR"] == 10.12
    assert bicycle.parameters["lam"] == pytest.approx(math.radians(18.2), abs=1e-15)
    assert not set(OPTIONAL_PARAMETERS) & set(bicycle.parameters)
    warnings = validate(bicycle).warnings
    assert any(w.startswith("IByy absent") for w in warnings)
    assert any(w.startswith("IHyy absent") for w in warnings)


def test_sbw2024_controller_is_the_steer_into_lean_law():
    # README: T_delta = K(v) phi_dot with K(v) = 2 (6.5 - v) = 13 - 2 v  [N m s/rad].
    feedback = load_bicycle("sbw2024").controller.feedback_coefficients()
    assert len(feedback) == 2
    assert feedback[0][1, 2] == 13.0
    assert feedback[1][1, 2] == -2.0
    for k, matrix in enumerate(feedback):
        assert matrix.shape == (2, 4)
        others = matrix.copy()
        others[1, 2] = 0.0
        assert not others.any(), f"F_{k} has other non-zero gains"


def _readme_mm_law(v):
    # The model-matching law as data/sbw-treadmill/README.md gives it: steer row [roll, steer, roll_rate, steer_rate].
    k_t = 1.03764578291
    return np.array([-0.348543214119, 0.11782139859 * v**2 - 0.0267476413381,
                     -0.278924665158 * v + k_t * 2 * (6.5 - v), 0.016087729532 * v])


def test_sbw2024_mm_is_sbw2024_with_the_model_matching_law():
    matching, plain = load_bicycle("sbw2024-mm"), load_bicycle("sbw2024")
    assert matching.parameters == plain.parameters
    assert matching.extensions == plain.extensions
    feedback = matching.controller.feedback_coefficients()
    for v in (0.5, 1.5, 2.5, 3.6, 4.7, 5.2, 6.4):
        gains = sum(v**k * matrix for k, matrix in enumerate(feedback))
        np.testing.assert_allclose(gains[1], _readme_mm_law(v), rtol=1e-12, atol=1e-13)
        assert not gains[0].any()  # no roll torque


def test_sbw2024_mm_law_reproduces_the_logged_fork_command():
    # The firmware's own record: command_fork (read as steer_torque) from the logged states.
    from whipple.measurement.bundled import bundled_runs
    from whipple.measurement.runs import read_run

    feedback = load_bicycle("sbw2024-mm").controller.feedback_coefficients()
    for entry in bundled_runs("model-matching-on")[1::2]:  # 9 and 16.2 km/h
        run = read_run(entry)
        s = run.signals
        states = np.stack([s["roll_angle"], s["steer_angle"], s["roll_rate"], s["steer_rate"]])
        law = sum(run.speed() ** k * (matrix[1] @ states) for k, matrix in enumerate(feedback))
        logged = np.isfinite(s["controller_torque"])  # empty before the controller ran
        error = np.abs(law - s["steer_torque"])[logged]
        assert logged.sum() > 8000
        assert np.mean(error < 1e-4) >= 0.99, entry.name
        # The steer-into-lean law alone (sbw2024's) is far from the command: the feedback matters.
        plain = (13.0 - 2.0 * run.speed()) * s["roll_rate"]
        assert np.median(np.abs(plain - s["steer_torque"])[logged]) > 100 * np.median(error)


def test_unknown_builtin_name_lists_the_builtin_names():
    with pytest.raises(BicycleFileError) as caught:
        load_bicycle("benchmrk")
    message = str(caught.value)
    assert "\n" not in message and message.startswith("benchmrk:")
    for name in builtin_names():
        assert name in message


# --- writing and reading TOML -------------------------------------------------------------


def _full_bicycle() -> Bicycle:
    parameters = dict(load_bicycle("benchmark").parameters)
    # Floats whose shortest repr has 17 digits, and extremes, must survive exactly.
    parameters |= {"c": 0.1 + 0.2, "IBxz": 2.4000000000000004, "zB": -0.9 * (1 + 2**-52)}
    return Bicycle(
        parameters,
        name="test bike",
        description='quotes " and unicode é',
        uncertainty={"c": 0.001, "mB": 1 / 3},
        extensions=Extensions(
            steer_damping=0.3,
            steer_inertia=0.01,
            speed_scale=1.05,
            payload=Payload(mass=6.0, x=0.05, z=-0.75),
            tyre_compliance=TyreCompliance(11.5, 0.57, 0.15, pneumatic_trail=0.03),
        ),
        controller=Controller(
            steer={"roll_rate": (13.0, -2.0), "steer": (0.5,)}, roll={"roll": (-1.0, 0.0, 0.1)}
        ),
    )


def test_toml_round_trip_is_exact(tmp_path):
    bicycle = _full_bicycle()
    path = tmp_path / "bike.toml"
    write_bicycle_toml(bicycle, path)
    again = read_bicycle_toml(path)
    assert again == bicycle
    assert again.parameters["c"] == 0.1 + 0.2
    assert again.source == str(path)
    # Writing what was read gives the same bytes.
    second = tmp_path / "again.toml"
    write_bicycle_toml(again, second)
    assert second.read_bytes() == path.read_bytes()


@pytest.mark.parametrize("name", builtin_names())
def test_builtin_bicycles_round_trip(tmp_path, name):
    bicycle = load_bicycle(name)
    write_bicycle_toml(bicycle, tmp_path / f"{name}.toml")
    assert load_bicycle(tmp_path / f"{name}.toml") == bicycle


def test_default_tables_are_not_written(tmp_path):
    path = tmp_path / "plain.toml"
    write_bicycle_toml(load_bicycle("benchmark"), path)
    text = path.read_text(encoding="utf-8")
    for table in ("[uncertainty]", "[extensions", "[controller"):
        assert table not in text
    partial = _full_bicycle().with_extensions(payload=None, tyre_compliance=None, speed_scale=1.0)
    write_bicycle_toml(partial, path)
    text = path.read_text(encoding="utf-8")
    assert "speed_scale" not in text and "payload" not in text and "steer_damping" in text


def test_writing_over_the_source_file_is_refused(tmp_path, benchmark_file_text, write_file):
    path = write_file("bike.toml", benchmark_file_text)
    with pytest.raises(InputError, match="refusing to write output over input file"):
        write_bicycle_toml(read_bicycle_toml(path), path)
    assert path.read_text(encoding="utf-8") == benchmark_file_text


def test_name_defaults_to_the_file_stem(benchmark_file_text, write_file):
    text = re.sub(r"(?m)^name = .*$", "", benchmark_file_text)
    assert read_bicycle_toml(write_file("my_bike.toml", text)).name == "my_bike"


def test_a_single_number_is_a_constant_gain(benchmark_file_text, write_file):
    text = benchmark_file_text + "\n[controller.roll]\nsteer = 2.5\n"
    controller = read_bicycle_toml(write_file("bike.toml", text)).controller
    assert controller.roll == {"steer": (2.5,)}
    assert controller.feedback_coefficients()[0][0, 1] == 2.5


# --- BicycleParameters text files ---------------------------------------------------------

# In the layout of BicycleParameters' data/bicycles/<Name>/Parameters/<Name>Benchmark.txt:
# "name = value+/-uncertainty" lines (also "name = value"); values of the benchmark bicycle,
# uncertainties made up for the test.
_TEXT_FILE = """\
IBxx = 9.2+/-0.05
IBxz = 2.4+/-0.0
IByy = 11.0+/-0.1
IBzz = 2.8+/-0.02
IFxx = 0.1405+/-0.0
IFyy = 0.28+/-0.0

IHxx = 0.05892+/-0.0
IHxz = -0.00756+/-0.0
IHyy = 0.06+/-0.0
IHzz = 0.00708+/-0.0
IRxx = 0.0603+/-0.0
IRyy = 0.12+/-0.0
c = 0.08+/-0.0016907620071
g = 9.81
lam = 0.314159265358979323846+/-0.00349065850399
mB = 85.0+/-0.02
mF = 3.0+/-0.02
mH = 4.0+/-0.02
mR = 2.0+/-0.02
rF = 0.35+/-0.000122426879301
rR = 0.3+/-0.000122426879301
w = 1.02+/-0.002
xB = 0.3+/-0.00284415365691
xH = 0.9+/-0.00503272487149
zB = -0.9+/-0.00341340590315
zH = -0.7+/-0.00253087563355
"""


def test_benchmark_text_file_is_read(write_file):
    path = write_file("TestbikeBenchmark.txt", _TEXT_FILE)
    bicycle = read_benchmark_txt(path)
    assert bicycle.name == "Testbike"
    assert bicycle.parameters == load_bicycle("benchmark").parameters
    assert bicycle.uncertainty["c"] == 0.0016907620071
    assert bicycle.uncertainty["mB"] == 0.02
    assert "IBxz" not in bicycle.uncertainty  # zero uncertainty is no uncertainty
    assert "g" not in bicycle.uncertainty
    assert load_bicycle(path) == bicycle


@pytest.mark.parametrize(
    ("old", "new", "pattern"),
    [
        ("c = 0.08+/-0.0016907620071", "c = 0.08 +- 0.001", r"line 14: expected 'name = value'"),
        ("c = 0.08+/-0.0016907620071", "c = 2*0.04", r"line 14: expected"),
        ("g = 9.81", "g = 9.81\nc = 0.08", r"line 16: 'c' given twice"),
        ("g = 9.81", "gravity = 9.81", r"unknown key 'gravity' in the file"),
        ("mB = 85.0+/-0.02\n", "", r"missing key in the file: mB"),
    ],
    ids=["bad-separator", "expression", "duplicate", "unknown-key", "missing-key"],
)
def test_bad_benchmark_text_files(write_file, old, new, pattern):
    assert old in _TEXT_FILE
    path = write_file("BadBenchmark.txt", _TEXT_FILE.replace(old, new))
    with pytest.raises(BicycleFileError, match=pattern) as caught:
        load_bicycle(path)
    assert str(caught.value).startswith(f"{path}: ") and "\n" not in str(caught.value)


# --- bad TOML files -----------------------------------------------------------------------


def _set(key: str, value: str) -> tuple[str, str]:
    """Edit replacing the line that sets `key` (first match) by ``key = value``."""
    return (rf"(?m)^{key} = .*$", f"{key} = {value}")


def _drop(key: str) -> tuple[str, str]:
    return (rf"(?m)^{key} = .*\n", "")


_BAD_FILES = [
    # id, edit (regex, replacement) or appended text, error class, message pattern
    (
        "syntax-error",
        _set("w", "1.02 1"),
        BicycleFileError,
        r"TOML syntax error: .*\(at line 11, column 10\)$",
    ),
    ("unclosed-table", "\n[extensions\n", BicycleFileError, r"TOML syntax error"),
    (
        "unknown-parameter",
        _set("mB", "85.0\nmb = 1.0"),
        BicycleFileError,
        r"unknown key 'mb' in \[parameters\] \(did you mean 'mB'\?\)",
    ),
    (
        "unknown-top-level",
        "\n[matrices]\nM = 1\n",
        BicycleFileError,
        r"unknown key 'matrices' in the top level",
    ),
    (
        "unknown-uncertainty",
        "\n[uncertainty]\ntrail = 0.001\n",
        BicycleFileError,
        r"unknown key 'trail' in \[uncertainty\]",
    ),
    (
        "unknown-extension",
        "\n[extensions]\nsteer_dampng = 0.1\n",
        BicycleFileError,
        r"unknown key 'steer_dampng' in \[extensions\] \(did you mean 'steer_damping'\?\)",
    ),
    (
        "unknown-payload-key",
        "\n[extensions.payload]\nmass = 1.0\nx = 0.0\nz = -1.0\ny = 0\n",
        BicycleFileError,
        r"unknown key 'y' in \[extensions.payload\]",
    ),
    (
        "unknown-controller-state",
        "\n[controller.steer]\nlean_rate = [1.0]\n",
        BicycleFileError,
        r"unknown key 'lean_rate' in \[controller.steer\]",
    ),
    (
        "unknown-controller-table",
        "\n[controller.yaw]\nroll = [1.0]\n",
        BicycleFileError,
        r"unknown key 'yaw' in \[controller\]",
    ),
    ("missing-parameter", _drop("mB"), BicycleFileError, r"missing key in \[parameters\]: mB$"),
    (
        "missing-parameters",
        (r"(?m)^\[parameters\].*\n", "[bicycle]\n"),
        BicycleFileError,
        r"unknown key 'bicycle' in the top level",
    ),
    (
        "missing-payload-key",
        "\n[extensions.payload]\nmass = 1.0\nx = 0.0\n",
        BicycleFileError,
        r"missing key in \[extensions.payload\]: z",
    ),
    (
        "missing-tyre-key",
        "\n[extensions.tyre_compliance]\ncornering_stiffness = 11.5\ncamber_stiffness = 0.57\n",
        BicycleFileError,
        r"missing key in \[extensions.tyre_compliance\]: relaxation_length",
    ),
    (
        "string-value",
        _set("c", '"0.08"'),
        BicycleFileError,
        r"'c' in \[parameters\] must be a number, got a string \('0.08'\)",
    ),
    (
        "expression",
        _set("c", '"0.04 * 2"'),
        BicycleFileError,
        r"'c' in \[parameters\] must be a number, got a string",
    ),
    (
        "boolean-value",
        _set("mB", "true"),
        BicycleFileError,
        r"'mB' in \[parameters\] must be a number, got a boolean",
    ),
    (
        "array-value",
        _set("mB", "[85.0]"),
        BicycleFileError,
        r"'mB' in \[parameters\] must be a number, got an array",
    ),
    (
        "extensions-not-table",
        (r"(?m)^\[parameters\]", "extensions = 3\n[parameters]"),
        BicycleFileError,
        r"\[extensions\] must be a table, got a number",
    ),
    (
        "controller-not-table",
        (r"(?m)^\[parameters\]", 'controller = "none"\n[parameters]'),
        BicycleFileError,
        r"\[controller\] must be a table, got a string",
    ),
    (
        "gain-not-numbers",
        '\n[controller.steer]\nroll_rate = [13.0, "-2 v"]\n',
        BicycleFileError,
        r"'roll_rate' in \[controller.steer\] must be a non-empty array",
    ),
    (
        "empty-gain",
        "\n[controller.steer]\nroll_rate = []\n",
        BicycleFileError,
        r"'roll_rate' in \[controller.steer\] must be a non-empty array",
    ),
    ("name-not-string", _set("name", "3"), BicycleFileError, r"'name' in the top level must be"),
    ("negative-mass", _set("mB", "-85.0"), ParameterError, r"mB = -85 must not be negative"),
    ("negative-radius", _set("rF", "-0.35"), ParameterError, r"rF = -0.35 must not be negative"),
    ("point-wheel-spinning", _set("rF", "0.0"), ParameterError,
     r"rF = 0 \(a point front wheel\) needs IFyy = 0: a wheel of zero radius spins infinitely fast"),
    ("implausible-mass", _set("mB", "1e300"), ParameterError,
     r"mB = 1e\+300 kg is beyond 100000 kg: not a bicycle \(a unit or typing error\?\)"),
    ("implausible-length", _set("w", "1020.0"), ParameterError, r"w = 1020 m is beyond 100 m"),
    (
        "not-positive-definite",
        _set("IBxz", "10.0"),
        ParameterError,
        r"rear frame inertia \(IBxx, IByy, IBzz, IBxz\) is not positive semi-definite",
    ),
    (
        "negative-wheel-inertia",
        _set("IFxx", "-0.1405"),
        ParameterError,
        r"front wheel inertia \(IFxx, IFyy\) is not positive semi-definite",
    ),
    ("nan", _set("c", "nan"), ParameterError, r"c = nan is not finite"),
    ("inf", _set("mB", "inf"), ParameterError, r"mB = inf is not finite"),
    (
        "tilt-out-of-range",
        _set("lam", "1.6"),
        ParameterError,
        r"lam = 1.6 must be in \(-pi/2, pi/2\)",
    ),
    (
        "negative-uncertainty",
        "\n[uncertainty]\nc = -0.001\n",
        ParameterError,
        r"uncertainty of c = -0.001 must be finite and >= 0",
    ),
    (
        "huge-uncertainty",
        "\n[uncertainty]\nc = 1e300\n",
        ParameterError,
        r"uncertainty of c = 1e\+300 m is beyond 100 m: not a bicycle's",
    ),
    (
        "huge-angle-uncertainty",
        "\n[uncertainty]\nlam = 4.0\n",
        ParameterError,
        r"uncertainty of lam = 4 rad is beyond 3.142 rad",
    ),
    (
        "zero-speed-scale",
        "\n[extensions]\nspeed_scale = 0.0\n",
        ParameterError,
        r"extension speed_scale = 0 must be finite and > 0",
    ),
    (
        "negative-steer-inertia",
        "\n[extensions]\nsteer_inertia = -0.01\n",
        ParameterError,
        r"extension steer_inertia = -0.01 must be finite and >= 0",
    ),
    (
        "zero-relaxation",
        "\n[extensions.tyre_compliance]\ncornering_stiffness = 11.5\n"
        "camber_stiffness = 0.57\nrelaxation_length = 0.0\n",
        ParameterError,
        r"extension relaxation_length = 0 must be finite and > 0",
    ),
    (
        "payload-mass",
        "\n[extensions.payload]\nmass = 0.0\nx = 0.0\nz = -1.0\n",
        ParameterError,
        r"extension payload mass = 0 must be finite and > 0",
    ),
    (
        "nan-gain",
        "\n[controller.steer]\nroll_rate = [nan]\n",
        ParameterError,
        r"controller.steer.roll_rate has a coefficient that is not finite",
    ),
]


@pytest.mark.parametrize(
    ("edit", "error", "pattern"),
    [case[1:] for case in _BAD_FILES],
    ids=[case[0] for case in _BAD_FILES],
)
def test_bad_bicycle_files(benchmark_file_text, write_file, edit, error, pattern):
    if isinstance(edit, str):
        text = benchmark_file_text + edit
    else:
        text, count = re.subn(edit[0], edit[1], benchmark_file_text, count=1)
        assert count == 1, "the edit did not apply"
    path = write_file("bad.toml", text)
    with pytest.raises(error, match=pattern) as caught:
        load_bicycle(path)
    message = str(caught.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: ")
    assert caught.value.source == str(path)
    assert path.read_text(encoding="utf-8") == text  # the input is never touched


def test_all_physical_problems_are_reported_at_once(benchmark_file_text, write_file):
    text = re.sub(r"(?m)^mB = .*$", "mB = -1.0", benchmark_file_text)
    text = re.sub(r"(?m)^lam = .*$", "lam = 2.0", text)
    with pytest.raises(ParameterError) as caught:
        load_bicycle(write_file("bad.toml", text))
    assert "mB = -1 must not be negative; lam = 2 must be in" in str(caught.value)


def test_unreadable_files(tmp_path, write_file):
    with pytest.raises(BicycleFileError, match="no such file or built-in bicycle"):
        load_bicycle(tmp_path / "missing.toml")
    with pytest.raises(BicycleFileError, match="cannot read file"):
        read_bicycle_toml(tmp_path / "missing.toml")
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"\xff\xfe\x00name")
    with pytest.raises(BicycleFileError, match="not a UTF-8 text file"):
        load_bicycle(binary)


# --- validation ---------------------------------------------------------------------------


def test_validate_accepts_a_plain_mapping_and_names_missing_and_unknown_keys():
    parameters = dict(load_bicycle("benchmark").parameters)
    assert validate(parameters).ok
    del parameters["w"]
    parameters["trail"] = 0.08
    problems = validate(parameters).problems
    assert "unknown parameter(s): trail" in problems
    assert "missing parameter(s): w" in problems


def test_missing_optional_inertias_only_skip_checks():
    parameters = dict(load_bicycle("benchmark").parameters)
    del parameters["IByy"]
    report = validate(parameters)
    assert report.ok
    assert report.warnings == ("IByy absent: rear frame inertia checks needing it were skipped",)
    # The in-plane part of the tensor is still checked.
    parameters["IBxz"] = 10.0
    assert not validate(parameters).ok


def test_triangle_inequality_within_rounding_is_a_warning():
    # A thin disc lies on the limit IFyy = 2 IFxx; values rounded to 3-4 digits may exceed it
    # by a fraction of a unit in the last digit.
    parameters = dict(load_bicycle("benchmark").parameters)
    parameters |= {"IFxx": 0.0644, "IFyy": 0.1289}
    report = validate(parameters)
    assert report.ok
    assert any("front wheel inertia" in w and "taken as rounding" in w for w in report.warnings)
    parameters["IFyy"] = 0.1288  # exactly on the limit: nothing to say
    assert validate(parameters) == validate(load_bicycle("benchmark").parameters)


def test_triangle_inequality_beyond_rounding_is_a_warning_stating_the_violation():
    # Measured inertias break it within their measurement error; the model is still meaningful.
    bicycle = load_bicycle("benchmark").with_parameters(IByy=12.5)  # principal 10 + 2 = 12
    report = validate(bicycle)
    assert report.ok
    (warning,) = report.warnings
    assert warning.startswith("rear frame inertia (IBxx, IByy, IBzz, IBxz) violates the triangle "
                              "inequality of principal moments by 0.5 kg m^2")
    assert "no uncertainty stated" in warning and "IByy does not enter the linear equations" in warning
    uncertain = dataclasses.replace(bicycle, uncertainty={"IByy": 0.5})
    assert "1.0 standard deviations of the stated uncertainties (0.5 kg m^2): within measurement error" in (
        validate(uncertain).warnings[0])
    # A wheel's moments both enter the equations.
    wheel = validate(load_bicycle("benchmark").with_parameters(IRyy=0.3))
    assert wheel.ok and "both of a wheel's moments enter the linear equations" in wheel.warnings[0]


def test_unusual_magnitudes_are_warnings_and_absurd_ones_problems():
    parameters = dict(load_bicycle("benchmark").parameters)
    assert validate(parameters | {"mB": 600.0}).warnings == (
        "mB = 600 kg is unusually large for a bicycle (above 500 kg)",)
    assert validate(parameters | {"g": 0.5}).warnings == ("g = 0.5 m/s^2 is unusually small (below 1 m/s^2)",)
    assert validate(parameters | {"IBxx": 2e6, "IBzz": 2e6}).problems[:2] == (
        "IBxx = 2e+06 kg m^2 is beyond 1e+06 kg m^2: not a bicycle (a unit or typing error?)",
        "IBzz = 2e+06 kg m^2 is beyond 1e+06 kg m^2: not a bicycle (a unit or typing error?)")


def test_what_no_rigid_bicycle_has_is_a_warning_not_a_problem():
    bicycle = load_bicycle("benchmark")
    below = validate(bicycle.with_parameters(zB=0.3))
    assert below.ok and below.warnings == (
        "zB = 0.3 m puts the rear frame's mass centre below the ground (z points down: a sign error?)",)
    massless = validate(bicycle.with_parameters(mH=0.0))  # the front frame keeps its inertia
    assert massless.ok and massless.warnings == (
        "mH = 0 with nonzero inertia (IHxx, IHyy, IHzz, IHxz): a body without mass has none",)
    damped = validate(bicycle.with_extensions(steer_damping=-0.5))
    assert damped.ok and "steer_damping = -0.5 is negative" in damped.warnings[0]
    # The two-mass-skate bicycle's massless wheels have no inertia: nothing to warn about.
    skate = Path(__file__).parent / "data" / "bicycleparameters" / "bicycles" / "TmsBenchmark.txt"
    assert validate(load_bicycle(skate)).warnings == ()
    batch = {k: np.full(3, v) for k, v in bicycle.parameters.items()} | {"zH": np.array([-0.7, 0.1, -0.7])}
    assert validate(batch).warnings == (
        "zH puts the front frame's mass centre below the ground (z points down: a sign error?) "
        "(in 1 of 3 sets, first at index 1)",)


def test_validate_broadcasts_over_parameter_sets():
    parameters = {k: np.full(5, v) for k, v in load_bicycle("benchmark").parameters.items()}
    assert validate(parameters).ok
    parameters["mB"] = np.array([85.0, -1.0, 85.0, -2.0, 85.0])
    parameters["c"] = 0.08  # scalars broadcast against arrays
    assert validate(parameters).problems == (
        "mB must not be negative (in 2 of 5 sets, first at index 1)",
    )


def test_check_physical_raises_one_line_with_the_source():
    bicycle = load_bicycle("benchmark").with_parameters(mR=-2.0, rR=-0.3)
    with pytest.raises(ParameterError) as caught:
        check_physical(bicycle, source="bike.toml")
    assert str(caught.value) == "bike.toml: rR = -0.3 must not be negative; mR = -2 must not be negative"
    assert check_physical(load_bicycle("benchmark")).ok


def test_non_numbers_and_bad_controller_states_are_problems():
    parameters = dict(load_bicycle("benchmark").parameters)
    parameters["c"] = "0.08"  # type: ignore[assignment]
    assert "c is not a number: '0.08'" in validate(parameters).problems
    assert "c is not a number: '0.08'" in validate(Bicycle(parameters)).problems
    parameters["c"] = True  # type: ignore[assignment]
    assert "c is not a number: True" in validate(Bicycle(parameters)).problems
    bicycle = load_bicycle("benchmark").with_controller(Controller(steer={"lean": (1.0,)}))
    assert "controller.steer: unknown state 'lean'" in validate(bicycle).problems


# --- data objects -------------------------------------------------------------------------


def test_bicycle_copies_its_inputs_and_helpers_return_new_objects():
    parameters = dict(load_bicycle("benchmark").parameters)
    bicycle = Bicycle(parameters)
    parameters["c"] = 1.0
    assert bicycle.parameters["c"] == 0.08
    changed = bicycle.with_parameters(c=0.1)
    assert changed.parameters["c"] == 0.1 and bicycle.parameters["c"] == 0.08
    with pytest.raises(ParameterError, match="unknown parameter"):
        bicycle.with_parameters(trail=0.1)
    damped = bicycle.with_extensions(steer_damping=0.2)
    assert damped.extensions.steer_damping == 0.2 and bicycle.extensions.is_base()
    assert not damped.extensions.is_base()


def test_empty_controller():
    assert Controller().is_empty()
    assert Controller().feedback_coefficients() == []
    assert not Controller(roll={"steer": (0.0,)}).is_empty()


def test_controller_feedback_rows_and_orders():
    controller = Controller(steer={"steer_rate": (1.0,)}, roll={"roll": (0.0, 0.0, 3.0)})
    f = controller.feedback_coefficients()
    assert len(f) == 3
    assert f[0][1, 3] == 1.0 and f[2][0, 0] == 3.0
    assert np.count_nonzero(np.stack(f)) == 2


def test_every_path_form_is_accepted(tmp_path):
    path = Path(tmp_path / "bike.toml")
    write_bicycle_toml(load_bicycle("benchmark"), str(path))
    assert load_bicycle(path) == load_bicycle(str(path)) == load_bicycle("benchmark")


def test_radii_of_gyration_no_part_of_a_bicycle_has():
    benchmark = load_bicycle("benchmark")
    # mB = 1e-3 kg with the benchmark's rear-frame inertia: a radius of gyration of 105 m (the
    # largest principal moment, 11 kg m^2), which only a body over 100 m across has.
    light = validate(benchmark.with_parameters(mB=1e-3))
    assert any(p.startswith("rear frame: a radius of gyration of 105 m") for p in light.problems), light.problems
    # 0.5 kg: 4.7 m, possible only for a body over 5 m across: a warning.
    unusual = validate(benchmark.with_parameters(mB=0.5))
    assert unusual.ok and any("radius of gyration of 4.69 m" in w for w in unusual.warnings)
    # The bicycles of the field are far inside both bounds; a point mass (no inertia) too.
    assert not [w for w in validate(benchmark).warnings if "gyration" in w]
    assert validate(benchmark.with_parameters(IRxx=0.0, IRyy=0.0, rR=0.0)).ok
    # In a batch, the rows are found (and a massless body is left to its own check).
    rows = validate_rows({**benchmark.parameters, "mB": np.array([85.0, 1e-3, 0.0])})
    assert rows[0] == "" and "radius of gyration" in rows[1] and "gyration" not in rows[2]
