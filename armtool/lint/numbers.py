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


def numeric_attributes(root: etree._Element) -> Iterator[tuple[etree._Element, str, str, int]]:
    """(element, attribute, raw value, expected count) for every numeric attribute under links and joints."""
    for top in root:
        if local_tag(top) not in ("link", "joint"):
            continue
        for el in top.iter(*NUMERIC_ATTRS):  # lxml filters by tag in C
            spec = NUMERIC_ATTRS[local_tag(el)]
            for attr, count in spec.items():
                raw = el.get(attr)
                if raw is not None:
                    yield el, attr, raw, count
