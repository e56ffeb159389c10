"""Where a key of a TOML file is written, so that a configuration error names file:line.

tomllib gives the values only, without places, and no maintained TOML reader for Python reports
the line of a key; this reads the places from the text. It is called only once tomllib has
accepted the document, so the lines it reads are valid TOML: table headers (`[a.b]`, `[[a.b]]`)
and key/value lines (`a.b = ...`, keys bare or quoted), with multi-line strings skipped.
"""

from __future__ import annotations

import json
import re

_BARE = r"[A-Za-z0-9_-]+"
_BASIC = r'"(?:[^"\\]|\\.)*"'
_LITERAL = r"'[^']*'"
_PART = re.compile(rf"\s*({_BARE}|{_BASIC}|{_LITERAL})\s*")
_KEY = rf"\s*(?:{_BARE}|{_BASIC}|{_LITERAL})\s*(?:\.\s*(?:{_BARE}|{_BASIC}|{_LITERAL})\s*)*"
_HEADER = re.compile(rf"\s*\[\[?({_KEY})\]")
_ASSIGNMENT = re.compile(rf"\s*({_KEY})=")

Key = tuple[str, ...]


def _parts(key: str) -> Key:
    parts = []
    for match in _PART.finditer(key):
        text = match.group(1)
        if text.startswith('"'):
            text = json.loads(text)  # TOML's basic-string escapes are JSON's (plus \U, rare in a key)
        elif text.startswith("'"):
            text = text[1:-1]
        parts.append(text)
    return tuple(parts)


def key_lines(text: str) -> dict[Key, int]:
    """Every table header and key of a TOML document: its full dotted key → the line (1-based)
    where it is first written."""
    lines: dict[Key, int] = {}
    table: Key = ()
    open_string: str | None = None  # the delimiter of a multi-line string that is still open
    for number, line in enumerate(text.splitlines(), 1):
        if open_string is not None:
            if line.count(open_string) % 2 == 1:
                open_string = None
            continue
        header = _HEADER.match(line)
        if header is not None:
            table = _parts(header.group(1))
            lines.setdefault(table, number)
            continue
        assignment = _ASSIGNMENT.match(line)
        if assignment is None:
            continue
        lines.setdefault(table + _parts(assignment.group(1)), number)
        rest = line[assignment.end() :]
        for delimiter in ('"""', "'''"):
            if rest.count(delimiter) % 2 == 1:
                open_string = delimiter
    return lines


def line_of(lines: dict[Key, int], key: Key) -> int | None:
    """The line of `key`; else of the first key written below it (`[a.b]` writes `a` only
    implicitly); else of the nearest enclosing key that is written (the keys of an inline table
    are on its line)."""
    if key in lines:
        return lines[key]
    below = [number for written, number in lines.items() if written[: len(key)] == key]
    if below:
        return min(below)
    for size in range(len(key) - 1, 0, -1):
        if key[:size] in lines:
            return lines[key[:size]]
    return None
