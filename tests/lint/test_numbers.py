"""The whole-file number check that lets U304/U305 skip the per-attribute walk must never pass a
text that the walk would report (it may send a sound file to the walk: that only costs time)."""

from __future__ import annotations

import math

from hypothesis import given
from hypothesis import strategies as st
from lxml import etree

from armtool.lint.numbers import all_plain, numeric_texts, numeric_values, parse_floats

TOKENS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.floats(min_value=-1e6, max_value=1e6).map(lambda v: f"{v:.4e}"),
    st.integers(-(10**400), 10**400).map(str),
    st.sampled_from(["1e400", "-1e309", "nan", "inf", "1_0", "5.", ".5", "+.5e-3", "", "abc", "1,5", "0x1", "١"]),
)
TEXTS = st.lists(TOKENS, min_size=0, max_size=4).flatmap(
    lambda tokens: st.sampled_from([" ", "  ", "\t", "\n", " \u2003 "]).map(lambda sep: sep.join(tokens))
)


def _exactly(texts: dict[int, set[str]]) -> bool:
    for count, items in texts.items():
        for raw in items:
            values = parse_floats(raw)
            if values is None or len(values) != count or not all(map(math.isfinite, values)):
                return False
    return True


@given(st.sets(TEXTS, max_size=6), st.sets(TEXTS, max_size=6))
def test_all_plain_never_passes_a_bad_text(ones: set[str], threes: set[str]) -> None:
    texts = {1: ones, 3: threes}
    if all_plain(texts):
        assert _exactly(texts)


def test_all_plain_on_sound_and_broken_texts() -> None:
    assert all_plain({1: {"1", " -2.5e-3 "}, 3: {"0 0 1", "1.5707963\t0\n0"}})
    assert not all_plain({1: {"1 2"}, 3: set()})
    assert not all_plain({1: set(), 3: {"0 0"}})
    assert not all_plain({1: {"nan"}, 3: set()})
    assert all_plain({1: {"1e308"}, 3: set()})
    assert not all_plain({1: set(), 3: {"1e308 1e308 0"}})  # the sum overflows: looked at closer


def test_numeric_texts_hold_every_text_numeric_values_reads() -> None:
    root = etree.fromstring(
        b'<robot name="r"><link name="a"><inertial><mass value="1"/>'
        b'<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="x"/></inertial>'
        b'<visual><geometry><mesh filename="m.stl" scale="1 1"/></geometry></visual></link>'
        b'<joint name="j" type="revolute"><origin xyz="0 0 1" rpy="0 0 9"/><axis xyz="0 1 0"/>'
        b'<limit lower="-1" upper="1" effort="2" velocity="3"/><mimic joint="k" multiplier="2" offset="q"/></joint></robot>'
    )
    texts = numeric_texts(root)
    for _el, _attr, raw, count, _values in numeric_values(root):
        assert raw in texts[count]
    assert "m.stl" not in texts[1] | texts[3] and "k" not in texts[1] | texts[3]
