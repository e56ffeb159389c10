"""`armtool tree`: the kinematic tree as text, dot and Mermaid, without numpy."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from lxml import etree
from typer.testing import CliRunner

from armtool.cli import app
from armtool.errors import ArmtoolError
from armtool.model.tree import read_tree, render_dot, render_mermaid, render_text
from tests.ik.test_group import ARM

runner = CliRunner()


def test_text_tree_shows_structure_types_axes_limits() -> None:
    text = render_text(read_tree(etree.fromstring(ARM)))
    lines = text.splitlines()
    assert lines[0] == "robot name is: arm"
    assert "8 links, 7 joints (3 fixed, 1 prismatic, 3 revolute)" in lines[1]
    assert "root link: world has 1 child(ren)" in text
    assert "└── base  ← world_joint (fixed)" in text
    assert "l1  ← j1 (revolute, axis [0 0 1], limits [-3, 3], velocity 1 rad/s, effort 1 N·m)" in text
    assert (
        "├── tool_frame  ← tool_frame_joint (fixed)" in text
        and "└── finger  ← finger_joint (prismatic, axis [1 0 0], limits [0, 0.04], velocity 1 m/s, effort 1 N)" in text
    )
    # depth shows as indentation: l3 is three levels below base
    assert any(line.startswith("            └── l3") for line in lines)


def test_zero_and_missing_velocity_or_effort_are_marked() -> None:
    """tree never showed velocity limits, where velocity="0" (unplannable) would be seen at once."""
    arm = (
        ARM.replace('upper="3" effort="1" velocity="1"/></joint>', 'upper="3" effort="1" velocity="0"/></joint>', 1)
        .replace(
            '<limit lower="0" upper="0.04" effort="1" velocity="1"/>',
            '<limit lower="0" upper="0.04" effort="0.0" velocity="1"/>',
        )
        .replace(
            'upper="3" effort="1" velocity="1"/></joint>\n  <joint name="flange_joint"',
            'upper="3"/></joint>\n  <joint name="flange_joint"',
        )
    )
    text = render_text(read_tree(etree.fromstring(arm)))
    assert "j1 (revolute, axis [0 0 1], limits [-3, 3], velocity 0 rad/s (ZERO), effort 1 N·m)" in text
    assert "j2 (revolute, axis [0 1 0], limits [-3, 3], velocity 1 rad/s, effort 1 N·m)" in text
    assert "j3 (revolute, axis [0 1 0], limits [-3, 3], no velocity, no effort)" in text
    assert "finger_joint (prismatic, axis [1 0 0], limits [0, 0.04], velocity 1 m/s, effort 0.0 N (ZERO))" in text
    assert "velocity 0 rad/s (ZERO)" in render_mermaid(read_tree(etree.fromstring(arm)))


def test_two_roots_and_dangling_joints_are_reported() -> None:
    broken = ARM.replace('<link name="finger"/>', '<link name="finger"/><link name="stray"/>').replace(
        '<child link="l3"/>', '<child link="l3x"/>'
    )
    text = render_text(read_tree(etree.fromstring(broken)))
    assert "root links (world, l3, stray)" in text
    assert "joint j3 connects l2 → l3x, which is not a link of the robot" in text


def test_dot_and_mermaid() -> None:
    tree = read_tree(etree.fromstring(ARM))
    dot = render_dot(tree)
    assert dot.startswith('digraph "arm" {') and dot.rstrip().endswith("}")
    assert '"l1" -> "joint:j2" [label="xyz: 0 0 0.3\\nrpy: 0 0 0"];' in dot and '"joint:j2" -> "l2";' in dot
    mermaid = render_mermaid(tree)
    assert mermaid.splitlines()[0] == "graph TD"
    assert 'L2_l1 -->|"j2 (revolute, axis [0 1 0], limits [-3, 3], velocity 1 rad/s, effort 1 N·m)"| L3_l2' in mermaid


def test_cli_writes_a_file_and_takes_xacro(tmp_path: Path) -> None:
    xacro = tmp_path / "arm.urdf.xacro"
    xacro.write_text(
        ARM.replace(
            '<robot name="arm">',
            '<robot xmlns:xacro="http://wiki.ros.org/xacro" name="$(arg name)"><xacro:arg name="name" default="x"/>',
        )
    )
    result = runner.invoke(app, ["tree", str(xacro), "--xacro-arg", "name:=my_arm"])
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("robot name is: my_arm")
    out = tmp_path / "arm.dot"
    result = runner.invoke(app, ["tree", str(xacro), "--xacro-arg", "name:=x", "--format", "dot", "-o", str(out)])
    assert result.exit_code == 0 and out.read_text().startswith('digraph "x"')


def test_cli_takes_a_moveit_config_package() -> None:
    package = Path(__file__).resolve().parents[2] / "fixtures" / "robots" / "clean_arm_moveit_config"
    result = runner.invoke(app, ["tree", "--moveit-config", str(package)])
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("robot name is: clean_arm")  # the URDF its .setup_assistant names
    assert (
        "joint1 (revolute, axis [0 0 1], limits [-3.1416, 3.1416], velocity 2.0 rad/s, effort 150 N·m)" in result.stdout
    )
    result = runner.invoke(app, ["tree"])
    assert isinstance(result.exception, ArmtoolError) and "--moveit-config DIR" in (result.exception.hint or "")


def test_tree_module_does_not_import_numpy() -> None:
    code = "import sys, armtool.model.tree, armtool.cli.tree; print('numpy' in sys.modules)"
    assert (
        subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
        == "False"
    )


REALWORLD = Path(__file__).resolve().parents[2] / ".." / "shared" / "realworld"


def test_realworld_gen3_lite() -> None:
    urdf = REALWORLD / "ros2_kortex/kortex_description/robots/gen3_lite.urdf"
    if not urdf.is_file():
        pytest.skip("the realworld corpus is absent")
    result = runner.invoke(app, ["tree", str(urdf)])
    assert result.exit_code == 0, result.output
    assert (
        "mimics right_finger_bottom_joint" in result.stdout
        and "tool_frame  ← tool_frame_joint (fixed)" in result.stdout
    )
