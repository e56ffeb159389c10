"""Which URDF attributes hold numbers, how many, and how to read and print them."""

from __future__ import annotations

import math
import re
from itertools import chain

from lxml import etree

# element tag -> {attribute: number of values}; only for elements below <link> or <joint>.
NUMERIC_ATTRS: dict[str, dict[str, int]] = {
    "origin": {"xyz": 3, "rpy": 3},
    "axis": {"xyz": 3},
    "limit": {"lower": 1, "upper": 1, "effort": 1, "velocity": 1},
    "safety_controller": {"soft_lower_limit": 1, "soft_upper_limit": 1, "k_position": 1, "k_velocity": 1},
    "dynamics": {"damping": 1, "friction": 1},
    "mimic": {"multiplier": 1, "offset": 1},
    "calibration": {"rising": 1, "falling": 1},
    "mass": {"value": 1},
    "inertia": {k: 1 for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")},
    "box": {"size": 3},
    "cylinder": {"radius": 1, "length": 1},
    "sphere": {"radius": 1},
    "mesh": {"scale": 3},
}


def parse_floats(text: str | None) -> list[float] | None:
    """Whitespace-separated numbers as urdfdom reads them; None if absent or any token is not a number."""
    if text is None:
        return None
    try:
        return list(map(float, text.split()))
    except ValueError:
        return None


_DECIMAL = re.compile(r"\s*[+-]?(\d*)\.(\d+)(?:[eE]([+-]?\d+))?\s*")


def half_unit_written(text: str) -> float:
    """Half a unit in the last digit of a decimal number as written (`5.23599` -> 5e-6,
    `1.5e-3` -> 5e-5): how far the exact value it stands for may lie. 0 for a number written
    without a fractional part (`3`, `1e2`), whose precision the text does not show."""
    match = _DECIMAL.fullmatch(text)
    if match is None:
        return 0.0
    exponent = int(match.group(3) or 0)
    return 0.5 * 10.0 ** (exponent - len(match.group(2)))


def fmt(value: float) -> str:
    """Short, exact-enough decimal for messages and fixes."""
    text = f"{value:.10g}"
    return "0" if text == "-0" else text


def numeric_values(root: etree._Element) -> list[tuple[etree._Element, str, str, int, list[float] | None]]:
    """(element, attribute, raw text, expected count, parsed values or None) for every numeric
    attribute under links and joints. Texts repeat a lot ("0 0 0"), so each is parsed once."""
    parsed: dict[str, list[float] | None] = {}
    out = []
    for top in root.iterchildren("link", "joint"):
        for el in top.iter(*NUMERIC_ATTRS):  # lxml filters by tag in C
            attrib = el.attrib
            for attr, count in NUMERIC_ATTRS[el.tag].items():
                raw = attrib.get(attr)
                if raw is not None:
                    values = parsed[raw] if raw in parsed else parsed.setdefault(raw, parse_floats(raw))
                    out.append((el, attr, raw, count, values))
    return out


# For the whole-file fast check: tags all of whose attributes are numbers with one count, and the
# numeric attributes of the two tags that also carry a name (<mesh filename>, <mimic joint>).
_NAMED = {"mesh": ("filename",), "mimic": ("joint",)}
_PLAIN = {
    count: tuple(tag for tag, attrs in NUMERIC_ATTRS.items() if tag not in _NAMED and set(attrs.values()) == {count})
    for count in (1, 3)
}
_IN_NAMED = tuple((attr, count) for tag in _NAMED for attr, count in NUMERIC_ATTRS[tag].items())
assert sorted(sum(_PLAIN.values(), ()) + tuple(_NAMED)) == sorted(NUMERIC_ATTRS)


def numeric_texts(root: etree._Element) -> dict[int, set[str]]:
    """{expected count: distinct texts}: a superset of the texts that numeric_values() reads,
    each under the count it would be read with.

    Elements anywhere in the file are taken, and every attribute of a purely numeric tag: a text
    that is not a number here may be no numeric attribute at all, but one that numeric_values()
    would read is always here. A rule that finds nothing wrong in these has nothing to report,
    and this costs a third of numeric_values() (attribute texts come from lxml in one call).
    """
    by_count: dict[int, set[str]] = {1: set(), 3: set()}
    for count, tags in _PLAIN.items():
        add = by_count[count].update
        for el in root.iter(tags):
            add(el.values())
    for el in root.iter(*_NAMED):
        for attr, count in _IN_NAMED:
            raw = el.get(attr)
            if raw is not None:
                by_count[count].add(raw)
    return by_count


def all_plain(texts: dict[int, set[str]]) -> bool:
    """True if every text is `count` finite numbers: then no numeric attribute is malformed or
    non-finite. parse_floats() for all texts at once, in C-level loops (map, sum); a sum that
    is finite has no NaN or Inf among its terms (one that overflows answers False: look closer)."""
    for count, items in texts.items():
        if not items:
            continue
        tokens = list(map(str.split, items))
        if set(map(len, tokens)) != {count}:
            return False
        try:
            total = sum(map(float, chain.from_iterable(tokens)))
        except ValueError:
            return False
        if not math.isfinite(total):
            return False
    return True


def owner(el: etree._Element) -> str:
    """Which joint or link an element belongs to, for messages: "joint 'elbow': " (or "")."""
    for anc in el.iterancestors("joint", "link"):
        name = anc.get("name")
        return f"{anc.tag} '{name}': " if name else f"unnamed <{anc.tag}>: "
    return ""
