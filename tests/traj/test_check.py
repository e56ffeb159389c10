"""Each check code fires on the defect it names (with point, time, joint and the file's line), and not on a clean trajectory."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from armtool.traj.check import CODES, CheckOptions, check, hermite_extremes
from armtool.traj.formats import read_trajectory
from armtool.traj.limits import load_limits
from armtool.traj.timing import time_optimal
from armtool.traj.trajectory import Trajectory

from .helpers import CLEAN_URDF, JOINTS, clean_limits, random_path


def timed() -> Trajectory:
    return time_optimal(random_path(1), clean_limits())


def codes(traj: Trajectory, **opts: object) -> list[str]:
    return [f.code for f in check(traj, clean_limits(), CheckOptions(**opts))]  # type: ignore[arg-type]


def test_a_time_optimal_trajectory_passes() -> None:
    assert codes(timed()) == []


def test_T101_time_not_increasing() -> None:
    t = timed()
    times = t.times.copy()
    times[5] = times[4]
    findings = check(replace(t, times=times), clean_limits())
    assert [f.code for f in findings] == ["T101"]
    assert "point 5" in findings[0].message


def test_T201_position_outside_limits_names_point_and_joint() -> None:
    text = "time_s," + ",".join(f"{j}_rad" for j in JOINTS) + "\n0,0,0,0,0,0,0\n1,0,2.5,0,0,0,0\n2,0,0,0,0,0,0\n"
    traj = read_trajectory("t.csv", text).trajectory
    findings = [f for f in check(traj, load_limits(CLEAN_URDF, acc_limits=["100"]), CheckOptions()) if f.code == "T201"]
    assert len(findings) == 1
    f = findings[0]
    assert f.line == 3 and "point 1" in f.message and "t=1.0000 s" in f.message and "joint2" in f.message


def test_T301_T302_velocity_and_acceleration_over_limits() -> None:
    t = timed()
    fast = replace(t, times=t.times * 0.9, velocities=t.velocities / 0.9, accelerations=t.accelerations / 0.81)
    got = set(codes(fast))
    assert {"T301", "T302"} <= got
    messages = [f.message for f in check(fast, clean_limits())]
    assert any("file's velocity field" in m for m in messages) and any("between samples" in m for m in messages)


def test_T301_by_finite_differences_without_velocities() -> None:
    t = timed()
    assert codes(replace(t, velocities=None, accelerations=None)) == []
    fast = replace(t, times=t.times * 0.8, velocities=None, accelerations=None)
    assert "T301" in codes(fast) and "T302" in codes(fast)


def test_T303_jerk_only_with_a_jerk_limit() -> None:
    t = timed()
    assert codes(t) == []
    lim = load_limits(CLEAN_URDF, acc_limits=["10"], jerk_limits=["1"])
    assert "T303" in [f.code for f in check(t, lim)]


def test_T304_a_joint_with_velocity_zero_in_the_urdf_is_said_to_be_unchecked(tmp_path: Path) -> None:
    urdf = tmp_path / "arm.urdf"
    text = CLEAN_URDF.read_text()
    joint3 = text.index('name="joint3"')
    at = text.index('velocity="', joint3)
    urdf.write_text(text[:at] + 'velocity="0" old_' + text[at:])  # joint3's velocity="0" (unplannable)
    t = timed()
    fast = replace(t, times=t.times / 20, velocities=t.velocities * 20, accelerations=None)  # 20× too fast
    limits = load_limits(urdf, acc_limits=["1e6"])
    findings = [f for f in check(fast, limits) if f.code == "T304" or "joint3" in f.message]
    assert [f.code for f in findings] == ["T304"]  # joint3's speed cannot be judged: said, not passed
    assert findings[0].severity.value == "warning" and "velocity was not checked" in findings[0].message
    assert "joint 'joint3' (arm.urdf:" in findings[0].message and "--vel-limit joint3=VALUE" in (findings[0].hint or "")
    assert "T301" in [f.code for f in check(fast, limits)]  # the other joints' speed is still judged
    assert "T304" not in codes(t)  # every joint has a velocity limit in the clean arm
    assert "T304" not in [f.code for f in check(t.untimed(), limits)]  # an untimed path has no speed


def test_T401_velocities_that_do_not_belong_to_the_positions() -> None:
    t = timed()
    v = t.velocities.copy()
    v[10:12, 2] *= -1
    assert "T401" in codes(replace(t, velocities=v, accelerations=None))


def test_T501_jump_relative_and_absolute() -> None:
    q = np.linspace(0, 0.3, 30)[:, None] * np.ones((1, 6))
    q[15:, 3] += 1.5  # a branch switch of joint4 between points 14 and 15
    path = Trajectory(JOINTS, q, source="p.csv")
    findings = [f for f in check(path, clean_limits(), CheckOptions(max_step=0.5)) if f.code == "T501"]
    assert len(findings) == 1
    assert "point 15" in findings[0].message and "joint4" in findings[0].message
    assert "relative rule" in findings[0].message and "absolute rule" in findings[0].message
    smooth = Trajectory(JOINTS, np.linspace(0, 0.3, 30)[:, None] * np.ones((1, 6)))
    assert codes(smooth, max_step=0.5) == []


def test_T601_T602_unknown_and_duplicate_joints() -> None:
    q = np.zeros((3, 3))
    traj = Trajectory(("joint1", "joint1", "elbow"), q, np.array([0.0, 1, 2]))
    got = codes(traj)
    assert "T601" in got and "T602" in got


def test_T701_T702_not_at_rest() -> None:
    t = timed()
    v = t.velocities.copy()
    v[0, 0] = 0.5
    v[-1, 1] = -0.5
    got = codes(replace(t, velocities=v, accelerations=None))
    assert "T701" in got and "T702" in got


def test_every_code_is_tested_here() -> None:
    import inspect
    import sys

    source = inspect.getsource(sys.modules[__name__])
    assert all(f"test_{code}" in source or code in source.split("def test_every_code")[0] for code in CODES)


def test_hermite_extremes_is_exact_for_a_cubic() -> None:
    t = np.array([0.0, 2.0])
    # q = t³ - 3t²  →  v = 3t² - 6t (min -3 at t=1), a = 6t - 6, jerk 6
    q = np.array([[0.0], [8.0 - 12.0]])
    v = np.array([[0.0], [0.0]])
    vmax, amax, jmax = hermite_extremes(t, q, v)
    assert vmax[0, 0] == pytest.approx(3.0) and amax[0, 0] == pytest.approx(6.0) and jmax[0, 0] == pytest.approx(6.0)


def test_T401_accepts_a_bang_bang_switch_inside_a_segment() -> None:
    # One joint, +A then -A within one 1 s segment, at rest at both ends: mean velocity A/4, ends 0.
    A = 4.0
    traj = Trajectory(("joint1",), np.array([[0.0], [A / 4]]), np.array([0.0, 1.0]), np.zeros((2, 1)))
    lim = load_limits(CLEAN_URDF, acc_limits=[f"joint1={A}"])
    assert "T401" not in [f.code for f in check(traj, lim)]


def test_T303_sees_the_acceleration_step_at_a_knot() -> None:
    # Two parabolic segments of 0.5 s: +2 then -2 rad/s². Inside each the jerk is 0; at the knot
    # the acceleration steps by 4 rad/s² over a mean segment of 0.5 s: 8 rad/s³.
    t = np.array([0.0, 0.5, 1.0])
    q = np.array([[0.0], [0.25], [0.5]])
    v = np.array([[0.0], [1.0], [0.0]])
    traj = Trajectory(("joint1",), q, t, v)
    _, _, jerk = hermite_extremes(t, q, v)
    assert jerk[0, 0] == pytest.approx(0.0, abs=1e-9) and jerk[1, 0] == pytest.approx(8.0)
    assert "T303" in [f.code for f in check(traj, load_limits(CLEAN_URDF, acc_limits=["2"], jerk_limits=["7.9"]))]
    assert [f.code for f in check(traj, load_limits(CLEAN_URDF, acc_limits=["2"], jerk_limits=["8.1"]))] == []
