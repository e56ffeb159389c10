from __future__ import annotations

import math
from collections.abc import Iterator

from lxml import etree

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, FixSafety, Severity
from armtool.lint.numbers import fmt, parse_floats
from armtool.lint.rule import Rule, Target

# Real files write pi as 3.1416 or 3.14159265359: allow a little over pi.
TOLERANCE_RAD = 1e-3
_COMMON_DEGREES = {15, 30, 45, 60, 75, 90, 105, 120, 135, 150, 165, 180, 270, 360}


def wrap(angle: float) -> float:
    """The same rotation angle in (-pi, pi]."""
    wrapped = math.remainder(angle, 2.0 * math.pi)
    return math.pi if wrapped <= -math.pi else wrapped


def _degrees_like(v: float) -> bool:
    return v > 2 * math.pi or (v == int(v) and int(v) in _COMMON_DEGREES)


def looks_like_degrees(values: list[float]) -> bool:
    out = [abs(v) for v in values if abs(v) > math.pi + TOLERANCE_RAD]
    return bool(out) and all(_degrees_like(v) for v in out)


def _out_of_range(raw: str | None) -> bool:
    values = parse_floats(raw)
    if values is None or len(values) != 3 or not all(map(math.isfinite, values)):
        return False
    return any(abs(v) > math.pi + TOLERANCE_RAD for v in values)


class RpyOutOfRange(Rule):
    """
    What it does:
    Reports an <origin rpy="..."> with an angle outside [-π, π] (plus 1e-3 rad, since
    real files write π as 3.1416).

    Why is this bad?
    The rotation is still valid (angles are periodic), but the value is often degrees typed
    where URDF expects radians: rpy="0 0 90" turns 90 rad, the same rotation as 116.6°, not the
    quarter turn that was meant. Values that look like degrees (above 2π, or a whole number of
    common degrees such as 90) are warnings; other values, such as 4.712389 (3π/2), are radians
    that merely go the long way round, and are reported as info.

    Example:
    <origin xyz="0 0 0.1" rpy="0 0 90"/>

    Use instead:
    <origin xyz="0 0 0.1" rpy="0 0 1.5707963"/>

    Fix:
    Safe: wraps each angle to (-π, π], which keeps the same rotation. If the values were
    degrees, convert them by hand instead.
    """

    code, name, severity, target = "U301", "rpy-out-of-range", Severity.WARNING, Target.URDF
    fix_safety = FixSafety.SAFE

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        # Each distinct rpy text is checked once (in the whole file: a superset of those below links
        # and joints); then only origins holding an out-of-range one get a closer look.
        bad = {raw for raw in {origin.get("rpy") for origin in ctx.root.iter("origin")} if _out_of_range(raw)}
        if not bad:
            return
        hit = set()  # the top-level elements holding such an origin
        for origin in ctx.root.iter("origin"):
            if origin.get("rpy") in bad:
                node, parent = origin, origin.getparent()
                while parent is not None and parent is not ctx.root:
                    node, parent = parent, parent.getparent()
                hit.add(node)
        for top in [*ctx.links, *(j.el for j in ctx.joints)]:
            if top not in hit:
                continue
            for origin in top.iter("origin"):
                if origin.get("rpy") in bad:
                    yield from self._check_origin(ctx, top, origin)

    def _check_origin(self, ctx: UrdfContext, top: etree._Element, origin: etree._Element) -> Iterator[Finding]:
        raw = origin.get("rpy")
        values = parse_floats(raw)
        if raw is None or values is None or len(values) != 3 or not all(math.isfinite(v) for v in values):
            return
        if all(abs(v) <= math.pi + TOLERANCE_RAD for v in values):
            return
        tokens = raw.split()
        wrapped = [fmt(wrap(v)) if abs(v) > math.pi + TOLERANCE_RAD else tok for v, tok in zip(values, tokens)]
        owner = f"{top.tag} '{top.get('name')}'"
        if looks_like_degrees(values):
            radians = " ".join(fmt(math.radians(v)) for v in values)
            message = f'{owner}: rpy="{raw}" is outside [-π, π] and looks like degrees'
            hint = f'URDF angles are radians: rpy="{radians}" if degrees were meant'
        else:
            message = f'{owner}: rpy="{raw}" is outside [-π, π]'
            hint = f'write the same rotation as rpy="{" ".join(wrapped)}"'
            if not any(_degrees_like(abs(v)) for v in values if abs(v) > math.pi + TOLERANCE_RAD):
                # radians beyond π: the same rotation, written the long way round; nothing is wrong
                finding = ctx.finding(self, origin, message, attr="rpy", hint=hint, fix_value=" ".join(wrapped))
                yield finding.with_severity(Severity.INFO)
                return
            # one angle plainly in degrees (90 beside 4.71): a warning, whatever the others look like
            message += " and some of it looks like degrees"
            hint += "; URDF angles are radians"
        yield ctx.finding(self, origin, message, attr="rpy", hint=hint, fix_value=" ".join(wrapped))
