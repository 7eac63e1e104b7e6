"""The ``whipple fit`` command (draft) and the run figures."""

from __future__ import annotations

import csv

import numpy as np
import pytest
from matplotlib.figure import Figure

from whipple.bundled import bundled_reference_windows, bundled_runs
from whipple.cli import main
from whipple.plotting_runs import plot_eigenvalues, plot_run, plot_weave_fit
from whipple.runs import read_run
from whipple.speedometer import speed_regression
from whipple.weavefit import fit_window
from whipple.windows import find_windows


@pytest.fixture(scope="module")
def run():
    return read_run(bundled_runs()[2])


def test_fit_command_lists_windows_and_compares(tmp_path, capsys):
    source = bundled_runs()[2]
    table = tmp_path / "fits.csv"
    code = main(["fit", str(source), "--compare", str(bundled_reference_windows()),
                 "--csv", str(table)])
    assert code == 0
    out = capsys.readouterr().out
    assert "reference windows matched: 9 of 9" in out
    rows = list(csv.DictReader(table.open()))
    assert rows and all(row["run"] == "eigen_normal_sil6.5n2_12.6kph" for row in rows)
    fitted = [row for row in rows if row["damping"]]
    assert len(fitted) >= 9
    # The weave of this controlled bicycle at 3.6 m/s: stable, about 1.3 Hz.
    assert all(-8 < float(row["damping"]) < 0 and 5 < float(row["frequency"]) < 11
               for row in fitted)
    assert all(3.4 < float(row["speed_mean"]) < 3.8 for row in rows)


def test_fit_command_with_hand_picked_windows(tmp_path, capsys):
    windows = tmp_path / "w.csv"
    windows.write_text("run,start,stop\neigen_normal_sil6.5n2_12.6kph,20.28,22.46\n")
    figures = tmp_path / "figures"
    assert main(["fit", str(bundled_runs()[2]), "--windows", str(windows),
                 "--plots", str(figures)]) == 0
    out = capsys.readouterr().out
    assert "1 window(s)" in out and "20.28-22.46" in out
    assert sorted(p.name for p in figures.iterdir()) == [
        "eigen_normal_sil6.5n2_12.6kph_run.png",
        "eigen_normal_sil6.5n2_12.6kph_window01_20.28s.png",
    ]


def test_fit_command_refuses_bad_input(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("time,steer_angle\n0,1\n")
    assert main(["fit", str(bad)]) == 2
    assert "missing roll_rate" in capsys.readouterr().err
    source = bundled_runs()[2]
    assert main(["fit", str(source), "--csv", str(source)]) == 2


def test_figures(run, tmp_path):
    search = find_windows(run)
    figure = plot_run(run, search.windows, rejected=search.rejected)
    assert isinstance(figure, Figure) and len(figure.axes) >= 4
    window = search.windows[0]
    fit = fit_window(run, window)
    speeds = speed_regression(run.time, run.speed(), window.start, window.stop)
    single = plot_weave_fit(fit, run, speeds)
    assert "λ =" in single.axes[0].get_title()
    overview = plot_eigenvalues([speeds], [fit], model=(np.linspace(0, 6, 7), np.full(7, -2 + 8j)))
    overview.savefig(tmp_path / "eigenvalues.png")
    assert (tmp_path / "eigenvalues.png").stat().st_size > 0
