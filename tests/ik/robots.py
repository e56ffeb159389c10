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
