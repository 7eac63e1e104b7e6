"""Sphinx configuration of the whipple documentation (``docs/build`` runs it with warnings as errors).

The tutorial is a MyST-NB text notebook executed on every build, so its output cannot go stale;
the API reference is built from the docstrings (numpydoc); the command line's reference from
the parser itself (``_ext/cli_help.py``).
"""

import sys
from importlib.metadata import version as _version
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent / "_ext"))

project = "whipple"
author = "the whipple authors"
copyright = "the whipple authors, MIT licence"
release = _version("whipple")
version = release

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "cli_help",
]

# Files of the docs folder that are not pages: figure scripts, example inputs, build output.
exclude_patterns = ["_build", "figures", "examples", "**.ipynb_checkpoints", "jupyter_execute"]

# MyST: anchors for headings down to level 4, so that links such as page.md#a-heading resolve
# (and a broken one fails the build).
myst_heading_anchors = 4
myst_enable_extensions = ["dollarmath", "colon_fence"]

# The tutorial runs on every build (never from a cache): what it prints is what the code does.
nb_execution_mode = "force"
nb_execution_timeout = 600
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

autosummary_generate = True
autodoc_typehints = "none"  # numpydoc's sections carry the types, in words
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

html_theme = "furo"
html_title = f"whipple {release}"
