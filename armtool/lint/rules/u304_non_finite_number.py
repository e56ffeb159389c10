from __future__ import annotations

import math
from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.numbers import owner, parse_floats
from armtool.lint.rule import Rule, Target


def _finite(raw: str) -> bool:
    values = parse_floats(raw)
    return values is None or all(map(math.isfinite, values))


class NonFiniteNumber(Rule):
    """
    What it does:
    Reports NaN or Inf in a numeric attribute (origins, axes, limits, masses, inertias,
    geometry sizes).

    Why is this bad?
    NaN spreads through every transform computed after it: forward kinematics, collision
    checking and IK all return NaN without saying where it came from.

    Example:
    <origin xyz="0 nan 0.1"/>

    Use instead:
    <origin xyz="0 0 0.1"/>
    Unbounded joints are type="continuous", not upper="inf".
    """

    code, name, severity, target = "U304", "non-finite-number", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        if ctx.raw is not None:
            lowered = ctx.raw.lower()
            if b"nan" not in lowered and b"inf" not in lowered:
                return  # no "nan" or "inf" anywhere in the file: nothing to parse
        if ctx.numbers_plain() or all(_finite(raw) for texts in ctx.numeric_texts().values() for raw in texts):
            return  # "inf" was in a name or a comment, not in a number
        for el, attr, raw, _count, values in ctx.numeric_values():
            if values and not all(map(math.isfinite, values)):
                yield ctx.finding(
                    self,
                    el,
                    f'{owner(el)}<{local_tag(el)} {attr}="{raw}"> contains a non-finite number',
                    attr=attr,
                    hint="write a finite value",
                )
