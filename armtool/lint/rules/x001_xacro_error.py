from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class XacroError(Rule):
    """
    What it does:
    Reports a xacro file that the xacro package cannot expand: an undefined property or
    argument, an unknown macro, a missing include, a package that cannot be found.

    Why is this bad?
    `ros2 launch` fails at start-up with the same message, usually on someone else's machine.

    Example:
    <xacro:arm_segment name="link1"/>   (macro needs parent and child)

    Use instead:
    <xacro:arm_segment name="link1" parent="base_link" child="link1"/>
    Pass required arguments with `--xacro-arg name:=value`, packages with `--package-path`.
    """

    code, name, severity, target = "X001", "xacro-error", Severity.ERROR, Target.URDF

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
