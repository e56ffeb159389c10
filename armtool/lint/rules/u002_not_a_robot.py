from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class NotARobot(Rule):
    """
    What it does:
    Reports a .urdf or expanded .xacro file whose root element is not <robot>.
    Reported by the loader.

    Why is this bad?
    urdfdom only reads <robot>; a launch file or SDF saved as .urdf loads as nothing.

    Example:
    <sdf version="1.6"><model name="arm">...</model></sdf>

    Use instead:
    <robot name="arm">...</robot>
    """

    code, name, severity, target = "U002", "not-a-robot", Severity.ERROR, Target.URDF

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
