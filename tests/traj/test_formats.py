"""Every format reads what it writes; ROS 1/2 and MoveIt text as the tools print it; bad files say file:line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.traj.formats import TrajFormat, detect_format, format_trajectory, read_trajectory
from armtool.traj.trajectory import Trajectory

ROS2_ECHO = """header:
  stamp:
    sec: 0
    nanosec: 0
  frame_id: ''
joint_names:
- elbow
- shoulder
points:
- positions:
  - 0.5
  - 0.1
  velocities: []
  accelerations: []
  effort: []
  time_from_start:
    sec: 0
    nanosec: 0
- positions:
  - 0.6
  - 0.2
  velocities: []
  accelerations: []
  effort: []
  time_from_start:
    sec: 1
    nanosec: 500000000
---
"""

ROS1_ECHO = """header:
  seq: 0
  stamp:
    secs: 0
    nsecs:         0
  frame_id: ''
joint_names: [shoulder, elbow]
points:
  -
    positions: [0.1, 0.5]
    velocities: [0.0, 0.0]
    accelerations: []
    effort: []
    time_from_start:
      secs: 0
      nsecs:         0
  -
    positions: [0.2, 0.6]
    velocities: [0.0, 0.0]
    accelerations: []
    effort: []
    time_from_start:
      secs: 2
      nsecs: 250000000
---
"""


def sample(with_rates: bool = True) -> Trajectory:
    q = np.array([[0.0, 0.1], [0.25, -0.3], [0.5, 0.125]])
    return Trajectory(
        ("shoulder", "slide"),
        q,
        np.array([0.0, 0.5, 1.25]),
        q * 2 if with_rates else None,
        q * 3 if with_rates else None,
        prismatic=(False, True),
    )


@pytest.mark.parametrize("fmt", list(TrajFormat))
@pytest.mark.parametrize("rates", [True, False])
def test_every_format_reads_what_it_writes(tmp_path: Path, fmt: TrajFormat, rates: bool) -> None:
    traj = sample(rates)
    text = format_trajectory(traj, fmt)
    assert detect_format(text) is fmt or (fmt is TrajFormat.MOVEIT and detect_format(text) is TrajFormat.MOVEIT)
    path = tmp_path / "t.txt"
    path.write_text(text)
    back = read_trajectory(path).trajectory
    assert back.joint_names == traj.joint_names
    np.testing.assert_allclose(back.positions, traj.positions)
    assert back.times is not None
    np.testing.assert_allclose(back.times, traj.times, atol=1e-9)
    if rates:
        np.testing.assert_allclose(back.velocities, traj.velocities)
        np.testing.assert_allclose(back.accelerations, traj.accelerations)
    else:
        assert back.velocities is None and back.accelerations is None
    assert back.lines and all(n > 0 for n in back.lines)


def test_csv_names_units_like_servo_lut_apply() -> None:
    header = format_trajectory(sample(), TrajFormat.CSV).splitlines()[0]
    assert header == "time_s,shoulder_rad,slide_m,shoulder_rad_s,slide_m_s,shoulder_rad_s2,slide_m_s2"


def test_ros2_echo_is_read_with_its_times_and_lines() -> None:
    traj = read_trajectory("echo.yaml", ROS2_ECHO).trajectory
    assert traj.joint_names == ("elbow", "shoulder")
    np.testing.assert_allclose(traj.times, [0.0, 1.5])
    assert traj.lines == (10, 19)


def test_ros1_echo_secs_nsecs_and_reorder_by_name() -> None:
    traj = read_trajectory("echo.yaml", ROS1_ECHO).trajectory
    assert detect_format(ROS1_ECHO) is TrajFormat.ROS1
    np.testing.assert_allclose(traj.times, [0.0, 2.25])
    other = read_trajectory("echo2.yaml", ROS2_ECHO).trajectory.reorder(traj.joint_names)
    np.testing.assert_allclose(other.positions, traj.positions)  # same motion, joints listed in another order


def test_moveit_robot_trajectory() -> None:
    text = (
        "joint_trajectory:\n"
        + "".join("  " + ln + "\n" for ln in ROS2_ECHO.replace("---\n", "").splitlines())
        + "multi_dof_joint_trajectory:\n  joint_names: []\n  points: []\n"
    )
    assert detect_format(text) is TrajFormat.MOVEIT
    traj = read_trajectory("plan.yaml", text).trajectory
    np.testing.assert_allclose(traj.positions, [[0.5, 0.1], [0.6, 0.2]])


def test_untimed_csv_is_a_path() -> None:
    traj = read_trajectory("p.csv", "j1_rad,j2_rad\n0,0\n1,1\n").trajectory
    assert traj.times is None and traj.n_points == 2


@pytest.mark.parametrize("fmt", [TrajFormat.ROS2, TrajFormat.ROS1, TrajFormat.MOVEIT])
def test_an_untimed_path_is_not_written_as_a_ros_or_moveit_trajectory(fmt: TrajFormat) -> None:
    # Every time_from_start would be 0: ros2_controllers' joint_trajectory_controller rejects the
    # goal ("Time between points 0 and 1 is not strictly increasing").
    path = read_trajectory("p.csv", "j1_rad,j2_rad\n0,0\n1,1\n").trajectory
    with pytest.raises(ArmtoolError) as err:
        format_trajectory(path, fmt)
    assert "untimed path cannot be written" in err.value.what and "armtool traj time" in (err.value.hint or "")
    assert format_trajectory(path, TrajFormat.CSV).startswith("j1_rad,j2_rad")  # as a path, it can
    timed = read_trajectory("t.csv", "time_s,j1_rad,j2_rad\n0,0,0\n1,1,1\n").trajectory
    assert "nanosec: 0}" in format_trajectory(timed, TrajFormat.ROS2) or "nsecs: 0}" in format_trajectory(timed, fmt)


@pytest.mark.parametrize(
    "text, where, what",
    [
        ("time_s,j1_rad\n0,0\n1,nan\n", "p.csv:3", "nan"),
        ("time_s,j1_rad\n0,0\n1,abc\n", "p.csv:3", "not a number"),
        ("time_s,j1_rad\n0,0\n1\n", "p.csv:3", "fields"),
        ("time_s,j1_deg\n0,0\n", "p.csv:1", "not a time or joint column"),
        ("time_s\n0\n", "p.csv:1", "no joint position column"),
        ("joint_names: [a]\npoints:\n- positions: [1, 2]\n", "p.csv:3", "2 values for 1 joints"),
        ("joint_names: [a]\npoints:\n- positions: [.nan]\n", "p.csv:3", "nan"),
        ("joint_names: [a]\npoints: [\n", "p.csv:3", "not valid YAML"),
        ('{"joint_names": ["a"], "points": [{"positions": [NaN]}]}', "p.csv:1", "nan"),
        ('{"joint_names": ["a"],\n "points": [}', "p.csv:2", "not valid JSON"),
        ("header: {}\n", "p.csv", "not a trajectory"),
    ],
)
def test_malformed_files_say_what_and_where(text: str, where: str, what: str) -> None:
    with pytest.raises(ArmtoolError) as err:
        read_trajectory("p.csv", text)
    assert what in err.value.what.lower() or what in err.value.what
    assert err.value.where == where


def test_reorder_rejects_missing_joint() -> None:
    with pytest.raises(ArmtoolError, match="no joint"):
        sample().reorder(["shoulder", "elbow"])
