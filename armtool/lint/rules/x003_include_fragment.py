from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class IncludeFragment(Rule):
    """
    What it does:
    Says that a xacro file is an include-only fragment of another file of its package and was
    checked through it, not as a robot of its own: it does not expand or connect alone (xacro
    fails on an argument or macro of the includer, a joint names a link only the includer
    defines), and a file of the package `<xacro:include>`s it. Its findings are those of the
    includer's expansion that point into it; when the includer is linted in the same run they
    come with the includer's. Reported by the loader (armtool.lint.fragments).

    Why is this bad?
    It is not: linted alone, such a file would get untrue errors (unknown links, "joints form a
    loop", undefined arguments). The note says where its checks came from.

    Example:
    left_end_effector.urdf.xacro: <joint name="left_hand"><parent link="left_wrist"/>...
    (left_wrist is defined by baxter_base.urdf.xacro, which includes this file)

    Use instead:
    Nothing to change; lint the including file to check the robot.
    """

    code, name, severity, target = "X003", "include-fragment", Severity.INFO, Target.URDF

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
