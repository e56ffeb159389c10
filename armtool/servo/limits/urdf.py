"""Writing recorded limits into a URDF's text, keeping every other byte."""

from __future__ import annotations

import re
from dataclasses import dataclass

from armtool.errors import ArmtoolError

_JOINT_RE = re.compile(r"<joint\b[^>]*/>|<joint\b[^>]*>.*?</joint\s*>", re.S)
_NAME_RE = re.compile(r"""\bname\s*=\s*(["'])(.*?)\1""")
_TYPE_RE = re.compile(r"""\btype\s*=\s*(["'])(.*?)\1""")
_LIMIT_RE = re.compile(r"<limit\b[^>]*?/?>", re.S)
_ATTR_RE = r"""(\b{}\s*=\s*)(["'])(.*?)\2"""


@dataclass
class UrdfJoint:
    name: str
    type: str
    lower: float | None
    upper: float | None


def urdf_joints(text: str, source: str = "URDF") -> dict[str, UrdfJoint]:
    out: dict[str, UrdfJoint] = {}
    for m in _JOINT_RE.finditer(_blank_comments(text)):
        block = m.group(0)
        head = block[: block.index(">")]
        name, jtype = _NAME_RE.search(head), _TYPE_RE.search(head)
        if not name or not jtype:  # a URDF joint always has a type; a reference to one does not
            continue
        lim = _LIMIT_RE.search(block)
        lower = upper = None
        if lim:
            lo = re.search(_ATTR_RE.format("lower"), lim.group(0))
            hi = re.search(_ATTR_RE.format("upper"), lim.group(0))
            lower = _urdf_float(lo.group(3), "lower", name.group(2), text, m.start(), source) if lo else None
            upper = _urdf_float(hi.group(3), "upper", name.group(2), text, m.start(), source) if hi else None
        out[name.group(2)] = UrdfJoint(name.group(2), jtype.group(2) if jtype else "", lower, upper)
    return out


_NOT_JOINTS_RE = re.compile(r"<!--.*?-->|<(transmission|ros2_control|gazebo)\b.*?</\1\s*>", re.S)


def _urdf_float(value: str, attr: str, joint: str, text: str, offset: int, source: str) -> float:
    try:
        return float(value)
    except ValueError:
        line = text.count("\n", 0, offset) + 1
        raise ArmtoolError(
            f"joint '{joint}': <limit {attr}=\"{value}\"> is not a number",
            f"{source}:{line}",
            hint="run xacro first (xacro arm.urdf.xacro > arm.urdf) and pass the URDF it writes",
        ) from None


def _blank_comments(text: str) -> str:
    """Comments, and the blocks whose <joint name> only refers to a joint (<transmission>,
    <ros2_control>, <gazebo>), replaced by spaces of the same length, so offsets stay valid."""
    text = re.sub(r"<!--.*?-->", lambda m: " " * len(m.group(0)), text, flags=re.S)
    return _NOT_JOINTS_RE.sub(lambda m: " " * len(m.group(0)), text)


def check_urdf_names(text: str, names: list[str], source: str) -> dict[str, UrdfJoint]:
    joints = urdf_joints(text, source)
    missing = [n for n in names if n not in joints]
    if missing:
        raise ArmtoolError(
            f"joint(s) {', '.join(missing)} not in {source}",
            hint="available: " + ", ".join(sorted(joints)) + "; the arm file's joint names must match the URDF",
        )
    bad = [n for n in names if joints[n].type not in ("revolute", "prismatic")]
    if bad:
        raise ArmtoolError(
            f"joint(s) {', '.join(bad)} in {source} are not revolute (continuous/fixed joints have no limits)"
        )
    return joints


def patch_urdf(
    text: str, limits: dict[str, tuple[float, float]], allow_widen: bool = False, source: str = "URDF"
) -> str:
    """New URDF text with `<limit lower upper>` set per joint; everything else kept byte for byte."""
    existing = check_urdf_names(text, list(limits), source)
    if not allow_widen:
        wider = [
            f"{n}: measured {lo:.4f}..{hi:.4f}, URDF {existing[n].lower:.4f}..{existing[n].upper:.4f}"
            for n, (lo, hi) in limits.items()
            if existing[n].lower is not None
            and existing[n].upper is not None
            and (lo < existing[n].lower - 1e-6 or hi > existing[n].upper + 1e-6)  # type: ignore[operator]
        ]
        if wider:
            raise ArmtoolError(
                "measured limits lie outside the URDF's: " + "; ".join(wider),
                hint="check zero_ticks/direction in the arm file, or pass --allow-widen to write them anyway",
            )
    blanked = _blank_comments(text)
    edits: list[tuple[int, int, str]] = []
    for m in _JOINT_RE.finditer(blanked):
        head = m.group(0)[: m.group(0).index(">")]
        name = _NAME_RE.search(head)
        if not name or not _TYPE_RE.search(head) or name.group(2) not in limits:
            continue
        lo, hi = limits[name.group(2)]
        lim = _LIMIT_RE.search(m.group(0))
        if lim:
            tag = text[m.start() + lim.start() : m.start() + lim.end()]
            for attr, value in (("lower", lo), ("upper", hi)):
                pattern = re.compile(_ATTR_RE.format(attr))
                if pattern.search(tag):
                    tag = pattern.sub(lambda mm: f"{mm.group(1)}{mm.group(2)}{value:.6g}{mm.group(2)}", tag, count=1)  # noqa: B023 (runs at once)
                else:
                    tag = re.sub(r"<limit\b", f'<limit {attr}="{value:.6g}"', tag, count=1)
            for attr, default in (("effort", "1.0"), ("velocity", "1.0")):
                if not re.search(_ATTR_RE.format(attr), tag):
                    tag = re.sub(r"\s*/?>$", lambda mm: f' {attr}="{default}"{mm.group(0)}', tag, count=1)  # noqa: B023 (runs at once)
            edits.append((m.start() + lim.start(), m.start() + lim.end(), tag))
        else:
            close = m.group(0).rfind("</joint")
            if close < 0:
                raise ArmtoolError(f"joint '{name.group(2)}' in {source} is an empty element; cannot add a <limit>")
            line_start = text.rfind("\n", 0, m.start() + close) + 1
            indent = re.match(r"[ \t]*", text[line_start:]).group(0)  # type: ignore[union-attr]
            new = f'  <limit lower="{lo:.6g}" upper="{hi:.6g}" effort="1.0" velocity="1.0"/>\n{indent}'
            edits.append((m.start() + close, m.start() + close, new))
    for start, end, new in sorted(edits, reverse=True):
        text = text[:start] + new + text[end:]
    return text
