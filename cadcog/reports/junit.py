"""JUnit XML for CI systems: one test case per checked requirement.

The format CI services read (GitHub Actions reporters, GitLab, Jenkins): a ``<testsuites>`` with
one ``<testsuite>`` whose ``<testcase>`` elements carry a ``<failure>`` when a requirement does
not hold. Written with :mod:`xml.etree.ElementTree`, which escapes every name and message.
"""

from __future__ import annotations

import re
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


#: Characters XML 1.0 cannot carry at all (control characters but tab, newline and return; the
#: surrogates; U+FFFE, U+FFFF): shown as ``\\xNN`` / ``\\uNNNN`` instead of making the file
#: not well-formed (a body name from a STEP file or a baseline can hold any of them). A
#: carriage return too: every XML reader turns it into a newline (end-of-line handling), so it
#: is shown as ``\\r`` rather than read back as another character.
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0d\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


def xml_text(text: str) -> str:
    """``text`` with the characters XML 1.0 forbids, and the carriage return, written as Python
    escapes.

    Examples
    --------
    >>> print(xml_text("bolt" + chr(1) + " ESC" + chr(27) + "[31m ok"))
    bolt\\x01 ESC\\x1b[31m ok
    """
    return _NOT_XML.sub(lambda m: repr(m.group(0))[1:-1], text)


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
    suite = xml_text(suite)
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
        tc = ET.SubElement(
            ts, "testcase", classname=f"cadcog.check.{suite}", name=xml_text(c.id), time="0"
        )
        text = xml_text(
            f"{c.title}: {c.value} (required {c.limit})" + (f"; {c.detail}" if c.detail else "")
        )
        if not c.passed:
            failure = ET.SubElement(tc, "failure", message=text, type="requirement")
            failure.text = text
        out = ET.SubElement(tc, "system-out")
        out.text = text
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
