from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext

SHOWN = 8


class GroupStateMissingJoint(Rule):
    """
    What it does:
    Reports a <group_state> that gives no value for some joints of its group. Fixed joints,
    mimic joints and <passive_joint>s need no value and are not asked for.

    Why is this bad?
    The named pose is not a full configuration of the group: "go to home" leaves the missing
    joints wherever they happen to be, so the same pose gives different robot shapes, and
    a pose used as the start state in a test or a launch file is not reproducible.

    Example:
    <group name="arm"><chain base_link="base_link" tip_link="tool0"/></group>
    <group_state name="home" group="arm">
      <joint name="shoulder" value="0"/><joint name="elbow" value="1.2"/>
    </group_state>   (the chain also has wrist_1)

    Use instead:
    <group_state name="home" group="arm">
      <joint name="shoulder" value="0"/><joint name="elbow" value="1.2"/><joint name="wrist_1" value="0"/>
    </group_state>
    """

    code, name, severity, target = "S107", "group-state-missing-joint", Severity.WARNING, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        urdf = ctx.urdf
        if urdf is None:
            return
        passive = {el.get("name") for el in ctx.elements("passive_joint")}
        for state in ctx.elements("group_state"):
            group = state.get("group")
            if group is None or group not in ctx.groups:
                continue
            given = {el.get("name") for el in state if local_tag(el) == "joint"}
            missing = []
            for name in ctx.group_joints(group):
                joint = urdf.joint(name)
                if joint is None or not joint.moves or joint.el.find("mimic") is not None:
                    continue
                if name in passive or name in given:
                    continue
                missing.append(name)
            if not missing:
                continue
            shown = ", ".join(f"'{m}'" for m in missing[:SHOWN]) + (
                f" and {len(missing) - SHOWN} more" if len(missing) > SHOWN else ""
            )
            noun = "joint" if len(missing) == 1 else f"{len(missing)} joints"
            yield ctx.finding(
                self,
                state,
                f"group_state '{state.get('name')}' gives no value for {noun} of group '{group}': {shown}",
                attr="name",
                hint=f'add <joint name="..." value="..."/> for each, e.g. <joint name="{missing[0]}" value="..."/>',
            )
