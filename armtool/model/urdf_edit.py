"""Edit a URDF's bytes where lxml found its elements, keeping every other byte as written.

lxml gives the tree and each element's line, not its offsets. `XmlSource` walks the raw bytes
once for the start and end tags (comments, CDATA, processing instructions and the DOCTYPE
skipped, quotes honoured) and pairs them, in document order, with lxml's elements, checking the
pairing by tag name. An edit is a byte span and its replacement: set an attribute's value
(keeping its quotes), add missing attributes after the written ones, or insert a child element
on its own line with the indentation of its siblings and the file's line ending. Comments,
attribute order, quotes, line endings and the encoding declaration stay as the author wrote them.

Used by `lint --fix` (through `lint.locate.Locator`), `calibrate` (corrected `<origin>`s) and
`limits --urdf` (`<limit lower upper>`).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from typing import NamedTuple

from lxml import etree

from armtool.model.xmlsource import XmlSyntaxProblem, parse_xml


class ByteEdit(NamedTuple):
    """Replace data[start:end] with `replacement`."""

    start: int
    end: int
    replacement: bytes


class Tag(NamedTuple):
    start: int  # offset of the start tag's '<'
    end: int  # offset just past its '>'
    close: int  # offset of the end tag's '</' (== end for a self-closing element)
    self_closing: bool


class Attribute(NamedTuple):
    name: str  # as written, prefix included
    value_start: int  # inside the quotes
    value_end: int
    quote: bytes


class UneditableXml(Exception):
    """The bytes cannot be edited in place: malformed, not ASCII-compatible, or tags not paired."""

    def __init__(self, message: str, line: int = 1) -> None:
        super().__init__(message)
        self.message = message
        self.line = line


def escape_attribute(value: str, quote: str = '"') -> str:
    """XML attribute escaping for a value written between `quote`s (xml.sax.saxutils would pull
    urllib into `lint`'s start-up)."""
    value = value.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return value.replace('"', "&quot;") if quote == '"' else value.replace("'", "&apos;")


_SPACE = b" \t\r\n"
# One start tag: its name, then anything up to the '>' outside quotes (possessive: no backtracking).
_START_TAG = re.compile(rb"""<([^\s/>]*+)(?:[^"'>]++|"[^"]*+"|'[^']*+')*+>""")
_NAME_END = b" \t\r\n/>="


def _tag_name(data: bytes, start: int) -> bytes:
    end = start
    n = len(data)
    while end < n and data[end] not in _NAME_END:
        end += 1
    return data[start:end]


def _scan(data: bytes) -> tuple[list[tuple[bytes, int, int, bool]], dict[int, int]]:
    """Start tags (name, start, end, self_closing) in document order, and for each non-empty one
    (by its index) the offset of its end tag."""
    starts: list[tuple[bytes, int, int, bool]] = []
    closes: dict[int, int] = {}
    open_: list[int] = []
    find, i = data.find, 0

    def past(marker: bytes, at: int) -> int:
        k = find(marker, at)
        if k < 0:
            raise UneditableXml(f"unterminated markup: no {marker.decode()!r}")
        return k + len(marker)

    while True:
        i = find(b"<", i)
        if i < 0:
            break
        kind = data[i + 1 : i + 2]
        if kind == b"!":
            if data.startswith(b"<!--", i):
                i = past(b"-->", i + 4)
            elif data.startswith(b"<![CDATA[", i):
                i = past(b"]]>", i + 9)
            else:  # DOCTYPE, with or without an internal subset
                bracket, gt = find(b"[", i), find(b">", i)
                i = past(b"]", bracket) if 0 <= bracket < gt else i
                i = past(b">", i)
        elif kind == b"?":
            i = past(b"?>", i + 2)
        elif kind == b"/":
            if not open_:
                raise UneditableXml("end tag without a start tag")
            closes[open_.pop()] = i
            i = past(b">", i)
        else:
            tag = _START_TAG.match(data, i)
            if tag is None:
                raise UneditableXml("unterminated start tag")
            end = tag.end()
            closing = data[end - 2] == 47  # '/'
            starts.append((tag.group(1), i, end, closing))
            if not closing:
                open_.append(len(starts) - 1)
            i = end
    if open_:
        raise UneditableXml("start tag without an end tag")
    return starts, closes


class XmlSource:
    """A document's bytes, its lxml tree, and where each element's tags are in the bytes."""

    def __init__(self, data: bytes, root: etree._Element | None = None, encoding: str | None = None) -> None:
        """`root`: the tree lxml already built from exactly these bytes (saves parsing again).
        `encoding`: the bytes' real encoding, when it is not the one they declare."""
        if root is None:
            try:
                root = parse_xml(data)
            except XmlSyntaxProblem as exc:
                raise UneditableXml(exc.message, exc.line) from None
        self.data = data
        self.root = root
        self.encoding = encoding or root.getroottree().docinfo.encoding or "UTF-8"
        try:
            ascii_compatible = "<a/>".encode(self.encoding) == b"<a/>"
        except LookupError:
            ascii_compatible = False
        if not ascii_compatible:
            raise UneditableXml(f"cannot edit text in {self.encoding} in place")
        first_newline = data.find(b"\n")
        self.newline = b"\r\n" if first_newline > 0 and data[first_newline - 1] == 13 else b"\n"
        starts, closes = _scan(data)
        elements = list(root.iter(etree.Element))
        if len(elements) != len(starts):
            raise UneditableXml(f"found {len(starts)} start tags in the text, lxml {len(elements)} elements")
        encoding = self.encoding
        for el, (name, start, _end, _closing) in zip(elements, starts):
            if name.rpartition(b":")[2].decode(encoding, "replace") != el.tag.rpartition("}")[2]:
                line = data.count(b"\n", 0, start) + 1
                raise UneditableXml(
                    f"the text's <{name.decode(errors='replace')}> is lxml's <{etree.QName(el).localname}>", line
                )
        self._starts, self._closes = starts, closes
        self._index = {el: k for k, el in enumerate(elements)}

    @classmethod
    def from_text(cls, text: str) -> XmlSource:
        """For callers that hold the document as a str: its UTF-8 bytes, whatever it declares."""
        return cls(text.encode("utf-8"), encoding="UTF-8")

    # --- finding places -------------------------------------------------------------------

    def tag(self, el: etree._Element) -> Tag:
        k = self._index[el]
        _name, start, end, closing = self._starts[k]
        return Tag(start, end, self._closes.get(k, end), closing)

    def line_of(self, offset: int) -> int:
        return self.data.count(b"\n", 0, offset) + 1

    def char_offset(self, offset: int) -> int:
        """The offset in characters of the text as UTF-8, which is how `lint --fix` reads a file
        (whatever encoding it declares: a file that declares ISO-8859-1 but is saved as UTF-8 is
        common). Raises UnicodeDecodeError when the bytes before `offset` are not UTF-8."""
        return len(self.data[:offset].decode("utf-8"))

    def elements_at(self, line: int, tag: str) -> list[etree._Element]:
        """The `<tag>` elements lxml numbers `line` (libxml2 counts the line where a start tag ends)."""
        return [
            el for el in self.root.iter(etree.Element) if el.sourceline == line and el.tag.rpartition("}")[2] == tag
        ]

    def attributes(self, el: etree._Element) -> list[Attribute]:
        """The attributes as written in `el`'s start tag, in order."""
        data, tag = self.data, self.tag(el)
        i = tag.start + 1 + len(_tag_name(data, tag.start + 1))
        out: list[Attribute] = []
        while True:
            while data[i] in _SPACE:
                i += 1
            if data[i] in b"/>":
                return out
            name = _tag_name(data, i)
            i += len(name)
            while data[i] in _SPACE or data[i] == 61:  # '='
                i += 1
            quote = data[i : i + 1]
            end = data.index(quote, i + 1)
            out.append(Attribute(name.decode(self.encoding, "replace"), i + 1, end, quote))
            i = end + 1

    def _end_of_attributes(self, el: etree._Element) -> int:
        attrs = self.attributes(el)
        if attrs:
            return attrs[-1].value_end + 1
        tag = self.tag(el)
        return tag.start + 1 + len(_tag_name(self.data, tag.start + 1))

    def _indent(self, offset: int) -> bytes:
        """The spaces and tabs that start the line holding `offset`."""
        line_start = self.data.rfind(b"\n", 0, offset) + 1
        end = line_start
        while end < offset and self.data[end] in b" \t":
            end += 1
        return self.data[line_start:end]

    def _starts_line(self, offset: int) -> bool:
        line_start = self.data.rfind(b"\n", 0, offset) + 1
        return not self.data[line_start:offset].strip(_SPACE)

    def child_indent(self, parent: etree._Element) -> bytes:
        """The indentation of `parent`'s children: that of the first child written on its own
        line, else the parent's plus one step (a tab if the parent is indented with tabs)."""
        for child in parent.iterchildren(etree.Element):
            start = self.tag(child).start
            if self._starts_line(start):
                return self._indent(start)
        own = self._indent(self.tag(parent).start)
        return own + (b"\t" if own.endswith(b"\t") else b"  ")

    # --- edits -------------------------------------------------------------------------------

    def _encode(self, text: str) -> bytes:
        return text.encode(self.encoding, errors="xmlcharrefreplace")

    def set_attributes(self, el: etree._Element, values: Mapping[str, str]) -> list[ByteEdit]:
        """Edits that give `el` these attribute values: a written value is replaced inside its own
        quotes; missing attributes are added, in the given order, after the written ones."""
        written = {a.name: a for a in self.attributes(el)}
        edits: list[ByteEdit] = []
        missing: list[str] = []
        for name, value in values.items():
            attr = written.get(name)
            if attr is None:
                missing.append(f' {name}="{escape_attribute(value)}"')
            else:
                new = self._encode(escape_attribute(value, attr.quote.decode()))
                edits.append(ByteEdit(attr.value_start, attr.value_end, new))
        if missing:
            at = self._end_of_attributes(el)
            edits.append(ByteEdit(at, at, self._encode("".join(missing))))
        return edits

    def element_text(self, tag: str, values: Mapping[str, str]) -> bytes:
        return self._encode(f"<{tag}" + "".join(f' {k}="{escape_attribute(v)}"' for k, v in values.items()) + "/>")

    def insert_child(
        self, parent: etree._Element, tag: str, values: Mapping[str, str], *, first: bool = False
    ) -> ByteEdit:
        """An edit that adds `<tag values/>` as `parent`'s first (or last) child, on a line of its
        own, indented like its siblings. `parent` must not be self-closing."""
        where = self.tag(parent)
        if where.self_closing:
            raise ValueError(f"<{etree.QName(parent).localname}> is an empty element")
        element = self.element_text(tag, values)
        indent, nl = self.child_indent(parent), self.newline
        if first:
            return ByteEdit(where.end, where.end, nl + indent + element)
        if self._starts_line(where.close):
            line_start = self.data.rfind(b"\n", 0, where.close) + 1
            return ByteEdit(line_start, line_start, indent + element + nl)
        own = self._indent(where.start)
        return ByteEdit(where.close, where.close, nl + indent + element + nl + own)

    def apply(self, edits: Iterable[ByteEdit]) -> bytes:
        """The bytes with the edits made (they must not overlap)."""
        data = self.data
        last = len(data) + 1
        for edit in sorted(edits, key=lambda e: (e.start, e.end), reverse=True):
            if edit.end > last:
                raise ValueError("overlapping edits")
            data = data[: edit.start] + edit.replacement + data[edit.end :]
            last = edit.start
        return data


def urdf_joints(root: etree._Element) -> dict[str, etree._Element]:
    """The robot's joints by name: the top-level `<joint name>` elements (a `<joint>` inside a
    `<transmission>`, `<ros2_control>` or `<gazebo>` only refers to one)."""
    return {el.get("name", ""): el for el in root.iterchildren("joint") if el.get("name") is not None}


__all__ = [
    "Attribute",
    "ByteEdit",
    "Tag",
    "UneditableXml",
    "XmlSource",
    "escape_attribute",
    "urdf_joints",
]
