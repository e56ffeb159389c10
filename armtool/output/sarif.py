"""SARIF 2.1.0 for code-scanning UIs; each rule's documentation comes from its docstring.
The lint rules are the default; `traj check` passes its own codes and driver name.

What GitHub's code scanning needs of a result (docs.github.com, "SARIF support for code
scanning": partialFingerprints, region.startLine/startColumn/endLine/endColumn and
artifactLocation.uri are marked required; fullDescription.text is limited to 1024 characters):

* `artifactLocation.uri` is a URI reference, so the path is percent-encoded (a space, `#`, `ü`),
  relative to the repository root (the nearest directory above the working directory with a
  `.git`, else the working directory) with `uriBaseId: "%SRCROOT%"`, whatever way the inputs were
  given; `run.originalUriBaseIds` says what %SRCROOT% is. Symbolic links are resolved first, as
  GitHub asks. A file outside the root gets an absolute `file://` URI.
* `region` spans the token the finding points at: a whole start tag `<joint ...>`, an attribute
  with its value, or else the rest of the line. Columns count Unicode code points
  (`columnKind: "unicodeCodePoints"`), as armtool's columns do.
* `partialFingerprints.primaryLocationLineHash` identifies the result across commits by what is
  written there, not by its line number: a hash of the source text from the finding's line on
  (the first 100 non-blank characters), then `:N` for the N-th line of the file with the same hash.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import quote

from armtool import __version__
from armtool.docs_links import DOCS_URL
from armtool.fileio import read_regular
from armtool.lint.finding import Finding, Severity
from armtool.lint.registry import RULES
from armtool.output.base import LintReport

_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}
HELP_URI = DOCS_URL + "rules.md#{code}"


@dataclass(frozen=True)
class SarifRule:
    """One `reportingDescriptor`: what a code means and where its documentation lives."""

    code: str
    name: str
    summary: str
    documentation: str
    severity: Severity
    help_uri: str


@dataclass(frozen=True)
class SarifTool:
    """The `tool.driver` of the run: its name and every rule it can report."""

    name: str
    rules: Sequence[SarifRule]


def lint_tool() -> SarifTool:
    """`armtool lint`'s driver: every registered rule, documented by its docstring."""
    return SarifTool(
        "armtool",
        [
            SarifRule(
                rule.code,
                rule.name,
                rule.summary(),
                rule.documentation(),
                rule.severity,
                HELP_URI.format(code=rule.code.lower()),
            )
            for rule in RULES
        ],
    )


SRCROOT = "%SRCROOT%"
MAX_DESCRIPTION = 1024  # GitHub's limit for fullDescription.text
_HASH_CHARS = 100  # non-blank characters of source text a fingerprint covers
# An attribute with its quoted value, where a finding's column points at the attribute's name.
_ATTRIBUTE = re.compile(r"""[\w:.-]+\s*=\s*(?:"[^"]*"|'[^']*')""")


def repository_root(start: Path) -> Path:
    """The nearest directory at or above `start` with a `.git` (a checkout or a worktree), else `start`."""
    for directory in [start, *start.parents]:
        if (directory / ".git").exists():
            return directory
    return start


def short_description(text: str) -> str:
    """`text` cut to GitHub's 1024 characters, at a word, marked with an ellipsis."""
    if len(text) <= MAX_DESCRIPTION:
        return text
    cut = text[: MAX_DESCRIPTION - 1].rsplit(None, 1)[0]
    return cut + "…"


class _Sources:
    """The text of each finding's file (read once), for regions and fingerprints; a file that cannot
    be read (stdin, removed since) still gets a one-character region and a fingerprint of the finding."""

    def __init__(self) -> None:
        self._lines: dict[str, list[str] | None] = {}
        self._hashes: dict[str, list[str]] = {}

    def lines(self, path: str) -> list[str] | None:
        if path not in self._lines:
            try:  # as the engine reads it: a regular file, never blocking on a FIFO
                self._lines[path] = read_regular(path).decode("utf-8", errors="replace").splitlines()
            except (OSError, ValueError):
                self._lines[path] = None
        return self._lines[path]

    def region(self, f: Finding) -> dict[str, int]:
        start_line, start_col = max(f.line, 1), max(f.column, 1)
        end_line, end_col = start_line, start_col + 1
        lines = self.lines(f.path)
        if lines is not None and start_line <= len(lines):
            text = lines[start_line - 1]
            i = start_col - 1
            if i < len(text) and text[i] == "<":
                end_line, end_col = self._tag_end(lines, start_line, i)
            elif (m := _ATTRIBUTE.match(text, i)) is not None:
                end_col = m.end() + 1
            elif text[i:].strip():
                end_col = len(text.rstrip()) + 1
        return {"startLine": start_line, "startColumn": start_col, "endLine": end_line, "endColumn": end_col}

    @staticmethod
    def _tag_end(lines: list[str], line: int, col: int) -> tuple[int, int]:
        """(line, column after) the `>` that closes the start tag at lines[line-1][col] (quotes skipped)."""
        quote_char = ""
        for number in range(line, min(len(lines), line + 200) + 1):
            text = lines[number - 1]
            for k in range(col + 1 if number == line else 0, len(text)):
                ch = text[k]
                if quote_char:
                    quote_char = "" if ch == quote_char else quote_char
                elif ch in "\"'":
                    quote_char = ch
                elif ch == ">":
                    return number, k + 2
        return line, len(lines[line - 1].rstrip()) + 1

    def fingerprint(self, f: Finding) -> str:
        lines = self.lines(f.path)
        if lines is None or not 1 <= f.line <= len(lines):
            digest = hashlib.sha256(f"{f.code}\0{f.message}".encode()).hexdigest()[:16]
            return f"{digest}:1"
        hashes = self._hashes.get(f.path)
        if hashes is None:
            hashes = self._hashes[f.path] = self._line_hashes(lines)
        digest = hashes[f.line - 1]
        return f"{digest}:{hashes[: f.line].count(digest)}"

    @staticmethod
    def _line_hashes(lines: list[str]) -> list[str]:
        """Per line, a hash of the non-blank text from that line on (its first _HASH_CHARS characters)."""
        squeezed = ["".join(line.split()) for line in lines]
        out = []
        for i in range(len(lines)):
            window, j = "", i
            while len(window) < _HASH_CHARS and j < len(lines):
                window += squeezed[j] + "\n"
                j += 1
            out.append(hashlib.sha256(window[:_HASH_CHARS].encode()).hexdigest()[:16])
        return out


def _artifact(path: str, root: str) -> dict[str, str]:
    """`path` as an artifactLocation: percent-encoded, relative to `root` (both with symlinks resolved)."""
    if path == "-":  # stdin
        return {"uri": "-"}
    real = os.path.realpath(path)
    try:
        inside = os.path.commonpath([real, root]) == root
    except ValueError:  # another drive (Windows): not under the root
        inside = False
    if inside:
        relative = os.path.relpath(real, root).replace(os.sep, "/")
        return {"uri": quote(relative, safe="/"), "uriBaseId": SRCROOT}
    return {"uri": Path(real).as_uri()}


class SarifFormatter:
    def __init__(self, tool: SarifTool | None = None, root: Path | None = None) -> None:
        self._tool = tool
        self._root = root

    def render(self, report: LintReport, *, color: bool) -> str:
        tool = self._tool or lint_tool()
        root = os.path.realpath(self._root or repository_root(Path.cwd()))
        rules = [
            {
                "id": rule.code,
                "name": rule.name,
                "shortDescription": {"text": short_description(rule.summary)},
                "fullDescription": {"text": short_description(rule.documentation)},
                "help": {"text": rule.documentation},
                "helpUri": rule.help_uri,
                "defaultConfiguration": {"level": _LEVEL[rule.severity]},
            }
            for rule in tool.rules
        ]
        index = {rule.code: i for i, rule in enumerate(tool.rules)}
        sources = _Sources()
        results = []
        for f in report.findings:
            text = f.message + (f"\nhint: {f.hint}" if f.hint else "")
            results.append(
                {
                    "ruleId": f.code,
                    "ruleIndex": index.get(f.code, 0),
                    "level": _LEVEL[f.severity],
                    "message": {"text": text},
                    "locations": [
                        {"physicalLocation": {"artifactLocation": _artifact(f.path, root), "region": sources.region(f)}}
                    ],
                    "partialFingerprints": {"primaryLocationLineHash": sources.fingerprint(f)},
                }
            )
        doc = {
            "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
            "version": "2.1.0",
            "runs": [
                {
                    "tool": {
                        "driver": {
                            "name": tool.name,
                            "version": __version__,
                            "informationUri": "https://github.com/armtool/armtool",
                            "rules": rules,
                        }
                    },
                    "originalUriBaseIds": {
                        SRCROOT: {
                            "uri": Path(root).as_uri().rstrip("/") + "/",
                            "description": {"text": "The repository root (or the working directory outside one)."},
                        }
                    },
                    "columnKind": "unicodeCodePoints",
                    "results": results,
                }
            ],
        }
        return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
