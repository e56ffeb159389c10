"""Which URDF attributes hold numbers, how many, and how to read and print them."""

from __future__ import annotations

from collections.abc import Iterator

from lxml import etree

from armtool.lint.locate import local_tag

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
            for attr, count in NUMERIC_ATTRS[el.tag].items():  # type: ignore[index]
                raw = attrib.get(attr)
                if raw is not None:
                    values = parsed[raw] if raw in parsed else parsed.setdefault(raw, parse_floats(raw))
                    out.append((el, attr, raw, count, values))
    return out
