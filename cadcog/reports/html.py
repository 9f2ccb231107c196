"""Small HTML helpers shared by cadcog's self-contained reports (no template engine).

Every value put into a page goes through :func:`html.escape` or a number format; figures are
embedded as PNG data URIs so that a page is one file that opens anywhere.
"""

from __future__ import annotations

import base64
import html
from pathlib import Path
from typing import Any

CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; max-width: 1240px;
       margin: 2em auto; padding: 0 1em; color: #222; line-height: 1.45; }
h1 { margin-bottom: 0.1em; } h2 { border-bottom: 2px solid #dde; padding-bottom: 0.2em;
       margin-top: 1.8em; }
.sub { color: #666; margin-top: 0; }
table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.92em; }
th, td { padding: 0.3em 0.7em; border-bottom: 1px solid #e4e4ea; text-align: right; }
th { background: #f3f4f8; } td.l, th.l { text-align: left; }
img { max-width: 100%; border: 1px solid #eee; margin: 0.5em 0; }
.ok { color: #17803d; font-weight: 600; } .bad { color: #b42318; font-weight: 600; }
.note { background: #f7f7fb; border-left: 4px solid #99a; padding: 0.5em 1em; font-size: 0.9em; }
.big { font-size: 1.25em; }
nav a { margin-right: 1em; }
.wide { overflow-x: auto; } td.l { overflow-wrap: break-word; }  /* ids break only if too long */
td { font-variant-numeric: tabular-nums; } .v { white-space: nowrap; }
"""


def img_tag(path: Path, alt: str) -> str:
    """An ``<img>`` with the PNG at ``path`` embedded as a data URI."""
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return f'<img src="data:image/png;base64,{data}" alt="{html.escape(alt)}">'


def num(value: float, digits: int = 4) -> str:
    """A number with ``digits`` decimals; round-off never shows as ``-0.0000``."""
    return f"{round(float(value), digits) + 0.0:.{digits}f}"


def vec(values: Any, digits: int = 3) -> str:
    """A vector as ``(x, y, z)`` with ``digits`` decimals."""
    return "(" + ", ".join(num(v, digits) for v in values) + ")"


def table(header: list[str], rows: list[list[str]], left: int = 1) -> str:
    """A table; cells are HTML already (escape them); the first ``left`` columns align left."""
    th = "".join(
        f'<th class="{"l" if i < left else ""}">{html.escape(h)}</th>' for i, h in enumerate(header)
    )
    body = "".join(
        "<tr>"
        + "".join(f'<td class="{"l" if i < left else ""}">{c}</td>' for i, c in enumerate(r))
        + "</tr>"
        for r in rows
    )
    return f"<table><thead><tr>{th}</tr></thead><tbody>{body}</tbody></table>"
