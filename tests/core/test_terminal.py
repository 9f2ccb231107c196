"""What reaches a terminal: control characters from the user's files are shown as escapes,
never obeyed; JSON stays JSON."""

from __future__ import annotations

import json
import re

from hypothesis import given
from hypothesis import strategies as st

from cadcog.cli import main
from cadcog.core.terminal import printable

RAW = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x9f\ud800-\udfff]")


@given(st.text(alphabet=st.characters(codec=None)))
def test_nothing_raw_survives(text):
    shown = printable(text)
    assert not RAW.search(shown)
    for kept in "\n\t\r":  # lines, tabs and the status line's carriage return pass
        assert shown.count(kept) == text.count(kept)
    shown.encode("utf-8")  # a lone surrogate could not be written to a UTF-8 terminal


@given(
    st.dictionaries(
        st.text(alphabet=st.characters(codec=None)), st.text(alphabet=st.characters(codec=None))
    )
)
def test_json_through_it_is_the_same_json(obj):
    text = json.dumps(obj, ensure_ascii=False)
    assert json.loads(printable(text)) == obj


def test_a_file_name_with_an_escape_sequence_is_shown_not_obeyed(tmp_path, capsys):
    name = tmp_path / "sat\x1b[2J\x1b[31m.step"
    assert main(["massprops", str(name)]) == 2
    err = capsys.readouterr().err
    assert "\x1b" not in err and "\\u001b[2J" in err
