"""The package's shape, as docs/architecture.md describes it, checked on the source itself.

Concept sub-packages import one way (model -> stability, simulation -> measurement -> diagnosis ->
cli), modules stay small, the CLI stays thin, and imports sit at the top of modules.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SOURCE = Path(__file__).resolve().parents[1] / "src" / "whipple"

#: Layer of each sub-package: a module may import from its own layer's packages only below it,
#: or from a lower layer. stability and simulation share a layer and do not import each other.
LAYERS = {"errors": -1, "number_text": -1, "atomic": 0, "input_files": 0, "distributed": 0, "model": 1, "stability": 2,
          "simulation": 2, "measurement": 3, "diagnosis": 4, "cli": 5}


def _modules() -> dict[str, Path]:
    return {".".join(path.relative_to(SOURCE.parent).with_suffix("").parts).removesuffix(".__init__"): path
            for path in SOURCE.rglob("*.py")}


def _imports(path: Path) -> list[tuple[str, bool]]:
    """(imported whipple module, whether at module level) for every import in a file."""
    tree = ast.parse(path.read_text())
    top = {id(node) for node in tree.body}
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("whipple"):
            found.append((node.module, id(node) in top))
        elif isinstance(node, ast.Import):
            found += [(alias.name, id(node) in top) for alias in node.names if alias.name.startswith("whipple")]
    return found


def _package(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def test_concept_subpackages_and_few_top_level_modules():
    packages = [p.name for p in SOURCE.iterdir() if (p / "__init__.py").exists() and p.name != "data"]
    assert {"model", "stability", "simulation", "measurement", "diagnosis"} <= set(packages)
    assert len(list(SOURCE.glob("*.py"))) <= 8


@pytest.mark.parametrize("module, path", sorted(_modules().items()))
def test_module_size(module, path):
    lines = len(path.read_text().splitlines())
    assert lines <= 600, f"{module}: {lines} lines"
    if module.startswith("whipple.cli."):
        assert lines < 250, f"{module}: {lines} lines"


def test_imports_flow_one_way_and_sit_at_the_top():
    problems = []
    for module, path in _modules().items():
        mine = _package(module)
        for target, at_top in _imports(path):
            if not at_top:
                problems.append(f"{module}: import of {target} inside a function")
            theirs = _package(target)
            if target == "whipple" or theirs in ("", "generated", "derivation", "data") or theirs == mine:
                continue
            if mine in LAYERS and theirs in LAYERS and LAYERS[theirs] >= LAYERS[mine]:
                problems.append(f"{module} imports {target}: against the direction of the layers")
    assert not problems, "\n".join(problems)


def test_no_import_cycles():
    modules = _modules()
    graph = {module: {target for target, _ in _imports(path) if target in modules}
             for module, path in modules.items()}
    state: dict[str, int] = {}

    def visit(node: str, trail: list[str]) -> None:
        state[node] = 1
        for nxt in graph[node]:
            if state.get(nxt) == 1:
                raise AssertionError("import cycle: " + " -> ".join(trail[trail.index(nxt):] + [nxt]))
            if nxt not in state:
                visit(nxt, trail + [nxt])
        state[node] = 2

    for module in graph:
        if module not in state:
            visit(module, [module])
