"""Read XML safely (no entity ever resolved from disk or network) and find places in its text.

lxml gives each element's line; columns, attribute positions and fix offsets come from the text.
"""

from __future__ import annotations

import re
from bisect import bisect_right
from pathlib import Path

from lxml import etree

MAX_FILE_BYTES = 64 * 1024 * 1024


def secure_parser(*, keep_blank_text: bool = True) -> etree.XMLParser:
    # resolve_entities=False: entity references stay unexpanded (billion laughs, XXE);
    # no_network / load_dtd=False: nothing is fetched; huge_tree=False keeps libxml2's limits.
    # keep_blank_text=False drops whitespace-only text between elements (the linter reads no
    # such text; the tree is ~10% faster to build).
    return etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=False,
        remove_comments=False,
        remove_pis=True,
        remove_blank_text=not keep_blank_text,
    )


class XmlSyntaxProblem(Exception):
    def __init__(self, message: str, line: int, column: int) -> None:
        super().__init__(message)
        self.message = message
        self.line = line
        self.column = column


def parse_xml(data: bytes, *, keep_blank_text: bool = True) -> etree._Element:
    """Parse bytes into an element tree, raising XmlSyntaxProblem with a line for any malformation."""
    if not data.strip():
        raise XmlSyntaxProblem("file is empty", 1, 1)
    if b"\x00" in data[:8192] and not data.startswith((b"\xff\xfe", b"\xfe\xff")):  # UTF-16 has NULs
        raise XmlSyntaxProblem("file is binary, not XML", 1, 1)
    try:
        root = etree.fromstring(data, parser=secure_parser(keep_blank_text=keep_blank_text))
    except etree.XMLSyntaxError as exc:
        line, col = exc.position if exc.position else (1, 1)
        msg = exc.msg or str(exc)
        msg = re.sub(r",? line \d+, column \d+\s*(\(<string>, line \d+\))?$", "", msg).strip()
        raise XmlSyntaxProblem(msg, max(line, 1), max(col, 1)) from None
    except ValueError as exc:  # e.g. unicode strings with encoding declaration
        raise XmlSyntaxProblem(str(exc), 1, 1) from None
    if root is None:
        raise XmlSyntaxProblem("no root element", 1, 1)
    return root


def declares_entities(root: etree._Element) -> bool:
    dtd = root.getroottree().docinfo.internalDTD
    return dtd is not None and any(True for _ in dtd.iterentities())


# The rest of a start tag: quoted values may hold '>'. No match: the tag never ends.
_TAG_REST = re.compile(r"""[^"'>]*(?:(?:"[^"]*"|'[^']*')[^"'>]*)*>""")
_ATTR_RE_CACHE: dict[str, re.Pattern[str]] = {}


def _attr_re(attr: str) -> re.Pattern[str]:
    pat = _ATTR_RE_CACHE.get(attr)
    if pat is None:
        pat = re.compile(r"(?<![\w:.-])" + re.escape(attr) + r"\s*=\s*(\"([^\"]*)\"|'([^']*)')")
        _ATTR_RE_CACHE[attr] = pat
    return pat


class SourceText:
    """The text of one file with line offsets, to turn lxml's lines into columns and edit spans."""

    def __init__(self, path: Path, text: str) -> None:
        self.path = path
        self.text = text
        # Offsets of line starts, found on demand: a finding near the top of a long file (the root
        # link's) needs only the first lines indexed, not the whole file.
        self._line_starts = [0]
        self._indexed_all = False

    def _index_to(self, line: int | None = None, offset: int | None = None) -> list[int]:
        """Line starts, known at least up to `line` and past `offset` (or the whole file)."""
        starts = self._line_starts
        if self._indexed_all:
            return starts
        find, append = self.text.find, starts.append
        while (line is None or len(starts) < line) and (offset is None or starts[-1] <= offset):
            i = find("\n", starts[-1])
            if i < 0:
                self._indexed_all = True
                break
            append(i + 1)
        return starts

    @property
    def _starts(self) -> list[int]:
        """Offset of each line's first character."""
        return self._index_to()

    @classmethod
    def read(cls, path: Path, data: bytes | None = None) -> SourceText:
        """The file's text; `data` is its bytes when the caller has read them already."""
        if data is None:
            data = path.read_bytes()
        return cls(path, data.decode("utf-8", errors="replace"))

    def line_offset(self, line: int) -> int:
        line = max(line, 1)
        starts = self._index_to(line=line)
        return starts[min(line, len(starts)) - 1]

    def position(self, offset: int) -> tuple[int, int]:
        """1-based (line, column) of a character offset."""
        starts = self._index_to(offset=offset)
        idx = bisect_right(starts, offset) - 1
        return idx + 1, offset - starts[idx] + 1

    def start_tag_span(self, line: int, tag: str | None) -> tuple[int, int] | None:
        """Offsets of the start tag `<tag ...>` that covers `line` (any element's if tag is None).

        libxml2 numbers an element by the line where its start tag ends, so a tag written over
        several lines is found by looking back from the end of that line.
        """
        begin = self.line_offset(line)
        end_of_line = self.text.find("\n", begin)
        end_of_line = len(self.text) if end_of_line < 0 else end_of_line
        pattern = re.compile(r"<(?![!?/])") if tag is None else re.compile("<" + re.escape(tag) + r"(?=[\s/>])")
        m = pattern.search(self.text, begin, end_of_line)
        if m is None:
            window = max(0, begin - 20_000)
            starts = [hit for hit in pattern.finditer(self.text, window, end_of_line)]
            m = starts[-1] if starts else None
        if m is None:
            return None
        pos = m.start()
        rest = _TAG_REST.match(self.text, m.end())  # up to the first '>' outside quotes
        if rest is None:
            return pos, len(self.text)
        return (pos, rest.end()) if rest.end() >= begin else None

    def attr_value_span(self, line: int, tag: str | None, attr: str) -> tuple[int, int] | None:
        """Offsets of the value (inside the quotes) of `attr` in the start tag on `line`."""
        span = self.start_tag_span(line, tag)
        if span is None:
            return None
        m = _attr_re(attr).search(self.text, span[0], span[1])
        if m is None:
            return None
        group = 2 if m.group(2) is not None else 3
        return m.start(group), m.end(group)

    def locate(self, line: int, tag: str | None, attr: str | None = None) -> tuple[int, int]:
        """Best (line, column) for an element, or for one of its attributes."""
        if attr is not None:
            span = self.attr_value_span(line, tag, attr)
            if span is not None:
                m_start = self.text.rfind(attr, self.line_offset(1), span[0])
                return self.position(m_start if m_start >= 0 else span[0])
        tag_span = self.start_tag_span(line, tag)
        if tag_span is not None:
            return self.position(tag_span[0])
        return line, 1
