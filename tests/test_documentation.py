"""The documentation's promises to a newcomer, checked on the files themselves.

The README is a first screen (under 100 lines, a command within its first 40, the test command
CI runs), ``docs/`` holds documentation rather than a dated notebook of experiments (those are
in ``benchmarks/results/``), and the command line says its version and what it does.
"""

from __future__ import annotations

import re
from importlib.metadata import version
from pathlib import Path

import pytest

from whipple.cli import main

ROOT = Path(__file__).resolve().parents[1]
#: An ISO date (2026-12-01) or a month of a year (2026-12): what marks an experiment's record.
DATE = re.compile(r"\b(19|20)\d\d-(0[1-9]|1[0-2])\b")


def _code_lines(text: str) -> list[tuple[int, str]]:
    """Return (line number, line) of the README's code: indented or fenced blocks."""
    found, fenced = [], False
    for number, line in enumerate(text.splitlines(), start=1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if fenced or (line.startswith("    ") and line.strip()):
            found.append((number, line.strip()))
    return found


def _headings(text: str) -> list[str]:
    """Return the Markdown headings of a text, outside its fenced code blocks."""
    headings, fence = [], None
    for line in text.splitlines():
        stripped = line.lstrip()
        if stripped.startswith(("```", "~~~")):
            mark = stripped[:3]
            fence = None if fence == mark else (fence or mark)
            continue
        if fence is None and re.match(r"#{1,6} ", line):
            headings.append(line)
    return headings


def test_readme_is_a_first_screen():
    text = (ROOT / "README.md").read_text()
    lines = text.splitlines()
    assert len(lines) < 100, f"README.md has {len(lines)} lines"
    commands = [(n, line) for n, line in _code_lines(text) if line.startswith(("pip ", "whipple ", "git "))]
    assert commands, "README.md shows no command"
    assert commands[0][0] <= 40, f"README.md's first command is on line {commands[0][0]}"


def test_readme_holds_the_test_command_ci_runs():
    ci = (ROOT / ".ci" / "run").read_text()
    command = 'pip install -e ".[test]" && pytest -q'
    assert command in ci.splitlines()
    assert command in [line for _, line in _code_lines((ROOT / "README.md").read_text())]


def test_no_dated_headings_in_docs():
    dated = [f"{path.relative_to(ROOT)}: {heading}" for path in sorted((ROOT / "docs").rglob("*.md"))
             if "_build" not in path.parts for heading in _headings(path.read_text()) if DATE.search(heading)]
    assert not dated, "dated headings belong in benchmarks/results/:\n" + "\n".join(dated)


def test_dated_heading_is_detected():
    assert _headings("# Rates of record (2026-12-02)\n```\n# 2026-12-02\n```\n") == ["# Rates of record (2026-12-02)"]
    assert DATE.search("## Rates (2026-11-27, late)")
    assert not DATE.search("## Meijaard et al. 2007")


def test_version_is_the_installed_one(capsys):
    with pytest.raises(SystemExit) as ended:
        main(["--version"])
    assert ended.value.code == 0
    assert capsys.readouterr().out.strip() == f"whipple {version('whipple')}"


def test_help_says_what_the_tool_does(capsys):
    with pytest.raises(SystemExit) as ended:
        main(["--help"])
    assert ended.value.code == 0
    out = capsys.readouterr().out
    assert "Whipple bicycle" in out and "measured data" in out
    for command in ("check", "diagnose", "evaluate", "fit", "sweep"):
        assert f"whipple {command} " in out


def test_api_reference_lists_every_public_name():
    import whipple

    api = (ROOT / "docs" / "reference" / "api.md").read_text()
    listed = set(re.findall(r"^   (whipple\.[\w.]+)$", api, re.M))
    missing = [name for name in whipple.__all__ if name != "__version__"
               and f"{whipple._HOME[name]}.{name}" not in listed]
    assert not missing, f"docs/reference/api.md misses: {missing}"


def test_exporting_modules_declare_all():
    import importlib

    import whipple

    problems = []
    for module_name, exported in whipple._EXPORTS.items():
        module = importlib.import_module(module_name)
        declared = getattr(module, "__all__", None)
        if declared is None:
            problems.append(f"{module_name} has no __all__")
            continue
        problems += [f"{module_name}.__all__ lacks {name}" for name in exported if name not in declared]
        problems += [f"{module_name}.__all__ names {name}, which it lacks" for name in declared
                     if not hasattr(module, name)]
    assert not problems, "\n".join(problems)
