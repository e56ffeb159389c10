from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class UrdfIsXacro(Rule):
    """
    What it does:
    Says that a file named `.urdf` is a xacro (it has `xacro:` elements or `${...}`
    expressions) and was expanded as one. Reported by the loader; its other findings are
    those of the expansion.

    Why is this bad?
    Tools that read a `.urdf` as plain URDF (robot_state_publisher given the file, check_urdf,
    Gazebo, RViz) see unexpanded macros: links a `<xacro:macro>` would create are missing
    (links named but not defined, several roots) and `${...}` stays text. ROS launch files run
    xacro on it and work, so the mistake goes unnoticed until another tool reads the file.

    Example:
    arm.urdf containing <xacro:include filename="..."/>

    Use instead:
    arm.urdf.xacro (and xacro arm.urdf.xacro > arm.urdf where a plain URDF is needed)
    """

    code, name, severity, target = "X002", "urdf-is-xacro", Severity.INFO, Target.URDF

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
