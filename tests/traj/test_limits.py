"""Limits: velocity from the URDF, acceleration from MoveIt's joint_limits.yaml or options, never from effort."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.traj.limits import load_limits

from .helpers import CLEAN_LIMITS, CLEAN_URDF

REALWORLD = Path(__file__).resolve().parents[2] / ".." / "shared" / "realworld"


def test_urdf_velocity_and_yaml_acceleration() -> None:
    lim = load_limits(CLEAN_URDF, CLEAN_LIMITS)
    i = lim.index("joint3")
    assert lim.velocity[i] == 2.5 and lim.acceleration[i] == 5.0
    assert lim.lower[i] == -2.6 and lim.upper[i] == 2.6
    assert "left_finger_joint" in lim.names and lim.prismatic[lim.index("left_finger_joint")]


def test_effort_is_never_an_acceleration() -> None:
    lim = load_limits(CLEAN_URDF)
    assert np.all(np.isnan(lim.acceleration))
    with pytest.raises(ArmtoolError) as err:
        lim.require_acceleration()
    assert "--acc-limit" in (err.value.hint or "") and "joint_limits.yaml" in (err.value.hint or "")


def test_options_override_and_name_unknown_joints() -> None:
    lim = load_limits(CLEAN_URDF, CLEAN_LIMITS, acc_limits=["1.5", "joint2=0.5"], vel_limits=["joint1=0.1"])
    assert lim.acceleration[lim.index("joint1")] == 1.5 and lim.acceleration[lim.index("joint2")] == 0.5
    assert lim.velocity[lim.index("joint1")] == 0.1
    with pytest.raises(ArmtoolError, match="no joint 'joint9'"):
        load_limits(CLEAN_URDF, acc_limits=["joint9=1"])
    with pytest.raises(ArmtoolError, match="positive"):
        load_limits(CLEAN_URDF, acc_limits=["-1"])


def test_not_moveit_format_is_an_error(tmp_path: Path) -> None:
    other = tmp_path / "joint_limits.yaml"
    other.write_text("joint1:\n  limit:\n    lower: -1\n    upper: 1\n    velocity: 2\n")  # franka_description's layout
    with pytest.raises(ArmtoolError, match="not MoveIt's joint_limits.yaml"):
        load_limits(CLEAN_URDF, other)


def test_scaling_factors_from_the_file_and_options(tmp_path: Path) -> None:
    f = tmp_path / "jl.yaml"
    f.write_text(
        CLEAN_LIMITS.read_text().replace("default_velocity_scaling_factor: 1.0", "default_velocity_scaling_factor: 0.1")
    )
    assert load_limits(CLEAN_URDF, f).velocity_scaling == 0.1
    assert load_limits(CLEAN_URDF, f, velocity_scaling=0.5).velocity_scaling == 0.5
    with pytest.raises(ArmtoolError, match="outside"):
        load_limits(CLEAN_URDF, f, acceleration_scaling=2.0)


def test_moveit_resources_panda_limits() -> None:
    jl = REALWORLD / "moveit_resources" / "panda_moveit_config" / "config" / "joint_limits.yaml"
    if not jl.is_file():
        pytest.skip("corpus not present")
    from tests.ik.robots import erd

    lim = load_limits(erd("panda_description/urdf/panda.urdf"), jl)
    i = lim.index("panda_joint1")
    assert lim.acceleration[i] == 3.75 and lim.jerk[i] == 300.0 and lim.velocity[i] == pytest.approx(2.175)


MOVEIT_PACKAGE = Path(__file__).resolve().parents[2] / "fixtures" / "robots" / "clean_arm_moveit_config"


def test_ros2_parameter_file_reads_as_the_flat_one(tmp_path: Path) -> None:
    """`/**: ros__parameters: robot_description_planning: joint_limits:` (was "no `joint_limits:`
    mapping"), keys with `$(var tf_prefix)`: matched by the rest of the name, or substituted."""
    ros2 = MOVEIT_PACKAGE / "config" / "joint_limits.yaml"
    lim = load_limits(CLEAN_URDF, ros2)
    i = lim.index("joint3")
    assert (lim.velocity[i], lim.acceleration[i]) == (2.5, 5.0)
    assert (lim.velocity_scaling, lim.acceleration_scaling) == (0.5, 0.25)
    assert "matched by the rest of the name" in lim.sources[i]
    prefixed = load_limits(CLEAN_URDF, ros2, xacro_args={"tf_prefix": "left_"})  # no left_joint3 in this URDF
    assert np.isnan(prefixed.acceleration[prefixed.index("joint3")])


def test_moveit_applies_limits_by_their_flags(tmp_path: Path) -> None:
    """As RobotModelLoader: max_velocity without has_velocity_limits is not read; has_velocity_limits:
    false drops the URDF's velocity; min/max_position apply without a flag."""
    f = tmp_path / "joint_limits.yaml"
    f.write_text(
        "joint_limits:\n"
        "  joint1: {max_velocity: 0.1, max_position: 1.0}\n"
        "  joint2: {has_velocity_limits: false}\n"
        "  joint3: {has_acceleration_limits: true, max_acceleration: '5'}\n"
    )
    with pytest.raises(ArmtoolError, match="max_acceleration` of joint 'joint3' is '5', not a number") as err:
        load_limits(CLEAN_URDF, f)
    assert err.value.where == f"{f}:4"
    f.write_text(f.read_text().replace("'5'", "5"))
    lim = load_limits(CLEAN_URDF, f)
    assert lim.velocity[lim.index("joint1")] == 2.0 and lim.upper[lim.index("joint1")] == 1.0
    assert np.isnan(lim.velocity[lim.index("joint2")])
    assert lim.acceleration[lim.index("joint3")] == 5.0
