from __future__ import annotations

import re
from collections.abc import Iterator

from lxml import etree

from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext

FINGER_NAME = re.compile(r"finger|gripper|jaw|claw", re.IGNORECASE)
# "gripper_yaw", "LeftGripperRoll", "GRIPPER_Z": a wrist axis that carries the gripper, not a finger.
WRIST_AXIS = re.compile(r"yaw|pitch|roll|wrist|rot|twist|(?:^|[_\-])[xyz](?:[_\-]?joint)?$", re.IGNORECASE)
ARM_NAME = re.compile(r"arm|manipulator", re.IGNORECASE)
# Groups meant to hold the gripper: the gripper itself, or an "arm_and_hand" planning group.
HAND_NAME = re.compile(r"hand|gripper|finger|eef|end_?effector|claw|jaw|tool", re.IGNORECASE)


class GripperJointInArmGroup(Rule):
    """
    What it does:
    Reports finger or gripper joints inside a group that is used for inverse kinematics.

    An IK group is a group that is some end effector's parent_group, that contains a
    <chain>, or whose name says arm or manipulator. A finger joint is a moving joint of an
    end effector's group below its parent_link, or a joint named finger/gripper/jaw/claw
    (wrist axes such as "gripper_yaw" excepted). End effector groups themselves, groups
    named for the hand, and groups that include an end effector's group as a subgroup
    (an "arm_and_hand" planning group) are left alone.

    Why is this bad?
    The IK solver treats the finger as one more arm axis: a 6-DOF arm becomes a redundant
    7-DOF "arm" whose solutions open and close the gripper to reach a pose, KDL/TRAC-IK
    chains end at a finger instead of the flange, and the fingers move during arm motions.

    Example:
    <group name="arm"><chain base_link="base_link" tip_link="left_finger"/></group>

    Use instead:
    <group name="arm"><chain base_link="base_link" tip_link="tool0"/></group>
    <group name="gripper"><joint name="left_finger_joint"/></group>
    <end_effector name="hand" group="gripper" parent_link="tool0" parent_group="arm"/>
    """

    code, name, severity, target = "S109", "gripper-joint-in-arm-group", Severity.WARNING, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        urdf = ctx.urdf
        if urdf is None:
            return
        effectors = ctx.elements("end_effector")
        ee_groups = {el.get("group") for el in effectors if el.get("group")}
        parent_groups = {el.get("parent_group"): el.get("name") for el in effectors if el.get("parent_group")}

        fingers: dict[str, str] = {}  # joint -> why it is a finger joint
        for el in effectors:
            ee_group, mount = el.get("group"), el.get("parent_link")
            if not ee_group or ee_group not in ctx.groups or not mount or mount not in urdf.link_names:
                continue
            for joint_name in ctx.group_joints(ee_group):
                joint = urdf.joint(joint_name)
                if joint is not None and joint.moves and joint.child and mount in urdf.ancestors(joint.child):
                    fingers.setdefault(joint_name, f"in end effector group '{ee_group}'")
        for joint in urdf.joints:
            if joint.name and joint.moves and FINGER_NAME.search(joint.name) and not WRIST_AXIS.search(joint.name):
                fingers.setdefault(joint.name, "named like a finger")

        for name, group in ctx.groups.items():
            if name in ee_groups or HAND_NAME.search(name) or self._includes(ctx, name, ee_groups):
                continue
            if name in parent_groups:
                why = f"parent_group of end_effector '{parent_groups[name]}'"
            elif any(local_tag(el) == "chain" for el in group):
                why = "it holds a chain"
            elif ARM_NAME.search(name):
                why = "its name says arm"
            else:
                continue
            seen: set[str] = set()
            for el in group:
                found = [j for j in self._joints_of(ctx, el) if j in fingers and j not in seen]
                if not found:
                    continue
                seen.update(found)
                listed = ", ".join(f"'{j}' ({fingers[j]})" for j in found)
                noun = "gripper joint" if len(found) == 1 else "gripper joints"
                yield ctx.finding(
                    self,
                    el,
                    f"group '{name}' is used for IK ({why}) but contains {noun} {listed}",
                    attr=_attr(el),
                    hint="end the arm at the flange or tool link and put the fingers in their own group, "
                    "attached with <end_effector parent_group=...>",
                )

    @staticmethod
    def _joints_of(ctx: SrdfContext, el: etree._Element) -> list[str]:
        """Joints one child element of a <group> brings into it."""
        assert ctx.urdf is not None
        tag, ref = local_tag(el), el.get("name")
        if tag == "joint" and ref:
            return [ref]
        if tag == "link" and ref:
            return [j.name for j in ctx.urdf.joints_by_child.get(ref, ()) if j.name]
        if tag == "chain":
            chain = ctx.chain_links(el.get("base_link", ""), el.get("tip_link", ""))
            return [j.name for link in (chain or [])[1:] for j in ctx.urdf.joints_by_child.get(link, ()) if j.name]
        if tag == "group" and ref:
            return ctx.group_joints(ref)
        return []

    @staticmethod
    def _includes(ctx: SrdfContext, name: str, targets: set[str | None], _seen: frozenset[str] = frozenset()) -> bool:
        """True if group `name` has one of `targets` among its subgroups, at any depth."""
        group = ctx.groups.get(name)
        if group is None or name in _seen:
            return False
        for el in group:
            if local_tag(el) == "group":
                ref = el.get("name")
                if ref in targets or (ref and GripperJointInArmGroup._includes(ctx, ref, targets, _seen | {name})):
                    return True
        return False


def _attr(el: etree._Element) -> str:
    return "tip_link" if local_tag(el) == "chain" else "name"
