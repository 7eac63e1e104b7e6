"""A Sphinx directive that prints a ``whipple`` command's help, taken from the parser itself.

``.. whipple-help:: diagnose`` renders ``whipple diagnose --help``; without an argument, the
top-level help. The reference of the command line therefore cannot drift from the code.
"""

from __future__ import annotations

import os

from docutils import nodes
from sphinx.util.docutils import SphinxDirective


class WhippleHelp(SphinxDirective):
    """Render ``whipple [COMMAND] --help`` as a literal block."""

    optional_arguments = 1

    def run(self) -> list[nodes.Node]:
        from whipple.cli import build_parser

        command = self.arguments[0] if self.arguments else None
        previous = os.environ.get("COLUMNS")
        os.environ["COLUMNS"] = "100"  # argparse wraps to the terminal; the page has its own width
        try:
            parser = build_parser([command] if command else [])
            if command:
                parser = next(action for action in parser._subparsers._group_actions  # noqa: SLF001
                              if hasattr(action, "choices")).choices[command]
            text = parser.format_help()
        finally:
            if previous is None:
                os.environ.pop("COLUMNS", None)
            else:
                os.environ["COLUMNS"] = previous
        block = nodes.literal_block(text, text)
        block["language"] = "text"
        return [block]


def setup(app):
    """Register the directive."""
    app.add_directive("whipple-help", WhippleHelp)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
