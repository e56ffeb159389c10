from __future__ import annotations

import math
from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.numbers import parse_floats
from armtool.lint.rule import Rule, Target


class ZeroAxis(Rule):
    """
    What it does:
    Reports a moving joint whose <axis xyz> is the zero vector.

    Why is this bad?
    The joint has no direction: KDL and Pinocchio produce NaN transforms or a joint that
    never moves, and the Jacobian loses a column.

    Example:
    <axis xyz="0 0 0"/>

    Use instead:
    <axis xyz="0 0 1"/>
    """

    code, name, severity, target = "U302", "zero-axis", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for joint in ctx.joints:
            axis = joint.axis_el
            if axis is None or not joint.moves or joint.type == "floating":
                continue
            xyz = parse_floats(axis.get("xyz"))
            if xyz and len(xyz) == 3 and all(math.isfinite(v) for v in xyz) and math.hypot(*xyz) < 1e-12:
                yield ctx.finding(
                    self,
                    axis,
                    f"joint '{joint.name}': axis xyz=\"{axis.get('xyz')}\" has zero length",
                    attr="xyz",
                    hint='give the unit direction of motion in the joint frame, e.g. xyz="0 0 1"',
                )
