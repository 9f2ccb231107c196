"""mkdocs hooks: the command-line reference, generated from cadcog's own parsers, and Sphinx
roles in docstrings shown as code.

``docs/cli.md`` holds the marker ``<!-- cli-reference -->``; at build time it becomes one section
per subcommand with its ``--help`` text, so the page can never drift from the code. The
docstrings use Sphinx roles (``:func:`x```, readable in ``help()``); mkdocstrings renders
numpydoc but not roles, so the role names are dropped from the HTML.
"""

from __future__ import annotations

import argparse
import os
import re
from typing import Any

MARKER = "<!-- cli-reference -->"
ROLE = re.compile(r":(?:class|func|mod|meth|attr|data|exc|obj):\s*<code>~?([^<]+)</code>")


def cli_reference() -> str:
    """Markdown: the top-level help, then each subcommand's, in the order ``cadcog -h`` lists."""
    from cadcog.cli._main import build_parser

    os.environ["COLUMNS"] = "88"  # argparse wraps help to the terminal width
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    parts = ["```text", parser.format_help().rstrip(), "```", ""]
    for name, command in sub.choices.items():
        parts += [f"## cadcog {name}", "", "```text", command.format_help().rstrip(), "```", ""]
    return "\n".join(parts)


def on_page_markdown(markdown: str, page: Any, **_: Any) -> str:
    if MARKER in markdown:
        return markdown.replace(MARKER, cli_reference())
    return markdown


def on_page_content(html: str, page: Any, **_: Any) -> str:
    return ROLE.sub(lambda m: f"<code>{m.group(1)}</code>", html)
