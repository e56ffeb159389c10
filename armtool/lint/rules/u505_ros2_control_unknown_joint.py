from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.rule import Rule, Target
from armtool.suggest import did_you_mean


class Ros2ControlUnknownJoint(Rule):
    """
    What it does:
    Reports a `<joint>` inside a `<ros2_control>` tag that names a joint the URDF does not
    have (`<gpio>` and `<sensor>` entries are not joints and are not checked).

    Why is this bad?
    ros2_control's component parser requires every joint of a `<ros2_control>` tag to be in the
    URDF (since Jazzy it throws std::runtime_error, ros2_control #1256; before, the hardware
    interface exported state and command interfaces no joint has, and the controllers claiming
    the real joint found none). The controller manager does not start.

    Example:
    <ros2_control name="arm" type="system">
      <joint name="joint_1">...    (the URDF's joint is joint1)

    Use instead:
    <ros2_control name="arm" type="system">
      <joint name="joint1">...
    """

    code, name, severity, target = "U505", "ros2-control-unknown-joint", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for block in ctx.root:
            if local_tag(block) != "ros2_control":
                continue
            for el in block:
                if local_tag(el) != "joint":
                    continue
                name = el.get("name")
                if name is None or name in ctx.joint_names:
                    continue
                yield ctx.finding(
                    self,
                    el,
                    f"ros2_control '{block.get('name')}': joint '{name}' is not in the URDF{did_you_mean(name, ctx.joint_names)}",
                    attr="name",
                    hint="name a joint of the URDF (a configuration port belongs in <gpio>)",
                )
