"""``cadcog/reports/junit.py``: any requirement's names and messages, whatever characters a STEP
file or a baseline gives them, make a well-formed JUnit file that says them back."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from types import SimpleNamespace

from hypothesis import example, given
from hypothesis import strategies as st

from cadcog.reports.junit import junit_xml, xml_text

TEXT = st.text(max_size=30)  # any code point: controls, surrogates, U+FFFE included


def _case(i, title, detail, passed):
    return SimpleNamespace(
        id=f"r{i}.{title}", title=title, value="2 kg", limit="≤ 3 kg", passed=passed, detail=detail
    )


@example("", [("", "\r", False)])  # a CR came back as a newline (XML's end-of-line handling)
@given(TEXT, st.lists(st.tuples(TEXT, TEXT, st.booleans()), max_size=5))
def test_any_names_make_well_formed_xml_that_counts_the_failures(suite, rows):
    cases = [_case(i, t, d, p) for i, (t, d, p) in enumerate(rows)]
    root = ET.fromstring(junit_xml(suite, cases, 1.5).encode("utf-8"))  # parses: well-formed
    (ts,) = root
    failed = [c for c in cases if not c.passed]
    assert root.get("tests") == ts.get("tests") == str(len(cases))
    assert root.get("failures") == ts.get("failures") == str(len(failed))
    assert ts.get("name") == xml_text(suite) and ts.get("time") == "1.500"
    for tc, c in zip(ts, cases, strict=True):
        assert tc.get("name") == xml_text(c.id)
        failure = tc.find("failure")
        assert (failure is None) == c.passed
        said = tc.find("system-out").text
        assert said.startswith(xml_text(f"{c.title}: 2 kg (required ≤ 3 kg)"))
        if failure is not None:
            assert failure.get("message") == said == failure.text


@given(TEXT)
def test_xml_text_keeps_what_reads_back_and_escapes_only_the_rest(text):
    out = xml_text(text)
    forbidden = [c for c in text if (ord(c) < 32 and c not in "\t\n") or 0xD800 <= ord(c) <= 0xDFFF
                 or c in "\ufffe\uffff"]  # fmt: skip
    if not forbidden:
        assert out == text
    assert not any(c in out for c in forbidden)
