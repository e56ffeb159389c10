"""Which joints of a model something drives: a joint's effort limit matters only there.

A URDF says what drives a joint in its <transmission> elements (ROS 1's ros_control, Gazebo's
gazebo_ros_control), its <ros2_control> blocks, and Gazebo plugins that name joints
(`<gazebo><plugin>...<joint_name>` or `<joint>`: diff-drive wheels, mimic plugins). A joint none of
these name in a model that names some is passive: a caster's swivel, an idler wheel. A model that
declares no actuation at all (a URDF generated without its ros2_control) does not say; there a
continuous joint with effort="0" is taken for passive, since passive casters, wheels and rollers
are continuous joints, while an arm's driven joints have a range.
"""

from __future__ import annotations

from armtool.lint.context import JointView, UrdfContext
from armtool.lint.locate import local_tag


def driven_joints(ctx: UrdfContext) -> set[str] | None:
    """The joints the model's transmissions, ros2_control blocks and Gazebo plugins name; None
    when it has none of them."""
    names: set[str] = set()
    declared = False
    for trans in ctx.transmissions:
        declared = True
        names.update(j.get("name", "") for j in trans.findall("joint"))
    for block in ctx.root:
        tag = local_tag(block)
        if tag == "ros2_control":
            declared = True
            names.update(el.get("name", "") for el in block if local_tag(el) == "joint")
        elif tag == "gazebo":
            for plugin in block.iter("plugin"):
                for el in plugin.iter("joint_name", "joint", "left_joint", "right_joint"):
                    declared = True
                    names.update((el.text or "").split())
    return names - {""} if declared else None


def is_passive(ctx: UrdfContext, joint: JointView, driven: set[str] | None) -> bool:
    """Whether nothing drives this joint (`driven`: driven_joints(ctx))."""
    if driven is not None:
        return joint.name not in driven
    return joint.type == "continuous"
