"""Inline ignores: `<!-- armtool: ignore[U401] -->` silences the next element (and what it contains);
in YAML, `# armtool: ignore[K104]` silences its own line, or the block that follows it."""

from __future__ import annotations

import re
from typing import NamedTuple

from lxml import etree

from armtool.fileio import read_regular
from armtool.lint.finding import Finding
from armtool.model.xmlsource import XmlSyntaxProblem, parse_xml

_DIRECTIVE = re.compile(r"armtool:\s*ignore(?:\[([A-Za-z0-9_,\s-]*)\])?")


class Suppression(NamedTuple):
    codes: frozenset[str] | None  # None: every rule
    first_line: int
    last_line: int

    def covers(self, finding: Finding, line: int) -> bool:
        if not self.first_line <= line <= self.last_line:
            return False
        return self.codes is None or finding.code in self.codes or finding.name in self.codes


def _codes(match: re.Match[str]) -> frozenset[str] | None:
    """Codes are compared upper-case (U401), rule names lower-case (missing-inertial)."""
    if match.group(1) is None:
        return None
    items = (c.strip() for c in match.group(1).split(","))
    return frozenset(c.upper() if re.fullmatch(r"[A-Za-z]\d+", c) else c.lower() for c in items if c)


def xml_suppressions(data: bytes) -> list[Suppression]:
    if b"armtool:" not in data:
        return []
    try:
        root = parse_xml(data)
    except XmlSyntaxProblem:
        return []
    out: list[Suppression] = []
    for comment in root.iter(etree.Comment):
        match = _DIRECTIVE.search(comment.text or "")
        if match is None:
            continue
        nxt = comment.getnext()
        while nxt is not None and not isinstance(nxt.tag, str):
            nxt = nxt.getnext()
        if nxt is None:
            continue
        last = max((el.sourceline or 0) for el in nxt.iter())
        # From the comment on: libxml2 numbers a multi-line start tag by its last line.
        out.append(Suppression(_codes(match), comment.sourceline or 0, max(last, nxt.sourceline or 0)))
    return out


def yaml_suppressions(text: str) -> list[Suppression]:
    out: list[Suppression] = []
    lines = text.splitlines()
    for i, line in enumerate(lines):
        match = _DIRECTIVE.search(line)
        if match is None or "#" not in line:
            continue
        lineno = i + 1
        if line.strip().startswith("#"):
            # Own-line comment: the next content line and the block indented below it.
            j = i + 1
            while j < len(lines) and (not lines[j].strip() or lines[j].strip().startswith("#")):
                j += 1
            if j >= len(lines):
                continue
            indent = len(lines[j]) - len(lines[j].lstrip())
            k = j + 1
            while k < len(lines) and (not lines[k].strip() or len(lines[k]) - len(lines[k].lstrip()) > indent):
                k += 1
            out.append(Suppression(_codes(match), j + 1, k))
        else:
            out.append(Suppression(_codes(match), lineno, lineno))
    return out


class SuppressionIndex:
    """Reads each file once and answers: is this finding silenced by a comment?"""

    def __init__(self) -> None:
        self._by_path: dict[str, list[Suppression]] = {}

    def prime(self, path: str, data: bytes) -> None:
        """Take the bytes of `path` (as findings name it) that the linter has read already."""
        if path not in self._by_path:
            self._by_path[path] = self._parse(path, data)

    @staticmethod
    def _parse(path: str, data: bytes) -> list[Suppression]:
        if path.endswith((".yaml", ".yml")):
            return yaml_suppressions(data.decode("utf-8", "replace"))
        return xml_suppressions(data)

    def _for(self, path: str) -> list[Suppression]:
        if path not in self._by_path:
            try:
                data = read_regular(path)
            except OSError:
                data = b""
            self._by_path[path] = self._parse(path, data)
        return self._by_path[path]

    def silenced(self, finding: Finding) -> bool:
        places = [(finding.path, finding.line), *finding.related]
        return any(s.covers(finding, line) for path, line in places for s in self._for(path))
