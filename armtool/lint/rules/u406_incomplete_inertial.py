from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target

_INCOMPLETE = (
    "*[local-name()='link']/inertial"
    "[not(mass[1]/@value) or not(inertia[1][@ixx and @ixy and @ixz and @iyy and @iyz and @izz])]"
)


_COMPLETE = ("mass[1]/@value", *(f"inertia[1]/@{k}" for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")))


class IncompleteInertial(Rule):
    """
    What it does:
    Reports an <inertial> without <mass value> or without <inertia>.

    Why is this bad?
    urdfdom rejects the model ("inertial has no mass" / "no inertia").

    Example:
    <inertial><mass value="1.0"/></inertial>

    Use instead:
    <inertial><mass value="1.0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    """

    code, name, severity, target = "U406", "incomplete-inertial", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        # Counting in libxml2 first: complete when every <inertial> has a first <mass> with a value
        # and a first <inertia> with all six moments (an XPath predicate per element costs more).
        total = ctx.xpath(f"count({ctx.below_links('inertial')})")
        if all(ctx.xpath(f"count({ctx.below_links('inertial/' + part)})") == total for part in _COMPLETE):
            return
        # Only the incomplete ones, in file order (as the links and their <inertial>s come).
        for inertial in ctx.xpath(_INCOMPLETE):
            link = inertial.getparent()
            mass = inertial.find("mass")
            missing = []
            if mass is None or mass.get("value") is None:
                missing.append('<mass value="..."/>')
            inertia = inertial.find("inertia")
            if inertia is None:
                missing.append("<inertia .../>")
            else:
                absent = [k for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz") if inertia.get(k) is None]
                if absent:
                    missing.append("inertia attributes " + ", ".join(absent))
            if missing:
                yield ctx.finding(
                    self,
                    inertial,
                    f"link '{link.get('name')}': <inertial> lacks {' and '.join(missing)}",
                    hint="give all of mass and ixx, ixy, ixz, iyy, iyz, izz",
                )
