"""armtool.moveit.package: a MoveIt config package's files, found as MoveItConfigsBuilder finds them."""

from __future__ import annotations

from pathlib import Path

import pytest

from armtool.errors import ArmtoolError
from armtool.model.packages import PackageResolver
from armtool.moveit.package import read_package

ROBOTS = Path(__file__).resolve().parents[2] / "fixtures" / "robots"
PACKAGE = ROBOTS / "clean_arm_moveit_config"


def test_the_setup_assistant_names_urdf_and_srdf() -> None:
    pkg = read_package(PACKAGE, PackageResolver())
    assert pkg.name == "clean_arm_moveit_config" and pkg.robot_name == "clean_arm"
    assert pkg.ros == 2
    assert pkg.urdf == ROBOTS / "clean_arm" / "urdf" / "clean_arm.urdf"
    assert pkg.urdf_why == "named by .setup_assistant"
    assert pkg.srdf == PACKAGE / "config" / "clean_arm.srdf"
    config = PACKAGE / "config"
    assert (pkg.kinematics, pkg.joint_limits, pkg.pilz_limits) == (
        config / "kinematics.yaml",
        config / "joint_limits.yaml",
        config / "pilz_cartesian_limits.yaml",
    )
    # Two *_controllers.yaml: MoveItConfigsBuilder takes moveit_controllers.yaml
    assert pkg.moveit_controllers == config / "moveit_controllers.yaml"
    assert pkg.robot_controllers == config / "ros2_controllers.yaml"


def test_config_robot_urdf_xacro_wins_as_in_moveit_configs_builder(tmp_path: Path) -> None:
    root = tmp_path / "arm_moveit_config"
    (root / "config").mkdir(parents=True)
    (root / "package.xml").write_text("<package><name>arm_moveit_config</name></package>")
    (root / ".setup_assistant").write_text(
        "moveit_setup_assistant_config:\n  URDF:\n    package: nowhere\n    relative_path: urdf/arm.urdf\n"
        "  SRDF:\n    relative_path: config/arm.srdf\n"
    )
    (root / "config" / "arm.urdf.xacro").write_text("<robot name='arm'/>")
    pkg = read_package(root, PackageResolver())
    assert pkg.urdf == root / "config" / "arm.urdf.xacro"


def test_the_launch_files_name_the_robot(tmp_path: Path) -> None:
    root = tmp_path / "pkg"
    (root / "config").mkdir(parents=True)
    (root / "launch").mkdir()
    (root / "package.xml").write_text("<package><name>whatever_config</name></package>")
    (root / "launch" / "demo.launch.py").write_text('MoveItConfigsBuilder("gen3", package_name="whatever_config")\n')
    (root / "config" / "gen3.urdf.xacro").write_text("<robot name='gen3'/>")
    for name in ("moveit", "ros2", "gripper_moveit"):
        (root / "config" / f"{name}_controllers.yaml").write_text("{}\n")
    pkg = read_package(root, PackageResolver())
    assert pkg.robot_name == "gen3"
    assert pkg.urdf == root / "config" / "gen3.urdf.xacro"
    assert pkg.moveit_controllers == root / "config" / "moveit_controllers.yaml"


def test_not_a_moveit_config_is_an_input_error(tmp_path: Path) -> None:
    with pytest.raises(ArmtoolError, match="not a MoveIt config package"):
        read_package(tmp_path, PackageResolver())
