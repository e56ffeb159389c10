"""Which joints of a model nothing drives: a joint's effort limit matters only where something does.

A URDF says what drives a joint in its <transmission> elements (ROS 1's ros_control, Gazebo's
gazebo_ros_control), its <ros2_control> blocks, and Gazebo plugins that name joints
(`<gazebo><plugin>...<joint_name>` or `<joint>`: diff-drive wheels, mimic plugins). A continuous
joint none of these names is passive: a caster's swivel and wheel, an idler wheel, a roller
(trossen's mobile_ai.urdf writes effort="0" on them, literally true). A revolute or prismatic
joint is not taken for passive: an arm's or gripper's joint, whose effort="0" is a slip even where
the model declares no actuation for it.
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


def is_passive(joint: JointView, driven: set[str] | None) -> bool:
    """Whether this joint is passive: continuous, and not among `driven` (driven_joints(ctx))."""
    return joint.type == "continuous" and (driven is None or joint.name not in driven)
