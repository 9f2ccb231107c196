"""Plain-text tables whose columns fit their contents (``massprops``, ``estimate --setup``...).

Examples
--------
>>> print(text_table(["pair", "mass"], [["+x_-30_-30 / -x_30_-30", "1.2"], ["a / b", "10"]]))
pair                    mass
+x_-30_-30 / -x_30_-30   1.2
a / b                     10
"""

from __future__ import annotations

from collections.abc import Sequence

#: Spaces between two columns.
GAP = 2


def text_table(
    headers: Sequence[str], rows: Sequence[Sequence[str]], align: str | None = None, indent: int = 0
) -> str:
    """Rows under headers, each column as wide as its widest cell.

    Parameters
    ----------
    headers : sequence of str
    rows : sequence of sequences of str
        Each as long as ``headers``.
    align : str, optional
        One letter per column: ``l`` (left) or ``r`` (right); default: the first column left,
        the others right.
    indent : int
        Spaces before every line.
    """
    n = len(headers)
    align = align or "l" + "r" * (n - 1)
    if len(align) != n or any(len(r) != n for r in rows):
        raise ValueError("every row and the alignment need one entry per header")
    widths = [max(len(str(c)) for c in col) for col in zip(headers, *rows, strict=True)]
    lines = []
    for cells in [headers, *rows]:
        parts = [
            str(c).ljust(w) if a == "l" else str(c).rjust(w)
            for c, w, a in zip(cells, widths, align, strict=True)
        ]
        lines.append((" " * indent + (" " * GAP).join(parts)).rstrip())
    return "\n".join(lines)
