from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.numbers import fmt
from armtool.lint.rule import Rule, Target
from armtool.lint.rules.u404_inertia_not_positive_definite import RELATIVE_TOLERANCE as NEGATIVE_TOLERANCE
from armtool.lint.rules.u404_inertia_not_positive_definite import ZERO_INERTIA

RELATIVE_TOLERANCE = 1e-3
# A tensor whose largest moment is below this share of the model's largest changes no dynamics:
# a dummy inertial (mass 1e-6, every entry 1e-6) on a frame link, reported at info.
NEGLIGIBLE_SHARE = 1e-3


class InertiaTriangleInequality(Rule):
    """
    What it does:
    Reports an inertia tensor whose principal moments break the triangle inequality
    (the largest exceeds the sum of the other two by more than 0.1 %). A smallest moment that is
    negative only by floating-point rounding (-7.6e-18 beside 0.03: within U404's relative
    tolerance, so U404 calls the tensor singular, not indefinite) counts as 0: Sawyer's right_hand
    with ixx = iyy = izz = ixy = ixz = iyz = 0.01 has moments 0, 0, 0.03. A tensor negligible beside
    the model's others (its largest moment below 0.1 % of the model's largest: the dummy inertials
    of anymal's or Sawyer's frame links, every entry 1e-6 or 1e-8) is reported at info: it breaks
    the inequality by the letter but changes no dynamics.

    Why is this bad?
    No rigid body of positive mass has such moments: the tensor is a typo or a unit mix-up
    (g·mm² beside kg·m²). Gazebo/DART reject it; dynamics go wrong silently elsewhere.

    Example:
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.05"/>

    Use instead:
    <inertia ixx="0.03" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.05"/>
    """

    code, name, severity, target = "U405", "inertia-triangle-inequality", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        inertias = ctx.inertias()
        largest = max((m[2] for *_, m in inertias), default=0.0)
        for link, inertia, _values, (a, b, c) in inertias:
            if c < ZERO_INERTIA or a < -NEGATIVE_TOLERANCE * c:
                continue  # zero placeholders are fine; clearly negative moments are U404's
            a, b = (0.0 if abs(m) <= NEGATIVE_TOLERANCE * c else m for m in (a, b))  # rounding: 0
            if c <= (a + b) * (1 + RELATIVE_TOLERANCE):
                continue
            message = (
                f"link '{link.get('name')}': principal moments {fmt(a)}, {fmt(b)}, {fmt(c)} break the "
                f"triangle inequality ({fmt(c)} > {fmt(a)} + {fmt(b)})"
            )
            negligible = c < NEGLIGIBLE_SHARE * largest
            finding = ctx.finding(
                self,
                inertia,
                message + ("; negligible beside the model's other links (a dummy?)" if negligible else ""),
                hint="recompute the tensor; check units (kg·m²) and that every moment is about the centre of mass",
            )
            yield finding.with_severity(Severity.INFO) if negligible else finding
