"""JUnit XML for CI systems: one test case per checked requirement.

The format CI services read (GitHub Actions reporters, GitLab, Jenkins): a ``<testsuites>`` with
one ``<testsuite>`` whose ``<testcase>`` elements carry a ``<failure>`` when a requirement does
not hold. Written with :mod:`xml.etree.ElementTree`, which escapes every name and message.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from typing import Protocol


class Case(Protocol):
    @property
    def id(self) -> str: ...

    @property
    def title(self) -> str: ...

    @property
    def value(self) -> str: ...

    @property
    def limit(self) -> str: ...

    @property
    def passed(self) -> bool: ...

    @property
    def detail(self) -> str: ...


def junit_xml(suite: str, cases: Sequence[Case], time_s: float = 0.0) -> str:
    """The JUnit XML text of ``cases`` as one suite named ``suite``.

    Examples
    --------
    >>> from types import SimpleNamespace as C
    >>> xml = junit_xml("sat", [C(id="mass.max", title="mass", value="2 kg", limit="≤ 3 kg",
    ...                          passed=False, detail="a <b> & c")])
    >>> 'failures="1"' in xml and "a &lt;b&gt; &amp; c" in xml
    True
    """
    failures = sum(1 for c in cases if not c.passed)
    root = ET.Element(
        "testsuites", name="cadcog check", tests=str(len(cases)), failures=str(failures)
    )
    ts = ET.SubElement(
        root,
        "testsuite",
        name=suite,
        tests=str(len(cases)),
        failures=str(failures),
        errors="0",
        skipped="0",
        time=f"{time_s:.3f}",
    )
    for c in cases:
        tc = ET.SubElement(ts, "testcase", classname=f"cadcog.check.{suite}", name=c.id, time="0")
        text = f"{c.title}: {c.value} (required {c.limit})" + (f"; {c.detail}" if c.detail else "")
        if not c.passed:
            failure = ET.SubElement(tc, "failure", message=text, type="requirement")
            failure.text = text
        out = ET.SubElement(tc, "system-out")
        out.text = text
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
