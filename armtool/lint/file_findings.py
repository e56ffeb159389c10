"""Findings a loader reports about a whole file (invalid YAML, a xacro that fails): the rule of the
code gives their name and severity; the linter and the per-format loaders both make them."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from armtool.lint.finding import Finding
from armtool.lint.locate import display_path
from armtool.lint.registry import rule_class

if TYPE_CHECKING:
    from armtool.model.xacro_source import XacroFailure


def file_finding(code: str, path: Path, line: int, column: int, message: str, hint: str | None = None) -> Finding:
    """A finding a loader reports about a whole file (its code's rule gives name and severity)."""
    rule = rule_class(code)
    return Finding(display_path(path), line, column, rule.code, rule.name, rule.severity, message, hint)


def xacro_finding(exc: XacroFailure) -> Finding:
    """X001 at the include or macro call of the expanded file that leads to xacro's error."""
    finding = file_finding("X001", exc.path, exc.line, 1, f"xacro failed: {exc.message}", exc.hint)
    related = tuple((display_path(loc.path), loc.line) for loc in exc.trail)
    return finding._replace(related=related) if related else finding
