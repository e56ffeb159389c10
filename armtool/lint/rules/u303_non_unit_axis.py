from __future__ import annotations

import math
from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, FixSafety, Severity
from armtool.lint.numbers import fmt, parse_floats
from armtool.lint.rule import Rule, Target

TOLERANCE = 1e-4


class NonUnitAxis(Rule):
    """
    What it does:
    Reports a moving joint whose <axis xyz> is not a unit vector (length off by more than 1e-4).

    Why is this bad?
    Parsers disagree: some normalize the axis, others scale the joint motion or the
    Jacobian by its length, so the same URDF moves differently in different tools.

    Example:
    <axis xyz="0 0 2"/>

    Use instead:
    <axis xyz="0 0 1"/>

    Fix:
    Safe: divides the vector by its length (the direction is unchanged).
    """

    code, name, severity, target = "U303", "non-unit-axis", Severity.WARNING, Target.URDF
    fix_safety = FixSafety.SAFE

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for joint in ctx.joints:
            axis = joint.axis_el
            if axis is None or not joint.moves or joint.type == "floating":
                continue
            xyz = parse_floats(axis.get("xyz"))
            if not xyz or len(xyz) != 3 or not all(math.isfinite(v) for v in xyz):
                continue
            norm = math.hypot(*xyz)
            if norm < 1e-12 or abs(norm - 1.0) <= TOLERANCE:
                continue
            unit = " ".join(fmt(v / norm) for v in xyz)
            yield ctx.finding(
                self,
                axis,
                f"joint '{joint.name}': axis xyz=\"{axis.get('xyz')}\" has length {fmt(norm)}, not 1",
                attr="xyz",
                hint=f'use xyz="{unit}"',
                fix_value=unit,
            )
