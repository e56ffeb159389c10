"""Fold calibrated corrections into the URDF's joint `<origin>`s by editing the text.

The new origin of joint j is `origin_j · SE3(exp(r_j), t_j) · motion_j(offset_j)`: the 6-D
correction, then the zero offset turned into a rotation about (or a shift along) the joint axis,
so that the controller's reading q gives the real pose. Only the `xyz`/`rpy` attribute values of
those `<origin>` elements change; comments, formatting and every other element stay as written.
Joint gains have no place in a URDF: they are reported in calibration.yaml for the driver.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path

import numpy as np
from lxml import etree

from armtool.calib import se3
from armtool.calib.model import CalibModel
from armtool.calib.se3 import Array
from armtool.errors import ArmtoolError
from armtool.model.chain import axis_angle_batch
from armtool.model.xmlsource import parse_xml


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
            M[:3, :3] = axis_angle_batch(j.axis, np.array([offset]))[0]
        out[j.name] = D @ M
    return out


def _start_tags(text: str) -> Iterator[tuple[str, int, int, int, bool]]:
    """(name, start, end, depth, self_closing) of every start tag in document order.

    A small scanner rather than lxml's line numbers: an expanded xacro can hold many elements on
    one line, and an edit must land on exactly its element. Comments, CDATA, processing
    instructions and the DOCTYPE are skipped; quotes are honoured inside tags.
    """
    i, depth, n = 0, 0, len(text)

    def skip(after: str, start: int) -> int:
        k = text.find(after, start)
        return n if k < 0 else k + len(after)

    while True:
        i = text.find("<", i)
        if i < 0:
            return
        if text.startswith("<!--", i):
            i = skip("-->", i + 4)
        elif text.startswith("<![CDATA[", i):
            i = skip("]]>", i + 9)
        elif text.startswith("<?", i):
            i = skip("?>", i + 2)
        elif text.startswith("<!", i):
            bracket, close = text.find("[", i), text.find(">", i)
            i = skip("]>", bracket) if 0 <= bracket < close else skip(">", i)
        elif text.startswith("</", i):
            depth -= 1
            i = skip(">", i)
        else:
            j, quote = i + 1, ""
            while j < n:
                ch = text[j]
                if quote:
                    if ch == quote:
                        quote = ""
                elif ch in "\"'":
                    quote = ch
                elif ch == ">":
                    break
                j += 1
            name = re.match(r"[^\s/>]*", text[i + 1 :]).group(0)  # type: ignore[union-attr]
            closing = text[j - 1] == "/"
            yield name, i, j + 1, depth, closing
            if not closing:
                depth += 1
            i = j + 1


def _set_attributes(tag: str, values: dict[str, str]) -> str:
    closing = "/>" if tag.rstrip().endswith("/>") else ">"
    body = tag[: len(tag.rstrip()) - len(closing)]
    for attr, value in values.items():
        pattern = re.compile(r"(\s" + attr + r"\s*=\s*)(\"[^\"]*\"|'[^']*')")
        if pattern.search(body):
            body = pattern.sub(lambda m: f'{m.group(1)}"{value}"', body, count=1)  # noqa: B023 (used at once)
        else:
            body = body.rstrip() + f' {attr}="{value}"'
    return body + closing


def corrected_text(text: str, corrections: dict[str, Array], source: str = "URDF") -> str:
    """The URDF text with each named joint's <origin> multiplied on the right by its correction."""
    from armtool.model.chain import origin_matrix

    root = parse_xml(text.encode("utf-8"))
    elements = root.findall("joint")  # top-level joints only, not <transmission><joint>
    # Top-level <joint> start tags in the text, in document order, each with its <origin> child.
    spans: list[tuple[int, int, bool, tuple[int, int] | None]] = []
    inside = False
    for name, start, end, depth, closing in _start_tags(text):
        if depth <= 1:
            inside = name == "joint" and depth == 1
            if inside:
                spans.append((start, end, closing, None))
        elif inside and depth == 2 and name == "origin" and spans[-1][3] is None:
            spans[-1] = (*spans[-1][:3], (start, end))
    if len(spans) != len(elements):
        raise ArmtoolError(
            f"could not match the <joint> elements of {source} in its text", hint="report this with the file"
        )
    by_name = {el.get("name"): k for k, el in enumerate(elements)}
    edits: list[tuple[int, int, str]] = []
    for name, C in corrections.items():
        k = by_name.get(name)
        if k is None:
            raise ArmtoolError(
                f"joint '{name}' is not in {source}", hint="the dataset's URDF and the one being written must match"
            )
        el = elements[k]
        start, end, closing, origin_span = spans[k]
        new = origin_matrix(el.find("origin")) @ C
        values = {
            "xyz": " ".join(_fmt(v) for v in new[:3, 3]),
            "rpy": " ".join(_fmt(v) for v in se3.rpy_of(new[:3, :3])),
        }
        if origin_span is not None:
            edits.append(
                (origin_span[0], origin_span[1], _set_attributes(text[origin_span[0] : origin_span[1]], values))
            )
        elif closing:
            raise ArmtoolError(
                f"joint '{name}' is an empty element", f"{source}:{el.sourceline}", "a joint needs <parent> and <child>"
            )
        else:
            line_start = text.rfind("\n", 0, start) + 1
            indent = re.match(r"[ \t]*", text[line_start:start]).group(0)  # type: ignore[union-attr]
            edits.append((end, end, f'\n{indent}  <origin xyz="{values["xyz"]}" rpy="{values["rpy"]}"/>'))
    for start, end, replacement in sorted(edits, reverse=True):
        text = text[:start] + replacement + text[end:]
    return text


def relocate_meshes(text: str, source_dir: Path, out_dir: Path) -> str:
    """Rewrite relative `<mesh>`/`<texture>` filenames so they still resolve from `out_dir`.

    A relative filename (`assets/base.stl`) is relative to the URDF's own directory; once the
    URDF is written elsewhere it points at nothing. It becomes the relative path from `out_dir`
    to the same file. `package://`, `file://` and other URIs, and absolute paths, stay as written.
    """
    import os

    edits: list[tuple[int, int, str]] = []
    for name, start, end, _depth, _closing in _start_tags(text):
        if name not in ("mesh", "texture"):
            continue
        tag = text[start:end]
        m = re.search(r"\sfilename\s*=\s*(\"[^\"]*\"|'[^']*')", tag)
        if m is None:
            continue
        value = m.group(1)[1:-1]
        if not value or "://" in value or os.path.isabs(value):
            continue
        target = os.path.normpath(os.path.join(os.path.abspath(source_dir), value))
        new = os.path.relpath(target, os.path.abspath(out_dir)).replace(os.sep, "/")
        if new != value:
            edits.append((start, end, _set_attributes(tag, {"filename": new})))
    for start, end, replacement in sorted(edits, reverse=True):
        text = text[:start] + replacement + text[end:]
    return text


def check_reproduces(text: str, model: CalibModel, x: Array, source: str) -> None:
    """Refuse to write a URDF whose kinematics differ from the fitted model (gains aside)."""
    from armtool.model.chain import chain_from_xml

    chain = chain_from_xml(parse_xml(text.encode("utf-8")), model.chain.base, model.chain.tip, source=source)
    x = x.copy()
    x[12:].reshape(model.chain.n, 8)[:, 7] = 0.0  # a URDF has no gains; they are reported apart
    Q = model.chain.random(np.random.default_rng(0), 8)
    F = model.flange(x, Q)
    worst = max(float(np.abs(chain.fk(q) - T).max()) for q, T in zip(Q, F))
    if worst > 1e-7:
        raise ArmtoolError(
            f"internal error: the corrected URDF does not reproduce the fitted kinematics (off by {worst:.2g})",
            source,
            "nothing was written; please report this with the dataset",
        )


def expanded_text(urdf: Path, xacro_args: Mapping[str, str] | None = None, package_paths: Sequence[Path] = ()) -> str:
    """The URDF text to edit: the file itself, or a xacro's expansion."""
    if urdf.name.lower().endswith(".xacro"):
        from armtool.model.load import load_robot_xml

        root = load_robot_xml(urdf, xacro_args, package_paths)
        expanded: str = etree.tostring(root, encoding="unicode", pretty_print=True)
        return '<?xml version="1.0"?>\n' + expanded
    return urdf.read_bytes().decode("utf-8")
