"""A rigid rider joined to the rear frame: BicycleParameters' rider files, --rider."""

from pathlib import Path

import numpy as np
import pytest

from whipple.cli import main
from whipple.errors import BicycleFileError, ParameterError
from whipple.model.assembly import linear_model, whipple_matrices
from whipple.model.bodies import Body
from whipple.model.parameters import load_bicycle
from whipple.model.rider import Rider, add_rider
from whipple.stability.critical import critical_speeds

DATA = Path(__file__).parent / "data" / "bicycleparameters"
BROWSER = DATA / "bicycles" / "BrowserBenchmark.txt"
JASON = DATA / "riders" / "JasonBrowserBenchmark.txt"

#: Browser with the rider Jason by BicycleParameters 1.5.2 (``Bicycle('Browser').add_rider('Jason')``
#: on these two files, run once outside the test suite): joined rear frame, value and std.
BICYCLEPARAMETERS_JOINED = {
    "mB": (81.86, 2.0000999975), "xB": (0.28909943411648203, 0.00037572974283),
    "zB": (-1.040292283210937, 0.0017155441437), "IBxx": (11.35822782891604, 0.02847515833),
    "IByy": (12.217332897646934, 0.028663068086), "IBzz": (3.1211248578428963, 0.0034001841243),
    "IBxz": (-1.9694273509701732, 0.015396371194),
}
#: Its canonical matrices (``Bicycle.canonical(nominal=True)``; K0 without g).
BICYCLEPARAMETERS_MATRICES = {
    "M": [[102.78260127, 1.53494742], [1.53494742, 0.2466622]],
    "C1": [[0.0, 26.39273019], [-0.44980954, 1.03541962]],
    "K0": [[-89.32195981, -1.74159477], [-1.74159477, -0.67769624]],
    "K2": [[0.0, 74.12484375], [0.0, 1.57005903]],
}


#: Rigid (its front frame given in two parts) with the rider Jason's file for it, by
#: BicycleParameters 1.5.2 (``Bicycle('Rigid').add_rider('Jason')``, run once outside the test
#: suite): canonical matrices (K0 without g); its eigenvalue sweep on a 0.001 m/s grid is
#: stable from 5.837 to 9.973 m/s.
RIGID_MATRICES = {
    "M": [[131.18824613409137, 2.3247699570623443], [2.3247699570623443, 0.2224098842462465]],
    "C1": [[0.0, 42.71441594725409], [-0.31500940197505306, 1.4280565239436263]],
    "K0": [[-115.98421906435794, -2.4039424007706027], [-2.4039424007706027, -0.7504678251076073]],
    "K2": [[0.0, 104.18968929280831], [0.0, 2.228586013983513]],
}


def test_rigid_with_its_rider_equals_bicycleparameters():
    bicycle = load_bicycle(DATA / "bicycles" / "RigidBenchmark.txt",
                           rider=DATA / "riders" / "JasonRigidBenchmark.txt")
    matrices = whipple_matrices(bicycle.parameters)
    for name, expected in RIGID_MATRICES.items():
        ours = getattr(matrices, name) / (bicycle.parameters["g"] if name == "K0" else 1.0)
        np.testing.assert_allclose(ours, expected, rtol=1e-8, atol=1e-8, err_msg=name)
    found = critical_speeds(linear_model(bicycle))
    assert 5.836 < found.weave_speed <= 5.837 and 9.973 <= found.capsize_speed < 9.974


def test_browser_with_jason_equals_bicycleparameters():
    bicycle = load_bicycle(BROWSER, rider=JASON)
    assert bicycle.name == "Browser + JasonBrowser"
    for key, (value, std) in BICYCLEPARAMETERS_JOINED.items():
        assert bicycle.parameters[key] == pytest.approx(value, rel=1e-12), key
        assert bicycle.uncertainty[key] == pytest.approx(std, rel=1e-6), key
    matrices = whipple_matrices(bicycle.parameters)
    g = bicycle.parameters["g"]
    for name, expected in BICYCLEPARAMETERS_MATRICES.items():
        ours = getattr(matrices, name) / (g if name == "K0" else 1.0)
        np.testing.assert_allclose(ours, expected, rtol=1e-8, atol=1e-8, err_msg=name)
    # The rest of the bicycle is untouched.
    alone = load_bicycle(BROWSER)
    assert {k: v for k, v in bicycle.parameters.items() if not k.endswith("B") and not k.startswith("IB")} == \
        {k: v for k, v in alone.parameters.items() if not k.endswith("B") and not k.startswith("IB")}


def test_browser_with_jason_stable_range_matches_a_dense_eigenvalue_sweep():
    bicycle = load_bicycle(BROWSER, rider=JASON)
    found = critical_speeds(linear_model(bicycle))
    speeds = np.linspace(0.0, 10.0, 2001)
    real = np.linalg.eigvals(linear_model(bicycle).state_matrix(speeds)).real.max(axis=1)
    stable = speeds[real < 0]
    assert found.weave_speed == pytest.approx(stable.min(), abs=0.006)
    assert found.capsize_speed == pytest.approx(stable.max(), abs=0.006)
    # BicycleParameters' own eigenvalue sweep (0.01 m/s grid) gives stability from 5.00 to 7.11 m/s.
    assert 4.99 < found.weave_speed < 5.00 and 7.11 < found.capsize_speed < 7.12


def _tensor(body: Body) -> np.ndarray:
    return np.array([[body.xx, 0.0, body.xz], [0.0, body.yy, 0.0], [body.xz, 0.0, body.zz]])


def test_joined_inertia_equals_three_dimensional_parallel_axes():
    rng = np.random.default_rng(3)
    bicycle = load_bicycle("benchmark")
    for _ in range(20):
        mass, x, z = rng.uniform(40, 110), rng.uniform(0.1, 0.6), rng.uniform(-1.4, -0.8)
        xx, zz = rng.uniform(3, 12), rng.uniform(1, 5)
        rider = Rider(Body(mass, x, z, xx, rng.uniform(3, 12), zz, rng.uniform(-0.9, 0.9) * np.sqrt(xx * zz)))
        joined = add_rider(bicycle, rider).parameters
        frame = Body(*(bicycle.parameters[k] for k in ("mB", "xB", "zB", "IBxx", "IByy", "IBzz", "IBxz")))
        total = frame.mass + mass
        centre = (frame.mass * np.array([frame.x, 0, frame.z]) + mass * np.array([x, 0, z])) / total
        inertia = np.zeros((3, 3))
        for body in (frame, rider.body):
            r = np.array([body.x, 0.0, body.z]) - centre
            inertia += _tensor(body) + body.mass * (r @ r * np.eye(3) - np.outer(r, r))
        assert joined["mB"] == pytest.approx(total)
        assert [joined["xB"], joined["zB"]] == pytest.approx([centre[0], centre[2]])
        assert [joined["IBxx"], joined["IByy"], joined["IBzz"], joined["IBxz"]] == pytest.approx(
            [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 2]])


def test_bicycle_without_IByy_keeps_it_absent():
    bicycle = load_bicycle("sbw2024", rider=JASON)
    assert "IByy" not in bicycle.parameters
    assert bicycle.parameters["mB"] == pytest.approx(load_bicycle("sbw2024").parameters["mB"] + 72.0)


def _rider_file(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "RiderBenchmark.txt"
    path.write_text(text, encoding="utf-8")
    return path


GOOD = "mB = 72.0+/-2.0\nxB = 0.29\nyB = 0.0\nzB = -1.11\nIBxx = 8.0\nIBxz = -1.9\nIByy = 8.1\nIBzz = 2.4\n"


@pytest.mark.parametrize("text, error, words", [
    (GOOD.replace("yB = 0.0", "yB = 0.05"), ParameterError, "plane of symmetry"),
    (GOOD.replace("mB = 72.0+/-2.0", "mB = -72.0"), ParameterError, "mass must be positive"),
    (GOOD.replace("IBxz = -1.9", "IBxz = -9.0"), ParameterError, "not the inertia of a body"),
    (GOOD.replace("IBzz = 2.4", "IBzz = nan"), ParameterError, "not a finite number: IBzz"),
    (GOOD.replace("zB = -1.11\n", ""), BicycleFileError, "missing key in the rider file: zB"),
    (GOOD + "w = 1.02\n", BicycleFileError, "a rider file holds only"),
    (GOOD + "mB = 70\n", BicycleFileError, "given twice"),
    ("mB: 72\n", BicycleFileError, "line 1"),
])
def test_bad_rider_files_are_one_line_errors(tmp_path, text, error, words):
    path = _rider_file(tmp_path, text)
    with pytest.raises(error) as raised:
        load_bicycle("benchmark", rider=path)
    message = str(raised.value)
    assert words in message and "\n" not in message and str(path) in message


def test_cli_rider_option(tmp_path, capsys):
    assert main(["check", str(BROWSER), "--rider", str(JASON)]) == 0
    out = capsys.readouterr().out
    assert "Browser + JasonBrowser" in out and "weave speed:   4.99" in out
    path = _rider_file(tmp_path, GOOD.replace("yB = 0.0", "yB = 0.2"))
    before = path.read_bytes()
    assert main(["stability", "benchmark", "--rider", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(path) in err[0] and "Traceback" not in err[0]
    assert path.read_bytes() == before
    # A bicycle file given as the rider, and a rider file given as the bicycle.
    assert main(["check", "benchmark", "--rider", str(BROWSER)]) == 2
    assert "a bicycle file" in capsys.readouterr().err
    assert main(["check", str(JASON)]) == 2
    assert "--rider" in capsys.readouterr().err
    # Outputs never go over the rider file.
    copy = tmp_path / "JasonBrowserBenchmark.txt"
    copy.write_bytes(JASON.read_bytes())
    assert main(["stability", "benchmark", "--rider", str(copy), "--csv", str(copy)]) == 2
    assert "refusing to write output over input file" in capsys.readouterr().err
    assert copy.read_bytes() == JASON.read_bytes()
