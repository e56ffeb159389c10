from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class InvalidXml(Rule):
    """
    What it does:
    Reports a robot description that is not well-formed XML: empty, truncated, binary,
    or with a syntax error. Reported by the loader; no other rule can run on the file.

    Why is this bad?
    robot_state_publisher, MoveIt and every simulator refuse to load it, often far from
    where the file was edited.

    Example:
    <robot name="arm"><link name="base"></robot>

    Use instead:
    <robot name="arm"><link name="base"/></robot>
    """

    code, name, severity, target = "U001", "invalid-xml", Severity.ERROR, Target.URDF

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
