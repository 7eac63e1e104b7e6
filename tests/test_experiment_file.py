"""Experiment files: groups of runs, each with its bicycle; the bundled one; every mistake one line."""

from __future__ import annotations

from pathlib import Path

import pytest

from whipple.errors import ExperimentFileError, InputError
from whipple.measurement.bundled import bundled_experiment, bundled_runs
from whipple.measurement.experiment_file import read_experiment
from whipple.model.parameters import load_bicycle

BENCHMARK_TOML = Path(__file__).parents[1] / "src" / "whipple" / "data" / "benchmark.toml"


def test_the_bundled_experiment_holds_both_bundled_experiments():
    experiment = read_experiment("bundled")
    assert experiment.source == bundled_experiment()
    assert [g.name for g in experiment.groups] == ["mm_off", "mm_on"]
    off, on = experiment.groups
    assert [p.name for p in off.runs] == [e.name for e in bundled_runs()]
    assert [p.name for p in on.runs] == [e.name for e in bundled_runs("model-matching-on")]
    assert off.bicycle == load_bicycle("sbw2024") and on.bicycle == load_bicycle("sbw2024-mm")
    assert off.bicycle_file is None and off.layout is None and off.windows is None
    assert experiment.group("mm_on") is on
    assert experiment.inputs() == (experiment.source, *off.runs, *on.runs)
    assert on.read_runs()[0].name == "eigen_mm_sil6.5n2_5.4kph"


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    """Run files (contents do not matter to the reader), a bicycle, a layout and a windows file."""
    for name in ("a/run9.csv", "a/run10.csv", "a/run1.csv", "b/x1.csv", "b/x2.csv.gz", "same/run1.csv"):
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text("time,roll_rate\n", encoding="utf-8")
    (tmp_path / "bike.toml").write_text(BENCHMARK_TOML.read_text(encoding="utf-8"), encoding="utf-8")
    (tmp_path / "layout.toml").write_text('[columns]\nroll_rate = "roll_rate"\n', encoding="utf-8")
    (tmp_path / "w.csv").write_text("run,start,stop\nx1,1,2\n", encoding="utf-8")
    return tmp_path


def _write(folder: Path, text: str, name: str = "experiment.toml") -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def test_paths_relative_to_the_file_absolute_as_given_patterns_in_natural_order(folder, monkeypatch):
    sub = folder / "sub"
    sub.mkdir()
    path = _write(sub, f"""
description = "two groups"
[[group]]
name = "slow-1"
bicycle = "../bike.toml"
runs = ["../a/run*.csv"]
layout = "../layout.toml"
[[group]]
name = "fast_2"
bicycle = "benchmark"
runs = "{folder / 'b' / 'x1.csv'}"
layout = "sbw-treadmill"
windows = "../w.csv"
""")
    monkeypatch.chdir(folder / "a")  # the working folder plays no part
    experiment = read_experiment(path)
    assert experiment.description == "two groups"
    slow, fast = experiment.groups
    assert [p.name for p in slow.runs] == ["run1.csv", "run9.csv", "run10.csv"]
    assert all(p.is_file() for p in slow.runs)
    assert slow.bicycle.parameters == load_bicycle("benchmark").parameters
    assert slow.bicycle_file == sub / "../bike.toml" and slow.layout_file == sub / "../layout.toml"
    assert slow.layout is not None and slow.layout.name == "layout"
    assert fast.runs == (folder / "b" / "x1.csv",)
    assert fast.layout is not None and fast.layout.name == "sbw-treadmill" and fast.layout_file is None
    assert fast.windows == sub / "../w.csv"
    assert fast.inputs() == (folder / "b" / "x1.csv", sub / "../w.csv")


def test_a_builtin_name_wins_over_a_file_of_that_name(folder):
    (folder / "benchmark").write_text("not a bicycle", encoding="utf-8")
    path = _write(folder, '[[group]]\nname = "g"\nbicycle = "benchmark"\nruns = "b/x1.csv"\n')
    assert read_experiment(path).groups[0].bicycle_file is None
    path = _write(folder, '[[group]]\nname = "g"\nbicycle = "./benchmark"\nruns = "b/x1.csv"\n')
    with pytest.raises(ExperimentFileError, match="group 1 \\('g'\\): bicycle: .*benchmark"):
        read_experiment(path)


GOOD = '[[group]]\nname = "g"\nbicycle = "benchmark"\nruns = ["a/*.csv"]\n'
OTHER = '[[group]]\nname = "h"\nbicycle = "benchmark"\nruns = ["b/*.csv*"]\n'


@pytest.mark.parametrize("text, words", [
    ("[[group]\nname = 1", "TOML syntax error"),
    ("", "no groups"),
    ('description = "only"\n', "no groups"),
    ("group = 3\n", "'group' must be [[group]] tables"),
    ('[group]\nname = "g"\n', "'group' must be [[group]] tables"),
    (GOOD + "colour = 1\n", "group 1 ('g'): unknown key 'colour'"),
    ("title = 'x'\n" + GOOD, "the top level: unknown key 'title'"),
    ("description = 3\n" + GOOD, "'description' must be a string, got an integer"),
    ('[[group]]\nname = "g"\nruns = "a/*.csv"\n', "group 1 ('g'): missing key bicycle"),
    ("[[group]]\n", "group 1: missing keys name, bicycle, runs"),
    (GOOD.replace('"g"', '"two words"'), "must be a word"),
    (GOOD.replace('"g"', '"../up"'), "must be a word"),
    (GOOD.replace('"g"', "7"), "'name' must be a non-empty string, got an integer"),
    (GOOD + GOOD.replace('"g"', '"G"'), "group 2 ('G'): the name 'G' is given twice"),
    (GOOD.replace('["a/*.csv"]', '["a/*.txt"]'), "runs pattern 'a/*.txt' matches no file"),
    (GOOD.replace('["a/*.csv"]', '["a/missing.csv"]'), "no such run file 'a/missing.csv'"),
    (GOOD.replace('["a/*.csv"]', '["a"]'), "run 'a' is not a regular file"),
    (GOOD.replace('["a/*.csv"]', "[]"), "'runs' must be a run file or pattern, or a non-empty list"),
    (GOOD.replace('["a/*.csv"]', "3"), "'runs' must be a run file or pattern"),
    (GOOD.replace('["a/*.csv"]', '["a/*.csv", "a/run1.csv"]'), "run1.csv is listed twice"),
    (GOOD.replace('["a/*.csv"]', '["a/run1.csv", "same/run1.csv"]'), "two runs are named run1"),
    (GOOD + OTHER.replace('["b/*.csv*"]', '["b/../a/run9.csv"]'), "is in groups 'g' and 'h'"),
    (GOOD.replace('"benchmark"', '"nobike.toml"'), "no such bicycle file 'nobike.toml'"),
    (GOOD.replace('"benchmark"', '"layout.toml"'), "bicycle: "),
    (GOOD + 'layout = "nolayout.toml"\n', "no such layout file 'nolayout.toml'"),
    (GOOD + 'layout = "bike.toml"\n', "layout: "),
    (GOOD + 'windows = "nowindows.csv"\n', "no such windows file 'nowindows.csv'"),
    (GOOD + "windows = 1.5\n", "'windows' must be a non-empty string, got a number"),
])
def test_every_mistake_is_one_line_naming_the_file_and_the_group(folder, text, words):
    path = _write(folder, text)
    with pytest.raises(ExperimentFileError) as raised:
        read_experiment(path)
    message = str(raised.value)
    assert "\n" not in message and message.startswith(f"{path}: ")
    assert words in message
    assert isinstance(raised.value, InputError)


def test_unreadable_experiment_files(folder):
    for path, words in ((folder / "none.toml", "no such experiment file"), (folder / "a", "not a file")):
        with pytest.raises(ExperimentFileError, match=words):
            read_experiment(path)
    latin = folder / "latin.toml"
    latin.write_bytes(b'description = "caf\xe9"\n')
    with pytest.raises(ExperimentFileError, match="not a UTF-8 text file"):
        read_experiment(latin)


def test_a_bicycle_that_fails_its_checks_names_the_group(folder):
    (folder / "heavy.toml").write_text(BENCHMARK_TOML.read_text(encoding="utf-8").replace("mB = 85.0", "mB = -1.0"),
                                       encoding="utf-8")
    path = _write(folder, GOOD.replace('"benchmark"', '"heavy.toml"'))
    with pytest.raises(ExperimentFileError, match="group 1 \\('g'\\): bicycle: .*heavy.toml"):
        read_experiment(path)
