"""Kinematics-only models: deliberate, so reported once for the model, not per link or joint.

moveit_resources' panda.urdf and most ROS-Industrial support packages carry no <inertial> at
all, and ROS-Industrial writes effort="0" on every joint as "unknown". Such a model is meant for
planning, not for simulation or dynamics. In a model without any <inertial>, effort="0" is a
placeholder wherever it is written, also beside joints with a real effort (an arm at 0 beside a
torso at 100): nothing in it can be simulated anyway. In a model with dynamics, one missing
inertial or one zero effort among real ones is still a mistake and is still reported per link or
joint. Two or more moving parts are needed to call it a convention: a lone joint cannot tell a
convention from a slip.
"""

from __future__ import annotations

from armtool.lint.context import UrdfContext
from armtool.lint.numbers import parse_floats


def _moved_links(ctx: UrdfContext) -> list[str]:
    return [name for name in ctx.link_name.values() if name is not None and ctx.is_moved(name)]


def has_no_inertials(ctx: UrdfContext) -> bool:
    """No link of the model has an <inertial>, and at least two links move."""
    return len(_moved_links(ctx)) >= 2 and all(ctx.inertial_of(link) is None for link in ctx.links)


def efforts(ctx: UrdfContext) -> list[float]:
    out = []
    for joint in ctx.joints:
        if joint.moves and joint.limit() is not None:
            value = parse_floats(joint.limits.get("effort"))
            if value and len(value) == 1:
                out.append(value[0])
    return out


def all_efforts_zero(ctx: UrdfContext) -> bool:
    """Every moving joint's effort limit is 0 (at least two of them): ROS-Industrial's "unknown"."""
    values = efforts(ctx)
    return len(values) >= 2 and all(v == 0 for v in values)


def zero_efforts(ctx: UrdfContext) -> int:
    """How many moving joints have effort="0"."""
    return sum(1 for v in efforts(ctx) if v == 0)


def efforts_are_placeholders(ctx: UrdfContext) -> bool:
    """effort="0" is a placeholder here: on every joint, or anywhere in a model with no inertials."""
    return all_efforts_zero(ctx) or (has_no_inertials(ctx) and zero_efforts(ctx) > 0)


def description(ctx: UrdfContext) -> str:
    """The one info message for a kinematics-only model."""
    reasons = []
    if has_no_inertials(ctx):
        reasons.append("no link has an <inertial>")
    if all_efforts_zero(ctx):
        reasons.append('every joint has effort="0" (the ROS-Industrial convention for "unknown")')
    elif reasons and zero_efforts(ctx):
        count, total = zero_efforts(ctx), len(efforts(ctx))
        reasons.append(f'{count} of {total} joints have effort="0", placeholders like the missing inertials')
    return (
        f"kinematics-only model: {' and '.join(reasons)}; fine for planning and IK, not for simulation or "
        "dynamics (per-link and per-joint findings of this kind are not reported)"
    )
