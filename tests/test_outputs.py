"""Outputs that cannot be written, figure formats, and sizes a user can type.

Every failure to write is an OutputError naming the file the user asked for (never a temporary
file) and leaves nothing behind; every size a user can type is handled in bounded memory or
refused up front.
"""

from __future__ import annotations

import re
import time
from pathlib import Path

import numpy as np
import pytest

from whipple.atomic import atomic_path, check_writable, write_text_atomic
from whipple.cli import main
from whipple.errors import OutputError
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle
from whipple.simulation.scenario import MAX_SAMPLES, RunScenario, ScenarioError
from whipple.stability.critical import critical_speeds
from whipple.stability.eigen import MAX_SPEED, eigen_analysis, tracking_grid

PNG = b"\x89PNG\r\n\x1a\n"


def _locked(tmp_path: Path) -> Path:
    """A folder that refuses new files (chmod 555; /sys for a user who ignores modes)."""
    folder = tmp_path / "locked"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        (folder / "probe").write_text("")
    except OSError:
        return folder
    return Path("/sys")


@pytest.mark.parametrize("where", ["folder", "read-only", "parent is a file"])
def test_write_failures_name_the_target_and_leave_nothing(tmp_path, where):
    (tmp_path / "file").write_text("keep")
    target = {"folder": tmp_path, "read-only": _locked(tmp_path) / "out.csv",
              "parent is a file": tmp_path / "file" / "out.csv"}[where]
    before = sorted(tmp_path.rglob("*"))
    with pytest.raises(OutputError) as caught:
        write_text_atomic(target, "text")
    message = str(caught.value)
    assert message.startswith(f"{target}: ") and "\n" not in message
    assert ".out.csv." not in message  # not the temporary file
    assert sorted(tmp_path.rglob("*")) == before
    with pytest.raises(OutputError):
        check_writable(target)


def test_a_failure_inside_the_write_names_the_target(tmp_path):
    target = tmp_path / "out.json"
    with pytest.raises(OutputError, match=rf"^{target}: cannot write: No space left on device$"):
        with atomic_path(target):
            raise OSError(28, "No space left on device", "/tmp/.out.json.abc123")
    assert list(tmp_path.iterdir()) == []


def test_a_figure_without_a_suffix_is_png(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["stability", "benchmark", "--points", "51", "--plot", str(out)]) == 0
    assert out.read_bytes()[:8] == PNG
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_two_outputs_naming_one_file_are_refused(tmp_path, capsys):
    assert main(["stability", "benchmark", "--csv", str(tmp_path / "a"), "--plot", str(tmp_path / "a")]) == 2
    assert "--plot and --csv name the same file; one would replace the other" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_the_tracking_grid_stays_bounded_for_any_speed_range():
    assert tracking_grid(np.array([0.0, 10.0])).size == 1001  # unchanged below 100 m/s
    big = tracking_grid(np.array([0.0, MAX_SPEED]))
    assert big.size < 25_000 and np.all(np.diff(big) > 0)
    assert np.all(np.diff(big) <= np.maximum(0.0125, 1.01e-3 * big[1:]))
    with pytest.raises(ValueError, match="speeds beyond 1e\\+06 m/s are not analysed"):
        tracking_grid(np.array([0.0, 1e7]))


def test_check_and_stability_over_a_million_metres_per_second():
    model = linear_model(load_bicycle("benchmark"))
    started = time.perf_counter()
    wide = critical_speeds(model, 0.0, 1e6)
    result = eigen_analysis(model, np.linspace(0.0, 1e6, 1001))
    assert time.perf_counter() - started < 120  # a grid of 10^8 speeds would take hours
    narrow = critical_speeds(model, 0.0, 10.0)
    assert np.allclose(wide.stable_speed_ranges, narrow.stable_speed_ranges, rtol=0, atol=1e-9)
    assert np.all(np.isfinite(result.eigenvalues))


@pytest.mark.parametrize("changes", [{"sample_rate": 1e9}, {"duration": 1e300}, {"n_pushes": 10**9}])
def test_runs_too_large_to_simulate_are_refused_before_anything_is_allocated(changes):
    started = time.perf_counter()
    with pytest.raises(ScenarioError, match=re.escape(f"at most {MAX_SAMPLES:g} are simulated")):
        RunScenario(**changes)
    assert time.perf_counter() - started < 1.0
