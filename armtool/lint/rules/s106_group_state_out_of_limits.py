from __future__ import annotations

import math
from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.numbers import fmt, parse_floats
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext

TOLERANCE = 1e-6
ONE_DOF = ("revolute", "continuous", "prismatic")


class GroupStateOutOfLimits(Rule):
    """
    What it does:
    Reports a <group_state> joint value outside the URDF joint's [lower, upper] limits
    (radians for revolute joints, metres for prismatic ones; continuous joints have no
    bounds), and a value that is not a number.

    Why is this bad?
    MoveIt accepts the named pose, but the start or goal state is invalid: planning to
    "home" fails with "goal state is out of bounds", and a pose that is the start state
    makes every plan fail until the joint is moved back inside its limits.

    Example:
    <group_state name="home" group="arm"><joint name="elbow" value="90"/></group_state>

    Use instead:
    <group_state name="home" group="arm"><joint name="elbow" value="1.5708"/></group_state>
    """

    code, name, severity, target = "S106", "group-state-out-of-limits", Severity.ERROR, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        urdf = ctx.urdf
        if urdf is None:
            return
        for state in ctx.elements("group_state"):
            owner = f"group_state '{state.get('name')}'"
            for el in state:
                if local_tag(el) != "joint":
                    continue
                name = el.get("name")
                joint = urdf.joint(name) if name is not None else None
                if name is None or joint is None:
                    continue
                raw = el.get("value")
                values = parse_floats(raw)
                one_dof = joint.type in ONE_DOF
                if (
                    values is None
                    or not values
                    or (one_dof and len(values) != 1)
                    or not all(map(math.isfinite, values))
                ):
                    shown = "no value" if raw is None else f"value '{raw}'"
                    yield ctx.finding(
                        self,
                        el,
                        f"{owner}: joint '{name}' has {shown}, not a number",
                        attr="value" if raw is not None else "name",
                        hint='write one number, e.g. value="0.0"' if one_dof else "write the joint's values as numbers",
                    )
                    continue
                if not one_dof:
                    continue
                limits = urdf.limits_of(name)
                if limits is None:
                    continue
                lo, hi = limits
                value = values[0]
                if lo - TOLERANCE <= value <= hi + TOLERANCE:
                    continue
                unit = "m" if joint.type == "prismatic" else "rad"
                yield ctx.finding(
                    self,
                    el,
                    f"{owner}: joint '{name}' = {fmt(value)} is outside its limits [{fmt(lo)}, {fmt(hi)}] {unit}",
                    attr="value",
                    hint=_hint(value, lo, hi, joint.type == "prismatic"),
                )


def _hint(value: float, lo: float, hi: float, prismatic: bool) -> str:
    if not prismatic and abs(value) > 2 * math.pi and lo <= math.radians(value) <= hi:
        return f"values are radians: {fmt(value)} degrees is {fmt(round(math.radians(value), 4))}"
    if prismatic and abs(value) >= 1 and lo <= value / 1000 <= hi:
        return f"values are metres: {fmt(value)} mm is {fmt(value / 1000)}"
    return f"use a value within [{fmt(lo)}, {fmt(hi)}], or widen the joint's <limit> if the robot really reaches it"
