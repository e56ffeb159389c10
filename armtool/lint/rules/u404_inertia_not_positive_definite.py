from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.numbers import fmt
from armtool.lint.rule import Rule, Target

RELATIVE_TOLERANCE = 1e-6
# Below this (kg·m²) a tensor is a zero placeholder written with float noise (e.g. 1e-20).
ZERO_INERTIA = 1e-12


class InertiaNotPositiveDefinite(Rule):
    """
    What it does:
    Reports an inertia tensor with a negative principal moment (not positive
    semi-definite). A singular but semi-definite tensor with non-zero mass on a moving
    link (a point mass, a rod) is reported at info level; all-zero placeholders are quiet.

    Why is this bad?
    A negative moment of inertia is physically impossible: simulators reject the link or
    accelerate it the wrong way, and dynamics algorithms lose their guarantees.

    Example:
    <inertia ixx="-0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>

    Use instead:
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    Often a sign error in a product of inertia exported from CAD (URDF wants +Ixy, not -Ixy).
    """

    code, name, severity, target = "U404", "inertia-not-positive-definite", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for link, inertia, _values, moments in ctx.inertias():
            scale = max(abs(m) for m in moments)
            if scale < ZERO_INERTIA:
                continue
            if moments[0] > RELATIVE_TOLERANCE * scale:
                continue  # positive definite and not singular: most links
            name = link.get("name")
            shown = ", ".join(fmt(m) for m in moments)
            if moments[0] < -RELATIVE_TOLERANCE * scale:
                yield ctx.finding(
                    self,
                    inertia,
                    f"link '{name}': inertia is not positive definite (principal moments {shown})",
                    hint="recompute the tensor from CAD; check the signs of ixy, ixz, iyz",
                )
            elif moments[0] <= RELATIVE_TOLERANCE * scale and name is not None and ctx.is_moved(name):
                yield ctx.finding(
                    self,
                    inertia,
                    f"link '{name}': inertia is singular (principal moments {shown}); some simulators reject it",
                    hint="give the smallest moment a small positive value",
                ).with_severity(Severity.INFO)
