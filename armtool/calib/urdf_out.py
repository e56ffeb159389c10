"""Fold calibrated corrections into the URDF's joint `<origin>`s by editing the text.

The new origin of joint j is `origin_j · SE3(exp(r_j), t_j) · motion_j(offset_j)`: the 6-D
correction, then the zero offset turned into a rotation about (or a shift along) the joint axis,
so that the controller's reading q gives the real pose. Only the `xyz`/`rpy` attribute values of
those `<origin>` elements change; comments, formatting and every other element stay as written.
Joint gains have no place in a URDF: they are reported in calibration.yaml for the driver.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from lxml import etree

from armtool.calib import se3
from armtool.calib.model import CalibModel
from armtool.calib.se3 import Array
from armtool.errors import ArmtoolError
from armtool.model.xmlsource import SourceText, parse_xml


def _fmt(v: float) -> str:
    if abs(v) < 5e-13:
        return "0"
    text = f"{v:.10g}"
    return text


def joint_corrections(model: CalibModel, x: Array) -> dict[str, Array]:
    """joint name -> the 4×4 transform to right-multiply onto its URDF <origin>."""
    n = model.chain.n
    k = x[12:].reshape(n, 8)
    out: dict[str, Array] = {}
    for i, j in enumerate(model.chain.joints):
        D = se3.delta(k[i, :6])
        offset = float(k[i, 6])
        M = np.eye(4)
        if j.kind == "prismatic":
            M[:3, 3] = offset * j.axis
        else:
            M[:3, :3] = se3.rotation_about(j.axis, np.array([offset]))[0]
        out[j.name] = D @ M
    return out


def corrected_text(text: str, corrections: dict[str, Array], source: str = "URDF") -> str:
    """The URDF text with each named joint's <origin> multiplied on the right by its correction."""
    root = parse_xml(text.encode("utf-8"))
    src = SourceText(Path(source), text)
    edits: list[tuple[int, int, str]] = []
    joints = {el.get("name"): el for el in root.findall("joint")}  # not <transmission><joint>
    for name, C in corrections.items():
        el = joints.get(name)
        if el is None:
            raise ArmtoolError(f"joint '{name}' is not in {source}", hint="the dataset's URDF and the one being written must match")
        origin = el.find("origin")
        from armtool.ik.chain import origin_matrix

        new = origin_matrix(origin) @ C
        xyz = " ".join(_fmt(v) for v in new[:3, 3])
        rpy = " ".join(_fmt(v) for v in se3.rpy_of(new[:3, :3]))
        if origin is not None and origin.sourceline:
            span = src.start_tag_span(origin.sourceline, "origin")
            if span is None:
                raise ArmtoolError(f"cannot find the <origin> of joint '{name}' in the text", f"{source}:{origin.sourceline}")
            tag = text[span[0] : span[1]]
            closing = "/>" if tag.rstrip().endswith("/>") else ">"
            body = tag[: len(tag) - len(closing)]
            for attr, value in (("xyz", xyz), ("rpy", rpy)):
                pattern = re.compile(r"(\s" + attr + r"\s*=\s*)(\"[^\"]*\"|'[^']*')")
                if pattern.search(body):
                    body = pattern.sub(lambda m, v=value: f'{m.group(1)}"{v}"', body, count=1)
                else:
                    body = body.rstrip() + f' {attr}="{value}"'
            edits.append((span[0], span[1], body + closing))
        else:
            span = src.start_tag_span(el.sourceline or 1, "joint")
            if span is None:
                raise ArmtoolError(f"cannot find joint '{name}' in the text", f"{source}:{el.sourceline}")
            line_start = text.rfind("\n", 0, span[0]) + 1
            indent = re.match(r"[ \t]*", text[line_start:]).group(0)  # type: ignore[union-attr]
            edits.append((span[1], span[1], f'\n{indent}  <origin xyz="{xyz}" rpy="{rpy}"/>'))
    for start, end, replacement in sorted(edits, reverse=True):
        text = text[:start] + replacement + text[end:]
    return text


def expanded_text(urdf: Path) -> str:
    """The URDF text to edit: the file itself, or a xacro's expansion."""
    if urdf.name.lower().endswith(".xacro"):
        from armtool.model.load import load_robot_xml

        root = load_robot_xml(urdf)
        return '<?xml version="1.0"?>\n' + etree.tostring(root, encoding="unicode")
    return urdf.read_bytes().decode("utf-8")
