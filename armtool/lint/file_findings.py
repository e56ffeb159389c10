"""Findings a loader reports about a whole file (invalid YAML, a xacro that fails): the rule of the
code gives their name and severity; the linter and the per-format loaders both make them."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from armtool.lint.finding import Finding
from armtool.lint.locate import display_path
from armtool.lint.registry import rule_class

if TYPE_CHECKING:
    import yaml

    from armtool.model.xacro_source import XacroFailure

# The code of what a file kind's loader reports (not XML, not YAML, ...), by the kind's value as
# engine.FileKind and rule.Target name it.
LOADER_CODE: dict[str, str] = {
    "urdf": "U001",
    "xacro": "X001",
    "srdf": "S001",
    "kinematics": "K001",
    "joint_limits": "L001",
    "pilz": "P001",
    "controllers": "C001",
    "setup_assistant": "M101",
}


def file_finding(code: str, path: Path, line: int, column: int, message: str, hint: str | None = None) -> Finding:
    """A finding a loader reports about a whole file (its code's rule gives name and severity)."""
    rule = rule_class(code)
    return Finding(display_path(path), line, column, rule.code, rule.name, rule.severity, message, hint)


def invalid_yaml(code: str, path: Path, exc: yaml.YAMLError) -> Finding:
    """The loader finding of a YAML file PyYAML (or armtool.yamlload's alias guard) refused, at
    the mark of its problem."""
    mark = getattr(exc, "problem_mark", None)
    line, col = (mark.line + 1, mark.column + 1) if mark else (1, 1)
    problem = getattr(exc, "problem", None) or str(exc)
    return file_finding(code, path, line, col, f"invalid YAML: {problem}")


def xacro_finding(exc: XacroFailure) -> Finding:
    """X001 at the include or macro call of the expanded file that leads to xacro's error."""
    finding = file_finding("X001", exc.path, exc.line, 1, f"xacro failed: {exc.message}", exc.hint)
    related = tuple((display_path(loc.path), loc.line) for loc in exc.trail)
    return finding._replace(related=related) if related else finding
