"""Headless Chromium: on each page of a built site (or an HTML report), the content column's
width and every code block or table whose content is wider than its box, at each window width.

Run: ``.venv/bin/mkdocs build --strict && python3 tools/check_pages.py $PWD/build/site 1400,1280``
(add page names to check some only; a report: its folder and ``index.html``). Needs Debian's
``chromium``. Prints one line per page and width: ``content=<px> || <overflowing elements>``
(nothing after ``||``: nothing is cut or hidden behind a scroll bar).
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

#: Injected before ``</body>``: measures after load, writes the result into an attribute.
PROBE = """<script>window.addEventListener('load', () => {
  const r = [];
  document.querySelectorAll('pre > code, table').forEach(e => {
    const box = e.closest('.md-typeset__scrollwrap') || e.parentElement;
    const room = Math.min(e.clientWidth, box.clientWidth);
    if (e.scrollWidth > room + 2) {
      const text = e.textContent.trim().slice(0, 50).replace(/\\s+/g, ' ');
      r.push(e.tagName + ':' + e.scrollWidth + '>' + room + ':' + text);
    }
  });
  const c = document.querySelector('.md-content__inner') || document.body;
  document.body.setAttribute('data-overflow', 'content=' + c.clientWidth + ' || ' + r.join(' | '));
});</script>"""

CHROMIUM = [
    "chromium",
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--virtual-time-budget=3000",
    "--dump-dom",
]


def main() -> None:
    site = Path(sys.argv[1]).resolve()
    widths = [int(w) for w in sys.argv[2].split(",")]
    pages = sys.argv[3:] or sorted(
        p.name for p in site.glob("*.html") if not p.name.startswith("_")
    )
    for page in pages:
        probe = site / f"_check_{page}"
        text = (site / page).read_text(encoding="utf-8")
        probe.write_text(text.replace("</body>", PROBE + "</body>"), encoding="utf-8")
        try:
            for w in widths:
                argv = [*CHROMIUM, f"--window-size={w},900", probe.as_uri()]
                dom = subprocess.run(argv, capture_output=True, text=True, timeout=120).stdout
                m = re.search(r'data-overflow="([^"]*)"', dom)
                print(f"{page} @{w}: {m.group(1) if m else 'NO RESULT'}")
        finally:
            probe.unlink()


if __name__ == "__main__":
    main()
