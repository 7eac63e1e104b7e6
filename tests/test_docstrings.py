"""Every function the package exports documents its parameters and its result (NumPy sections).

``whipple.__all__`` is the public API the reference pages are built from: a function there with
arguments has a ``Parameters`` section naming every argument, and every one has a ``Returns``
(or ``Yields``) section, so that a user reading the API reference learns what to pass and what
comes back.
"""

from __future__ import annotations

import inspect
import re

import pytest

import whipple

FUNCTIONS = [name for name in whipple.__all__ if inspect.isfunction(getattr(whipple, name, None))]
SECTION = re.compile(r"^(\w[\w ]*)\n-{3,}$", re.M)


def sections(doc: str) -> dict[str, list[str]]:
    """Return a NumPy docstring's sections: title to the lines below its underline."""
    found: dict[str, list[str]] = {}
    marks = list(SECTION.finditer(doc))
    for mark, following in zip(marks, [*marks[1:], None], strict=True):
        body = doc[mark.end():following.start() if following else len(doc)]
        found[mark.group(1)] = body.strip("\n").splitlines()
    return found


def documented_names(lines: list[str]) -> set[str]:
    """Names of the items of a Parameters section (unindented lines: ``a, b : type``)."""
    names: set[str] = set()
    for line in lines:
        if line and not line[0].isspace():
            names.update(name.strip() for name in line.split(":")[0].split(","))
    return names


def test_the_section_parser():
    doc = "Sum.\n\nParameters\n----------\na, b : float\n    Terms.\nc : int\n\nReturns\n-------\nfloat\n    The sum.\n"
    found = sections(doc)
    assert documented_names(found["Parameters"]) == {"a", "b", "c"}
    assert found["Returns"][0] == "float"


def test_functions_are_found():
    assert len(FUNCTIONS) > 30


@pytest.mark.parametrize("name", FUNCTIONS)
def test_numpy_sections(name):
    function = getattr(whipple, name)
    found = sections(inspect.getdoc(function) or "")
    taken = [p.name for p in inspect.signature(function).parameters.values()
             if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    if taken:
        assert "Parameters" in found, f"{name} takes {taken} but has no Parameters section"
        missing = [p for p in taken if p not in documented_names(found["Parameters"])]
        assert not missing, f"{name}: parameters not documented: {missing}"
    assert "Returns" in found or "Yields" in found, f"{name} has no Returns section"
