from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext


class PassiveJointInGroup(Rule):
    """
    What it does:
    Reports a `<passive_joint>` written inside a `<group>`.

    Why is this bad?
    srdfdom reads `<passive_joint>` only at the top level of the SRDF (Model::loadPassiveJoints);
    inside a group it reads `<joint>`, `<link>`, `<chain>` and `<group>` children and ignores the
    rest. The joint is therefore not passive: MoveIt plans it as an active joint. That matters
    for a moving joint (a warning); for a mimic or fixed joint, which MoveIt never plans on its
    own, the line only does nothing (info; moveit_resources' Panda hand has one).

    Example:
    <group name="arm">
      <chain base_link="base_link" tip_link="tool0"/>
      <passive_joint name="caster_joint"/>
    </group>

    Use instead:
    <group name="arm">
      <chain base_link="base_link" tip_link="tool0"/>
    </group>
    <passive_joint name="caster_joint"/>
    """

    code, name, severity, target = "S112", "passive-joint-in-group", Severity.WARNING, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        for group in ctx.elements("group"):
            for el in group:
                if local_tag(el) != "passive_joint":
                    continue
                name = el.get("name", "")
                joint = ctx.urdf.joint(name) if ctx.urdf is not None else None
                inert = joint is not None and (joint.mimic_el is not None or joint.type == "fixed")
                found = ctx.finding(
                    self,
                    el,
                    f"group '{group.get('name')}': <passive_joint name=\"{name}\"> inside a group is ignored "
                    "(srdfdom reads passive joints at the top level only)"
                    + ("; harmless here: the joint is a mimic or fixed joint MoveIt does not plan" if inert else ""),
                    hint="move it out of the <group>, to the top level of the SRDF"
                    + (", or remove it" if inert else ""),
                )
                yield found.with_severity(Severity.INFO) if inert else found
