"""Real robots from example-robot-data (skip when absent) and small synthetic URDFs."""

from __future__ import annotations

import glob
import sys
from pathlib import Path

import pytest


def erd(relative: str) -> Path:
    """A file of the example-robot-data package, or skip the test."""
    hits = glob.glob(f"{sys.prefix}/**/example-robot-data/robots/{relative}", recursive=True)
    if not hits:
        pytest.skip(f"example-robot-data not installed ({relative})")
    return Path(hits[0])


ARMS = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_hand"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", None, None),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", None, None),
    "kinova": ("kinova_description/robots/kinova.urdf", None, None),
}

PLANAR_2R = """<robot name="planar">
  <link name="base"/>
  <link name="l1"/>
  <link name="l2"/>
  <link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.5 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="l2"/><child link="tool"/><origin xyz="0.3 0 0" rpy="0 0 0"/></joint>
</robot>
"""


def _revolute(
    name: str, parent: str, child: str, xyz: str, rpy: str, axis: str = "0 0 1", kind: str = "revolute"
) -> str:
    limit = '<limit lower="-3" upper="3" effort="1" velocity="1"/>' if kind != "continuous" else ""
    return (
        f'  <joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>{limit}</joint>\n'
    )


# A 6R arm with no two axes parallel or meeting: no closed form (EAIK has no decomposition for it).
GENERAL_6R = (
    '<robot name="general6r">\n'
    + "".join(f'  <link name="l{i}"/>\n' for i in range(7))
    + '  <link name="tool"/>\n'
    + _revolute("j1", "l0", "l1", "0 0 0.1", "0 0 0")
    + _revolute("j2", "l1", "l2", "0.05 0.02 0.2", "1.2 0.3 0")
    + _revolute("j3", "l2", "l3", "0.3 0.04 0.03", "0.2 -0.4 0.1")
    + _revolute("j4", "l3", "l4", "0.06 0.25 0.02", "-0.9 0.1 0.3")
    + _revolute("j5", "l4", "l5", "0.03 0.07 0.12", "0.7 0.5 -0.2")
    + _revolute("j6", "l5", "l6", "0.05 -0.04 0.09", "-0.6 0.2 0.4")
    + '  <joint name="tool_joint" type="fixed"><parent link="l6"/><child link="tool"/><origin xyz="0 0 0.05" rpy="0.1 0.2 0.3"/></joint>\n'
    + "</robot>\n"
)

# Two coaxial continuous joints: the tip's pose depends on q1 + q2 only, so a target has a solution
# for every q1 (and q and q + 2π are one configuration): solution sets can be built by hand.
COAXIAL_2R = (
    '<robot name="coaxial">\n  <link name="base"/>\n  <link name="l1"/>\n  <link name="l2"/>\n  <link name="tool"/>\n'
    + _revolute("j1", "base", "l1", "0 0 0.1", "0 0 0", kind="continuous")
    + _revolute("j2", "l1", "l2", "0 0 0.2", "0 0 0", kind="continuous")
    + '  <joint name="tool_joint" type="fixed"><parent link="l2"/><child link="tool"/><origin xyz="0.3 0 0"/></joint>\n'
    + "</robot>\n"
)
