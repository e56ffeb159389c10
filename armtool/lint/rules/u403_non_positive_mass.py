from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.numbers import parse_floats
from armtool.lint.rule import Rule, Target


def _not_positive(text: str) -> bool:
    value = parse_floats(text)
    return value is not None and len(value) == 1 and value[0] <= 0


class NonPositiveMass(Rule):
    """
    What it does:
    Reports a negative mass, and a zero mass on a link moved by a non-fixed joint.
    A zero mass on a fixed frame (a tool point, a sensor frame) is fine and not reported.

    Why is this bad?
    Simulators reject negative masses and drop or explode massless moving bodies;
    dynamics (gravity torques, RNEA) divides by or multiplies with it.

    Example:
    <mass value="0"/>   on a link driven by a revolute joint

    Use instead:
    <mass value="0.35"/>   (from CAD or a scale)
    """

    code, name, severity, target = "U403", "non-positive-mass", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        bad = sorted(text for text in set(ctx.xpath(ctx.below_links("inertial/mass/@value"))) if _not_positive(text))
        if not bad:
            return  # every mass in the file is a positive number (or not a number: U305's)
        # Only masses written as one of those texts (mass 0 on a fixed frame is common), in file order.
        same = " or ".join(f"@value=$v{i}" for i in range(len(bad)))
        for mass in ctx.xpath(ctx.below_links(f"inertial/mass[{same}]"), **{f"v{i}": t for i, t in enumerate(bad)}):
            link = mass.getparent().getparent()
            if link.find("inertial/mass") is not mass:
                continue  # the first <inertial>'s <mass> counts, as link.find("inertial/mass") would
            value = parse_floats(mass.get("value"))
            if not value or len(value) != 1:
                continue
            name = link.get("name")
            if value[0] < 0:
                yield ctx.finding(
                    self,
                    mass,
                    f"link '{name}' has negative mass {mass.get('value')}",
                    attr="value",
                    hint="masses are positive, in kg",
                )
            elif value[0] == 0 and name is not None and ctx.is_moved(name):
                yield ctx.finding(
                    self,
                    mass,
                    f"link '{name}' is moved by a joint but has mass 0",
                    attr="value",
                    hint="give the link's real mass in kg, or remove <inertial> if it is a frame",
                ).with_severity(Severity.WARNING)
