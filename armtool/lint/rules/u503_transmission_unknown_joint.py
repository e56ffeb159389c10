from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target
from armtool.suggest import did_you_mean


class TransmissionUnknownJoint(Rule):
    """
    What it does:
    Reports a <transmission> whose <joint name> names a joint that does not exist.

    Why is this bad?
    ros_control / ros2_control fail to load the hardware interface for it, and the
    controller manager refuses to start the arm's controllers.

    Example:
    <transmission name="t1"><joint name="shoulder_joint">...   (the joint is "shoulder")

    Use instead:
    <transmission name="t1"><joint name="shoulder">...
    """

    code, name, severity, target = "U503", "transmission-unknown-joint", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for trans in ctx.transmissions:
            for joint in trans.findall("joint"):
                name = joint.get("name")
                if name is not None and name not in ctx.joint_names:
                    yield ctx.finding(
                        self,
                        joint,
                        f"transmission '{trans.get('name')}' names unknown joint '{name}'{did_you_mean(name, ctx.joint_names)}",
                        attr="name",
                        hint="name an existing joint",
                    )
