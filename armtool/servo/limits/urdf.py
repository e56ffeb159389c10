"""Writing recorded limits into a URDF's text, keeping every other byte (`model.urdf_edit`)."""

from __future__ import annotations

from dataclasses import dataclass

from lxml import etree

from armtool.errors import ArmtoolError
from armtool.model.urdf_edit import ByteEdit, UneditableXml, XmlSource
from armtool.model.urdf_edit import urdf_joints as joint_elements


@dataclass
class UrdfJoint:
    name: str
    type: str
    lower: float | None
    upper: float | None


def _source(text: str, source: str) -> XmlSource:
    try:
        return XmlSource.from_text(text)
    except UneditableXml as exc:
        raise ArmtoolError(
            f"{source} is not a URDF armtool can edit: {exc.message}",
            f"{source}:{exc.line}",
            "pass the URDF file itself (for a xacro: xacro arm.urdf.xacro > arm.urdf)",
        ) from None


def _joints(doc: XmlSource, source: str) -> dict[str, tuple[UrdfJoint, etree._Element]]:
    """Joints with a type (a URDF joint always has one), each with its element."""
    out: dict[str, tuple[UrdfJoint, etree._Element]] = {}
    for name, el in joint_elements(doc.root).items():
        jtype = el.get("type")
        if jtype is None:
            continue
        lim = el.find("limit")
        lower = upper = None
        if lim is not None:
            line = doc.line_of(doc.tag(el).start)
            lower = _urdf_float(lim.get("lower"), "lower", name, line, source)
            upper = _urdf_float(lim.get("upper"), "upper", name, line, source)
        out[name] = (UrdfJoint(name, jtype, lower, upper), el)
    return out


def urdf_joints(text: str, source: str = "URDF") -> dict[str, UrdfJoint]:
    return {name: joint for name, (joint, _el) in _joints(_source(text, source), source).items()}


def _urdf_float(value: str | None, attr: str, joint: str, line: int, source: str) -> float | None:
    if value is None:
        return None
    try:
        return float(value)
    except ValueError:
        raise ArmtoolError(
            f"joint '{joint}': <limit {attr}=\"{value}\"> is not a number",
            f"{source}:{line}",
            hint="run xacro first (xacro arm.urdf.xacro > arm.urdf) and pass the URDF it writes",
        ) from None


def _check_names(joints: dict[str, UrdfJoint], names: list[str], source: str) -> None:
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


def check_urdf_names(text: str, names: list[str], source: str) -> dict[str, UrdfJoint]:
    joints = urdf_joints(text, source)
    _check_names(joints, names, source)
    return joints


def patch_urdf(
    text: str, limits: dict[str, tuple[float, float]], allow_widen: bool = False, source: str = "URDF"
) -> str:
    """New URDF text with `<limit lower upper>` set per joint; everything else kept byte for byte."""
    doc = _source(text, source)
    found = _joints(doc, source)
    existing = {name: joint for name, (joint, _el) in found.items()}
    _check_names(existing, list(limits), source)
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
    edits: list[ByteEdit] = []
    for name, (lo, hi) in limits.items():
        el = found[name][1]
        values = {"lower": f"{lo:.6g}", "upper": f"{hi:.6g}"}
        lim = el.find("limit")
        if lim is not None:
            for attr in ("effort", "velocity"):  # required by the URDF spec; kept when written
                if lim.get(attr) is None:
                    values[attr] = "1.0"
            edits += doc.set_attributes(lim, values)
        elif doc.tag(el).self_closing:
            raise ArmtoolError(f"joint '{name}' in {source} is an empty element; cannot add a <limit>")
        else:
            edits.append(doc.insert_child(el, "limit", {**values, "effort": "1.0", "velocity": "1.0"}))
    return doc.apply(edits).decode("utf-8")
