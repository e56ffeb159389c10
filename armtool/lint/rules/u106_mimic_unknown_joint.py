from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target
from armtool.suggest import did_you_mean


class MimicUnknownJoint(Rule):
    """
    What it does:
    Reports a <mimic joint="..."> that names a joint that does not exist, or the joint itself.

    Why is this bad?
    The mimic joint never moves (or MoveIt fails to load the model), so a gripper's second
    finger stays put in planning and simulation.

    Example:
    <mimic joint="finger_joint1"/>   (the joint is called left_finger_joint)

    Use instead:
    <mimic joint="left_finger_joint" multiplier="1" offset="0"/>
    """

    code, name, severity, target = "U106", "mimic-unknown-joint", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for joint in ctx.joints:
            mimic = joint.mimic_el
            if mimic is None:
                continue
            target = mimic.get("joint")
            if target is None:
                yield ctx.finding(
                    self,
                    mimic,
                    f"joint '{joint.name}': <mimic> has no joint attribute",
                    hint="name the joint to follow",
                )
            elif target == joint.name:
                yield ctx.finding(
                    self, mimic, f"joint '{joint.name}' mimics itself", attr="joint", hint="name another joint"
                )
            elif target not in ctx.joint_names:
                yield ctx.finding(
                    self,
                    mimic,
                    f"joint '{joint.name}' mimics unknown joint '{target}'{did_you_mean(target, ctx.joint_names - {joint.name})}",
                    attr="joint",
                    hint="name an existing joint",
                )
