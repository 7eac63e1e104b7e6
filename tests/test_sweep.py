"""``whipple sweep`` in chunks, batched validation, and chunks on a Dask cluster.

The Dask tests run an in-process cluster (threads) and check that the output is the serial
output byte for byte.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import numpy as np
import pytest

from whipple import distributed
from whipple.cli import main
from whipple.model.parameters import load_bicycle, validate, validate_rows
from whipple.stability.critical import CriticalSpeedTable
from whipple.stability.sweep import (
    SweepTask,
    TableChunk,
    _range_cells,
    analyse_chunk,
    analyse_sets,
    read_parameter_table,
    table_chunks,
)

NAMES = ("c", "lam", "mB", "xB", "IBxx", "mH", "w")


def _table(path, rows: int, seed: int = 0, bad: tuple[int, ...] = ()) -> None:
    """Random variations of the benchmark bicycle, with a negative mass in rows `bad`."""
    base = load_bicycle("benchmark").parameters
    rng = np.random.default_rng(seed)
    values = np.array([[base[name] * np.exp(0.15 * rng.standard_normal()) for name in NAMES]
                       for _ in range(rows)])
    values[list(bad), 2] *= -1
    lines = [",".join(NAMES)] + [",".join(f"{x:.10g}" for x in row) for row in values]
    path.write_text("\n".join(lines) + "\n")


def test_validate_rows_equals_validate_one_by_one():
    base = load_bicycle("benchmark").parameters
    rng = np.random.default_rng(3)
    count = 400
    sets = {name: value * np.exp(0.8 * rng.standard_normal(count)) * np.where(rng.random(count) < 0.02, -1, 1)
            for name, value in base.items()}
    sets["mB"][5] = 1e300  # beyond the limits: overflows in the equations
    sets["rR"][6], sets["IRyy"][6] = 0.0, 0.0  # a point wheel
    sets["IRyy"][7] = 0.1  # ... with spin inertia
    sets["rR"][7] = 0.0
    rows = validate_rows(sets)
    one_by_one = tuple("; ".join(validate({k: v[row] for k, v in sets.items()}).problems) for row in range(count))
    assert rows == one_by_one
    assert 20 < sum(bool(row) for row in rows) < count  # both verdicts are exercised


def test_point_masses_singular_mass_matrix_found_among_bad_sets():
    # The mass-matrix check of validate() runs only when a set has no other problem; in a
    # batch, another set's problem must not hide it.
    base = load_bicycle("benchmark").parameters
    sets = {name: np.full(2, value) for name, value in base.items()}
    sets["mB"][0] = -1.0
    for name in ("IBxx", "IBzz", "IBxz", "IHxx", "IHzz", "IHxz", "IRxx", "IFxx", "IRyy", "IFyy"):
        sets[name][1] = 0.0
    for name in ("rR", "rF"):
        sets[name][1] = 0.0
    sets["mR"][1] = sets["mF"][1] = sets["mH"][1] = 0.0
    sets["xB"][1] = 0.0
    rows = validate_rows(sets)
    assert rows[1] == "; ".join(validate({k: v[1] for k, v in sets.items()}).problems)
    assert "mass matrix" in rows[1] and "mB" in rows[0]


def test_chunks_give_the_output_of_one_chunk(tmp_path, capsys):
    sets = tmp_path / "sets.csv"
    _table(sets, 9, bad=(4,))
    whole, chunked = tmp_path / "whole.csv", tmp_path / "chunked.csv"
    assert main(["sweep", str(sets), "-o", str(whole), "--quiet"]) == 0
    assert main(["sweep", str(sets), "-o", str(chunked), "--quiet", "--chunk", "2"]) == 0
    assert whole.read_bytes() == chunked.read_bytes()
    assert "analysed 8 of 9 parameter sets (1 not physical" in capsys.readouterr().out
    lines = whole.read_text().splitlines()
    assert lines[0] == ",".join(NAMES) + ",weave_speed,capsize_speed,stable_speed_ranges,problem"
    assert len(lines) == 10 and "mB" in lines[5].split(",")[-1]
    # The input cells are repeated exactly.
    table = read_parameter_table(sets)
    assert float(lines[3].split(",")[1]) == table.columns["lam"][2]


def test_result_rows_equal_the_critical_speed_objects(tmp_path):
    """The sweep's array path gives each row the speeds and ranges of :class:`CriticalSpeeds`.

    (To rounding: the array path solves Whipple-form models in closed form.)
    """
    sets = tmp_path / "sets.csv"
    _table(sets, 300, seed=3, bad=(7, 100))
    table = read_parameter_table(sets)
    names = tuple(table.columns)
    chunk = TableChunk(names, np.stack([table.columns[name] for name in names], axis=-1))
    base = load_bicycle("benchmark")
    rows = analyse_chunk(SweepTask(chunk, base, (0.0, 10.0))).text.splitlines()
    problems, critical = analyse_sets(chunk, base, (0.0, 10.0))
    assert len(rows) == 300 and sum(1 for result in critical if result is None) == 2
    for row, result, problem in zip(rows, critical, problems, strict=True):
        cells = row.split(",")[len(names):]
        if result is None:
            assert cells[:3] == ["", "", ""] and problem
            continue
        for cell, expected in zip(cells[:2], (result.weave_speed, result.capsize_speed), strict=True):
            assert (cell == "") if expected is None else float(cell) == pytest.approx(expected, rel=1e-12,
                                                                                      abs=0.0)
        ranges = [tuple(map(float, pair.split(":"))) for pair in cells[2].split(";") if pair]
        assert len(ranges) == len(result.stable_speed_ranges)
        for mine, theirs in zip(ranges, result.stable_speed_ranges, strict=True):
            assert mine == pytest.approx(theirs, rel=1e-12, abs=0.0)


def test_range_cells_join_a_models_ranges_in_order():
    # Models 0 and 3 have several stable ranges, 1 and 4 none.
    table = CriticalSpeedTable(np.full(5, np.nan), np.full(5, np.nan), np.array([0, 0, 2, 3, 3, 3]),
                               np.array([0.5, 3.0, 4.25, 1.0, 2.0, 7.5]), np.array([1.5, 9.0, 6.0, 1.5, 5.0, 10.0]))
    assert _range_cells(table, 5) == ["0.5:1.5;3.0:9.0", "", "4.25:6.0", "1.0:1.5;2.0:5.0;7.5:10.0", ""]
    empty = CriticalSpeedTable(np.full(2, np.nan), np.full(2, np.nan), np.zeros(0, dtype=np.intp),
                               np.zeros(0), np.zeros(0))
    assert _range_cells(empty, 2) == ["", ""]


def test_reader_parses_decimal_numbers_and_names_bad_cells(tmp_path):
    sets = tmp_path / "sets.csv"
    sets.write_text("# a comment\nc, mB\n\n0.08, 85\n 10e-2 ,\"90\"\n,\n0.1,1e1\n")
    table = read_parameter_table(sets)
    assert table.rows == 3 and table.columns["c"].tolist() == [0.08, 0.1, 0.1]
    assert table.columns["mB"].tolist() == [85.0, 90.0, 10.0]
    # float() would read these as 0.1 and 12.0; no table means them as numbers.
    for cell in ("1_0e-2", "\uff11\uff12"):
        sets.write_text(f"c,mB\n0.08,85\n{cell},85\n")
        with pytest.raises(ValueError, match=r"line 3, column c: not a number"):
            read_parameter_table(sets)
    sets.write_text("c,mB\n" + "0.08,85\n" * 5 + "0.08,inf\n")
    names, chunks = table_chunks(sets, rows=2)
    assert names == ("c", "mB")
    with pytest.raises(ValueError, match=r"line 7, column mB: not finite: 'inf'"):
        list(chunks)
    sets.write_text("c,mB\n0.08,85\n0.08\n")
    with pytest.raises(ValueError, match=r"line 3: 1 cells, header has 2"):
        read_parameter_table(sets)


def _messy_table(path, seed: int) -> list[list[float]]:
    """A table of plain rows among comments, blank lines, quoted and spaced cells and CRLF ends.

    Returns the rows' values as Python's ``float`` reads the cells (the reference).
    """
    rng = np.random.default_rng(seed)
    lines, expected = ["# made by a test", "c,mB,w"], []
    for _ in range(60):
        values = (0.08 * np.exp(0.1 * rng.standard_normal(3)) * [1.0, 1000.0, 13.0]).tolist()
        cells = [repr(x) for x in values]
        kind = rng.integers(12)
        if kind == 0:
            lines.append("")
        elif kind == 1:
            lines.append("# " + ",".join(cells))
        if kind == 2:
            cells[1] = f'"{cells[1]}"'
        elif kind == 3:
            cells[0] = f" {cells[0]} "
        elif kind == 4:
            cells[2] = f"{values[2]:.3e}"
            values[2] = float(cells[2])
        lines.append(",".join(cells) + ("\r" if kind == 5 else ""))
        expected.append(values)
    path.write_text("\n".join(lines) + "\n", newline="")
    return expected


@pytest.mark.parametrize("rows", [1, 2, 7, 10_000])
def test_fast_and_general_readers_agree_on_messy_tables(tmp_path, rows):
    # Plain blocks take the fast reader, any other the general one: each chunk size mixes them
    # differently, and every one must read the values Python reads and repeat the rows as written.
    sets = tmp_path / "sets.csv"
    expected = _messy_table(sets, seed=rows)
    names, chunks = table_chunks(sets, rows=rows)
    chunks = list(chunks)
    assert names == ("c", "mB", "w")
    assert np.concatenate([chunk.values for chunk in chunks]).tolist() == expected
    written = [line.rstrip("\r") for line in sets.read_bytes().decode().split("\n")[2:]
               if line.strip() and not line.startswith("#")]
    assert [line for chunk in chunks for line in chunk.lines] == written


def test_bad_cell_after_plain_chunks_is_named_by_its_line(tmp_path):
    sets = tmp_path / "sets.csv"
    sets.write_text("c,mB\n# note\n" + "0.08,85\n" * 9 + "\n0.08,1e1\n")
    assert read_parameter_table(sets).columns["mB"].tolist() == [85.0] * 9 + [10.0]
    sets.write_text(sets.read_text() + "0.08,nan\n")
    for rows in (1, 3, 4, 100):
        with pytest.raises(ValueError, match=r"line 14, column mB: not finite: 'nan'"):
            list(table_chunks(sets, rows=rows)[1])


def test_bad_cell_late_in_the_table_leaves_no_output(tmp_path, capsys):
    sets, out = tmp_path / "sets.csv", tmp_path / "out.csv"
    sets.write_text("c\n" + "0.08\n" * 3 + "x\n")
    assert main(["sweep", str(sets), "-o", str(out), "--quiet", "--chunk", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "line 5, column c: not a number: 'x'" in err and str(sets) in err
    assert list(tmp_path.iterdir()) == [sets]


def test_dask_cluster_gives_the_serial_output(tmp_path, capsys):
    pytest.importorskip("distributed")
    from distributed import LocalCluster

    sets = tmp_path / "sets.csv"
    _table(sets, 7, seed=5, bad=(2,))
    serial, on_cluster = tmp_path / "serial.csv", tmp_path / "cluster.csv"
    assert main(["sweep", str(sets), "-o", str(serial), "--quiet", "--chunk", "3"]) == 0
    # Two threads in one worker process: tasks must not run in both at once (CasADi).
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None,
                      scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}) as cluster:
        assert main(["sweep", str(sets), "-o", str(on_cluster), "--quiet", "--chunk", "2",
                     "--scheduler", cluster.scheduler_address]) == 0
    assert serial.read_bytes() == on_cluster.read_bytes()


def test_map_ordered_keeps_the_order_on_a_local_cluster():
    pytest.importorskip("distributed")
    base = load_bicycle("benchmark")
    names, chunks = ("c",), [np.array([[0.08 + 0.01 * k]]) for k in range(5)]
    tasks = [SweepTask(TableChunk(names, values), base, (0.0, 10.0)) for values in chunks]
    with distributed.map_ordered(analyse_chunk, tasks, workers=2, processes=False) as results:
        texts = [result.text for result in results]
    assert texts == [analyse_chunk(task).text for task in tasks]


def test_cluster_option_errors_are_one_line(tmp_path, capsys):
    pytest.importorskip("distributed")
    sets = tmp_path / "sets.csv"
    sets.write_text("c\n0.08\n")
    assert main(["sweep", str(sets), "-o", str(tmp_path / "o.csv"), "--workers", "0"]) == 2
    assert capsys.readouterr().err.strip() == "whipple sweep: error: the number of workers must be at least 1, got 0"
    unreachable = "cannot reach the Dask scheduler at tcp://127.0.0.1:9 within 0.5 s"
    with pytest.raises(distributed.ClusterError, match=unreachable):
        distributed.map_ordered(str, [1], scheduler="tcp://127.0.0.1:9", connect_timeout=0.5)


@pytest.mark.slow
def test_an_unreachable_scheduler_is_one_line_and_writes_nothing(tmp_path, capsys):
    pytest.importorskip("distributed")
    sets = tmp_path / "sets.csv"
    sets.write_text("c\n0.08\n")
    assert main(["sweep", str(sets), "-o", str(tmp_path / "o.csv"), "--scheduler", "tcp://127.0.0.1:9"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in err
    assert not (tmp_path / "o.csv").exists()


def test_serial_sweep_does_not_import_dask(tmp_path):
    sets = tmp_path / "sets.csv"
    sets.write_text("c\n0.08\n")
    script = textwrap.dedent(f"""
        import sys
        import whipple.cli.sweep
        from whipple.cli import main
        assert main(["sweep", {str(sets)!r}, "-o", {str(tmp_path / "o.csv")!r}, "--quiet"]) == 0
        loaded = sorted(name for name in sys.modules if name.split(".")[0] in ("dask", "distributed"))
        assert not loaded, loaded
    """)
    subprocess.run([sys.executable, "-c", script], check=True, capture_output=True)


@pytest.mark.slow
def test_local_worker_processes_give_the_serial_output(tmp_path):
    pytest.importorskip("distributed")
    sets = tmp_path / "sets.csv"
    _table(sets, 6, seed=8, bad=(1,))
    serial, on_cluster = tmp_path / "serial.csv", tmp_path / "cluster.csv"
    assert main(["sweep", str(sets), "-o", str(serial), "--quiet"]) == 0
    assert main(["sweep", str(sets), "-o", str(on_cluster), "--quiet", "--chunk", "2", "--workers", "2"]) == 0
    assert serial.read_bytes() == on_cluster.read_bytes()
