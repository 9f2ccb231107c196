"""``cadcog/mass/materials.py``: a materials file's patterns match names as stated (``*`` any
text, ``?`` one character, every other character itself), and the first rule that matches a
body gives its material."""

from __future__ import annotations

from functools import cache

from hypothesis import example, given
from hypothesis import strategies as st

from cadcog.mass.materials import LIBRARY, MaterialMap, glob_match

NAME = st.text(alphabet="ab[]/.-_ ", max_size=8)
PATTERN = st.text(alphabet="ab[]/*?.", max_size=6)


def _reference(name: str, pattern: str) -> bool:
    """The stated rule, matched by hand (dynamic programming over both strings)."""

    @cache
    def m(i: int, j: int) -> bool:
        if j == len(pattern):
            return i == len(name)
        c = pattern[j]
        if c == "*":
            return m(i, j + 1) or (i < len(name) and m(i + 1, j))
        return i < len(name) and (c == "?" or c == name[i]) and m(i + 1, j + 1)

    return m(0, 0)


@example("bracket[2]", "bracket[2]")  # brackets are themselves, not a character class
@example("bracket2", "bracket[2]")
@example("a\nb", "a?b")  # a newline in an instance name is a character like any other
@given(NAME, PATTERN)
def test_glob_match_is_the_stated_rule(name, pattern):
    assert glob_match(name, pattern) == _reference(name, pattern)


@given(NAME)
def test_a_catch_all_matches_every_name_and_a_plain_pattern_only_itself(name):
    assert glob_match(name, "*")
    assert glob_match(name, name.replace("*", "").replace("?", "")) == (
        "*" not in name and "?" not in name
    )


@given(st.lists(st.tuples(PATTERN, st.sampled_from(sorted(LIBRARY))), max_size=5), NAME, NAME)
def test_the_first_rule_matching_the_body_or_an_assembly_above_it_wins(rules, own, parent):
    assignment = MaterialMap(tuple(rules)).assign([own, parent])
    first = next(((p, v) for p, v in rules if _reference(own, p) or _reference(parent, p)), None)
    if first is None:
        assert assignment is None
        return
    assert assignment is not None and assignment.rule == first[0]
    assert assignment.density_kg_m3 == LIBRARY[first[1]].density_kg_m3
