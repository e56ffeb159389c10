from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class EntityDeclaration(Rule):
    """
    What it does:
    Reports a DOCTYPE that declares XML entities. armtool never expands entities (no file
    or network access, no entity bombs), so the rest of the file is checked without them.

    Why is this bad?
    urdfdom (TinyXML2) does not expand custom entities either, so the robot that ROS sees
    differs from the one the author meant; external entities can read local files.

    Example:
    <!DOCTYPE robot [<!ENTITY len "0.3">]>

    Use instead:
    A xacro property: <xacro:property name="len" value="0.3"/>
    """

    code, name, severity, target = "U003", "entity-declaration", Severity.WARNING, Target.URDF

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
