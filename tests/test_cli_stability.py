"""``whipple stability`` and ``whipple sweep``.

Reference values: benchmark weave and capsize speeds, Meijaard et al. (2007) Table 2(a).
"""

from __future__ import annotations

import csv
import json

import numpy as np

from whipple.cli import main
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle
from whipple.stability.critical import critical_speeds


def test_stability_writes_figure_and_table(tmp_path, capsys):
    plot, table = tmp_path / "eig.png", tmp_path / "eig.csv"
    assert main(["stability", "benchmark", "--plot", str(plot), "--csv", str(table), "--points", "201",
                 "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert abs(summary["weave_speed"] - 4.29238253634111) < 1e-12
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = list(csv.reader(table.open()))
    assert len(rows) == 202 and rows[0][0] == "speed_m_per_s"


def test_stability_refuses_to_overwrite_its_input(tmp_path, capsys):
    source = tmp_path / "bike.toml"
    source.write_text((tmp_path / "x").as_posix())  # content irrelevant: refused before reading
    assert main(["stability", str(source), "--csv", str(source)]) == 2
    assert "refusing" in capsys.readouterr().err


def test_sweep_matches_single_analyses_and_reports_bad_rows(tmp_path, capsys):
    sets = tmp_path / "sets.csv"
    trails = [0.02, 0.08, 0.12]
    sets.write_text("c,mB\n" + "".join(f"{c},85.0\n" for c in trails) + "0.08,-1.0\n")
    out = tmp_path / "out.csv"
    assert main(["sweep", str(sets), "-o", str(out), "--quiet"]) == 0
    rows = list(csv.DictReader(out.open()))
    assert len(rows) == 4
    for row, trail in zip(rows, trails, strict=False):
        expected = critical_speeds(linear_model(load_bicycle("benchmark").with_parameters(c=trail)))
        weave = float(row["weave_speed"]) if row["weave_speed"] else None
        if expected.weave_speed is None:
            assert weave is None
        else:
            assert np.isclose(weave, expected.weave_speed, rtol=0, atol=1e-10)
    assert rows[3]["weave_speed"] == "" and "mB" in rows[3]["problem"]


def test_sweep_bad_table_is_one_line_error(tmp_path, capsys):
    sets = tmp_path / "sets.csv"
    sets.write_text("c,trail\n0.1,0.2\n")
    assert main(["sweep", str(sets), "-o", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "trail" in err and str(sets) in err
    sets.write_text("c\nabc\n")
    assert main(["sweep", str(sets), "-o", str(tmp_path / "o.csv")]) == 2
    assert "not a number" in capsys.readouterr().err
