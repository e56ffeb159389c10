"""Expand xacro with the xacro package while remembering where every element came from.

xacro builds a minidom tree without line numbers. We hook two of its functions:
`parse` tags each element of every file it reads with its file and line, and
`handle_macro_call` tags what a macro call produced with the call site. The expanded
document is re-read with lxml and the tags are moved into a side table.
"""

from __future__ import annotations

import contextlib
import io
import threading
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lxml import etree

from armtool.model.xmlsource import XmlSyntaxProblem, declares_entities, parse_xml
from armtool.model.origin import Origin, SourceLine
from armtool.model.packages import PackageResolver

SRC_ATTR = "armtool-src"
CALL_ATTR = "armtool-call"
_DIRECTIVES = {
    "xacro:property", "xacro:macro", "xacro:include", "xacro:if", "xacro:unless", "xacro:arg",
    "xacro:element", "xacro:attribute", "xacro:insert_block", "xacro:call",
}
_LOCK = threading.Lock()


class XacroFailure(Exception):
    def __init__(self, message: str, path: Path, line: int = 1) -> None:
        super().__init__(message)
        self.message = message
        self.path = path
        self.line = line


@dataclass
class Expansion:
    root: etree._Element
    origins: dict[etree._Element, Origin]
    files: list[Path]


def _checked_source(path: Path) -> tuple[Path, etree._Element] | None:
    """Read a file with armtool's safe parser before xacro's parser sees it: entities are refused here.
    None when it cannot be read: xacro then reports the missing include itself, at the including file."""
    try:
        data = path.read_bytes()
    except OSError:
        return None
    try:
        root = parse_xml(data)
    except XmlSyntaxProblem as exc:
        raise XacroFailure(f"not well-formed XML: {exc.message}", path, exc.line) from None
    if declares_entities(root):
        raise XacroFailure("DOCTYPE declares entities; armtool does not expand them", path, 1)
    return path, root


def _annotate(doc: Any, source: tuple[Path, etree._Element], files: list[Path]) -> None:
    path, root = source
    lx_elements = list(root.iter(etree.Element))
    dom_elements = doc.getElementsByTagName("*")
    if len(lx_elements) != len(dom_elements):
        return
    idx = len(files)
    files.append(path)
    for lx, dom in zip(lx_elements, dom_elements):
        if dom.tagName in _DIRECTIVES:
            continue
        dom.setAttribute(SRC_ATTR, f"{idx}:{lx.sourceline}")


@contextlib.contextmanager
def _hooked(xacro: Any, files: list[Path], resolver: PackageResolver, top: Path) -> Iterator[None]:
    from xacro import substitution_args

    orig_parse = xacro.parse
    orig_call = xacro.handle_macro_call
    orig_find = substitution_args._eval_find

    def parse(inp: Any, filename: str | None = None) -> Any:  # noqa: ANN401
        source = _checked_source(Path(filename).resolve()) if inp is None and filename else None
        doc = orig_parse(inp, filename)
        if source is not None:
            _annotate(doc, source, files)
        return doc

    def handle_macro_call(node: Any, macros: Any, symbols: Any) -> Any:
        src = None
        if node.nodeType == node.ELEMENT_NODE and node.hasAttribute(SRC_ATTR):
            src = node.getAttribute(SRC_ATTR)
            node.removeAttribute(SRC_ATTR)
        parent = node.parentNode
        before = list(parent.childNodes) if parent is not None else []
        done = orig_call(node, macros, symbols)
        if done and src and parent is not None:
            seen = {id(n) for n in before}
            for child in parent.childNodes:
                if id(child) in seen or child.nodeType != child.ELEMENT_NODE:
                    continue
                for el in [child, *child.getElementsByTagName("*")]:
                    old = el.getAttribute(CALL_ATTR)
                    el.setAttribute(CALL_ATTR, src + (";" + old if old else ""))
        elif not done and src:
            node.setAttribute(SRC_ATTR, src)
        return done

    def eval_find(pkg: str) -> str:
        found = resolver.find(pkg, top.parent)
        if found is None:
            raise xacro.XacroException(
                f"cannot find package '{pkg}' for $(find {pkg}); pass --package-path or set ROS_PACKAGE_PATH"
            )
        return str(found)

    xacro.parse = parse
    xacro.handle_macro_call = handle_macro_call
    substitution_args._eval_find = eval_find
    try:
        yield
    finally:
        xacro.parse = orig_parse
        xacro.handle_macro_call = orig_call
        substitution_args._eval_find = orig_find


def _parse_loc(value: str, files: list[Path]) -> SourceLine | None:
    idx, _, line = value.partition(":")
    try:
        return SourceLine(files[int(idx)], int(line))
    except (ValueError, IndexError):
        return None


def expand(path: Path, args: Mapping[str, str], resolver: PackageResolver) -> Expansion:
    """Run xacro on `path`; raise XacroFailure with xacro's own message on any error."""
    import xacro

    path = path.resolve()
    files: list[Path] = []
    sink = io.StringIO()
    with _LOCK, _hooked(xacro, files, resolver, path), contextlib.redirect_stderr(sink), \
            contextlib.redirect_stdout(sink):
        try:
            doc = xacro.process_file(str(path), mappings=dict(args), verbosity=0)
            text = doc.toxml()
        except XacroFailure:
            raise
        except Exception as exc:  # xacro raises many types; all become one clear failure
            where = Path(xacro.filestack[-1]) if getattr(xacro, "filestack", None) and xacro.filestack[-1] else path
            message = str(exc) or type(exc).__name__
            if isinstance(exc, RecursionError):
                message = "macro recursion too deep"
            raise XacroFailure(message, where) from None
        finally:
            with contextlib.suppress(Exception):
                xacro.init_stacks(None)
    try:
        root = parse_xml(text.encode("utf-8"))
    except XmlSyntaxProblem as exc:
        raise XacroFailure(f"expanded document is not well-formed: {exc.message}", path) from None
    origins: dict[etree._Element, Origin] = {}
    for el in root.iter(etree.Element):
        src = el.attrib.pop(SRC_ATTR, None)
        calls = el.attrib.pop(CALL_ATTR, None)
        if src is None and calls is None:
            continue
        call_locs = tuple(loc for loc in (_parse_loc(c, files) for c in (calls or "").split(";") if c) if loc)
        origins[el] = Origin(_parse_loc(src, files) if src else None, call_locs)
    return Expansion(root, origins, files)
