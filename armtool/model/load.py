"""Read a URDF, SRDF or their xacro into an lxml tree, with errors that say which file and how to fix it."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from lxml import etree

from armtool.errors import ArmtoolError
from armtool.model.packages import PackageResolver
from armtool.model.xmlsource import XmlSyntaxProblem, parse_xml


def _load_xml(
    path: Path, xacro_args: Mapping[str, str] | None, package_paths: Sequence[Path], what: str
) -> etree._Element:
    if not path.is_file():
        problem = "not a regular file (a FIFO, socket or device)" if path.exists() else "no such file"
        raise ArmtoolError(problem, str(path), f"check the path to the {what} or its xacro")
    if path.name.lower().endswith(".xacro"):
        from armtool.model.xacro_source import XacroFailure, expand

        try:
            root = expand(path, xacro_args or {}, PackageResolver(package_paths)).root
        except XacroFailure as exc:
            raise ArmtoolError(f"xacro failed: {exc.message}", f"{exc.path}:{exc.line}", exc.hint) from None
    else:
        try:
            root = parse_xml(path.read_bytes())
        except XmlSyntaxProblem as exc:
            raise ArmtoolError(
                f"not well-formed XML: {exc.message}", f"{path}:{exc.line}:{exc.column}", f"run `armtool lint {path}`"
            ) from None
        except OSError as exc:
            raise ArmtoolError(f"cannot read: {exc.strerror}", str(path)) from None
    if root.tag != "robot":
        raise ArmtoolError(f"root element is <{root.tag}>, not <robot>", str(path), f"pass a {what} file")
    return root


def load_robot_xml(
    path: Path, xacro_args: Mapping[str, str] | None = None, package_paths: Sequence[Path] = ()
) -> etree._Element:
    """The <robot> element of a .urdf, or of a .xacro after expansion."""
    return _load_xml(path, xacro_args, package_paths, "URDF")


def load_srdf_xml(
    path: Path, xacro_args: Mapping[str, str] | None = None, package_paths: Sequence[Path] = ()
) -> etree._Element:
    """The <robot> element of a .srdf, or of a .srdf.xacro after expansion (MoveIt 2 configs use both)."""
    return _load_xml(path, xacro_args, package_paths, "SRDF")


def urdf_text(path: Path, xacro_args: Mapping[str, str] | None = None, package_paths: Sequence[Path] = ()) -> str:
    """A URDF's text: the file as it is, or a xacro's expansion (a whole URDF document)."""
    if not path.name.lower().endswith(".xacro"):
        from armtool.fileio import read_text

        return read_text(path, "URDF", keep_bom=True)
    root = load_robot_xml(path, xacro_args, package_paths)
    text: str = etree.tostring(root, encoding="unicode", pretty_print=True)
    return '<?xml version="1.0"?>\n' + text
