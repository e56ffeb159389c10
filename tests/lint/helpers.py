"""Lint a snippet written to a temporary file; return what the engine found."""

from __future__ import annotations

from pathlib import Path

from armtool.lint.engine import LintOptions, lint_paths
from armtool.lint.finding import Finding

LINK = '<link name="{name}"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>'


def robot(body: str, name: str = "arm") -> str:
    """A URDF document with the given body (no XML declaration, so line numbers are easy to count)."""
    return f'<robot name="{name}">\n{body}\n</robot>\n'


def revolute(
    name: str, parent: str, child: str, limit: str = 'lower="-1" upper="1" effort="10" velocity="1"', extra: str = ""
) -> str:
    return (
        f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
        f'<axis xyz="0 0 1"/><limit {limit}/>{extra}</joint>'
    )


def lint_text(tmp_path: Path, text: str, filename: str = "robot.urdf", **options: object) -> list[Finding]:
    path = tmp_path / filename
    path.write_text(text, encoding="utf-8")
    return lint_paths([path], LintOptions(**options)).findings  # type: ignore[arg-type]


def codes(findings: list[Finding]) -> list[tuple[str, int]]:
    return [(f.code, f.line) for f in findings]
