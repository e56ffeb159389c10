"""Fold calibrated corrections into the URDF's joint `<origin>`s by editing the text.

The new origin of joint j is `origin_j · SE3(exp(r_j), t_j) · motion_j(offset_j)`: the 6-D
correction, then the zero offset turned into a rotation about (or a shift along) the joint axis,
so that the controller's reading q gives the real pose. Only the `xyz`/`rpy` attribute values of
those `<origin>` elements change; comments, formatting and every other element stay as written.
Joint gains have no place in a URDF: they are reported in calibration.yaml for the driver.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from armtool.calib.model import se3
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError
from armtool.model.chain import axis_angle_batch
from armtool.model.urdf_edit import ByteEdit, UneditableXml, XmlSource, urdf_joints
from armtool.model.xmlsource import parse_xml


def _fmt(v: float) -> str:
    if abs(v) < 5e-13:
        return "0"
    text = f"{v:.10g}"
    return text


def joint_corrections(model: CalibModel, x: Array) -> dict[str, Array]:
    """joint name -> the 4×4 transform to right-multiply onto its URDF <origin>."""
    parts = model.split(x)
    out: dict[str, Array] = {}
    for i, j in enumerate(model.chain.joints):
        D = se3.delta(parts.origin[i])
        offset = float(parts.offset[i])
        M = np.eye(4)
        if j.kind == "prismatic":
            M[:3, 3] = offset * j.axis
        else:
            M[:3, :3] = axis_angle_batch(j.axis, np.array([offset]))[0]
        out[j.name] = D @ M
    return out


def _editable(text: str, source: str) -> XmlSource:
    try:
        return XmlSource.from_text(text)
    except UneditableXml as exc:
        raise ArmtoolError(
            f"cannot edit {source} in place: {exc.message}", f"{source}:{exc.line}", "report this with the file"
        ) from None


def corrected_text(text: str, corrections: dict[str, Array], source: str = "URDF") -> str:
    """The URDF text with each named joint's <origin> multiplied on the right by its correction."""
    from armtool.model.chain import origin_matrix

    doc = _editable(text, source)
    joints = urdf_joints(doc.root)  # top-level joints only, not <transmission><joint>
    edits: list[ByteEdit] = []
    for name, C in corrections.items():
        el = joints.get(name)
        if el is None:
            raise ArmtoolError(
                f"joint '{name}' is not in {source}", hint="the dataset's URDF and the one being written must match"
            )
        origin = el.find("origin")
        new = origin_matrix(origin) @ C
        values = {
            "xyz": " ".join(_fmt(v) for v in new[:3, 3]),
            "rpy": " ".join(_fmt(v) for v in se3.rpy_of(new[:3, :3])),
        }
        if origin is not None:
            edits += doc.set_attributes(origin, values)
        elif doc.tag(el).self_closing:
            raise ArmtoolError(
                f"joint '{name}' is an empty element", f"{source}:{el.sourceline}", "a joint needs <parent> and <child>"
            )
        else:
            edits.append(doc.insert_child(el, "origin", values, first=True))
    return doc.apply(edits).decode("utf-8")


def relocate_meshes(text: str, source_dir: Path, out_dir: Path) -> str:
    """Rewrite relative `<mesh>`/`<texture>` filenames so they still resolve from `out_dir`.

    A relative filename (`assets/base.stl`) is relative to the URDF's own directory; once the
    URDF is written elsewhere it points at nothing. It becomes the relative path from `out_dir`
    to the same file. `package://`, `file://` and other URIs, and absolute paths, stay as written.
    """
    import os

    doc = _editable(text, "the URDF")
    edits: list[ByteEdit] = []
    for el in doc.root.iter("mesh", "texture"):
        value = el.get("filename")
        if not value or "://" in value or os.path.isabs(value):
            continue
        target = os.path.normpath(os.path.join(os.path.abspath(source_dir), value))
        new = os.path.relpath(target, os.path.abspath(out_dir)).replace(os.sep, "/")
        if new != value:
            edits += doc.set_attributes(el, {"filename": new})
    return doc.apply(edits).decode("utf-8") if edits else text


def check_reproduces(text: str, model: CalibModel, x: Array, source: str) -> None:
    """Refuse to write a URDF whose kinematics differ from the fitted model (gains and joint terms aside)."""
    from armtool.model.chain import chain_from_xml

    chain = chain_from_xml(parse_xml(text.encode("utf-8")), model.chain.base, model.chain.tip, source=source)
    x = model.urdf_part(x)  # a URDF has no gains or joint terms; they are reported apart
    Q = model.chain.random(np.random.default_rng(0), 8)
    F = model.flange(x, Q)
    worst = max(float(np.abs(chain.fk(q) - T).max()) for q, T in zip(Q, F))
    if worst > 1e-7:
        raise ArmtoolError(
            f"internal error: the corrected URDF does not reproduce the fitted kinematics (off by {worst:.2g})",
            source,
            "nothing was written; please report this with the dataset",
        )
