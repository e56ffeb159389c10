"""Closed-form paths (armtool.traj.branches): the nearest solution keeps a smooth path smooth, a jump
to another branch names the joints that flip and the joint at its limit, a passage through a wrist
singularity is listed with the joint that crosses it, and a locked Panda is solved in closed form
with its locked joint constant."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from armtool.cli import app
from armtool.errors import ArmtoolError
from armtool.ik.registry import make_solver
from armtool.model.chain import axis_angle_batch, load_chain
from armtool.traj import cartesian as cart
from armtool.traj.branches import nearest
from armtool.traj.plan import PathSpec, plan_cartesian
from tests.ik.robots import erd

OPTS = cart.CartesianOptions(eef_step_m=0.002, eef_step_rad=0.01)


def invoke(*args: str) -> tuple[int, str]:
    """Exit code and what the user reads (an ArmtoolError is exit 2 with its message, as `armtool` prints it)."""
    result = CliRunner().invoke(app, list(args))
    if isinstance(result.exception, ArmtoolError):
        return 2, str(result.exception)
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result.exit_code, result.stdout + result.stderr


def ur5() -> object:
    return load_chain(erd("ur_description/urdf/ur5_robot.urdf"))


def test_a_smooth_line_has_no_switch_and_small_steps() -> None:
    chain = ur5()
    q0 = np.array([0.3, -1.2, 1.5, -1.8, 0.8, 0.4])
    T0 = chain.fk(q0)  # type: ignore[attr-defined]
    T1 = T0.copy()
    T1[:3, 3] += [0.1, 0.05, -0.05]
    r = cart.compute_cartesian(chain, make_solver("analytic", chain), q0, [cart.line_segment(T0, T1)], OPTS)  # type: ignore[arg-type]
    assert r.closed_form and r.fraction == 1.0 and r.branch_switches == []
    assert np.abs(np.diff(r.q, axis=0)).max() < 0.02  # 2 mm steps: no joint moves more than 0.02 rad


def test_nearest_is_by_the_largest_joint_step() -> None:
    chain = ur5()
    prev = np.zeros(6)
    one_large = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.9])  # Euclidean 0.9, largest step 0.9
    all_small = np.full(6, 0.4)  # Euclidean 0.98, largest step 0.4
    np.testing.assert_array_equal(nearest(chain, (one_large, all_small), prev), all_small)  # type: ignore[arg-type]


def test_a_twist_past_wrist_3s_limit_jumps_to_another_branch_and_says_which_joints_flip() -> None:
    chain = ur5()
    qa = np.array([0.3, -1.2, 1.5, -1.8, 0.8, 5.0])
    T0 = chain.fk(qa)  # type: ignore[attr-defined]
    T1 = T0.copy()  # the tool turned 2 rad about its own z: wrist_3 would pass its limit 2π at 6.28
    T1[:3, :3] = T0[:3, :3] @ axis_angle_batch(np.array([0, 0, 1.0]), np.array([2.0]))[0]
    r = cart.compute_cartesian(chain, make_solver("analytic", chain), qa, [cart.line_segment(T0, T1)], OPTS)  # type: ignore[arg-type]
    assert r.reason == "jump" and r.fraction < 1
    first = r.branch_switches[0]
    assert first.jump and first.step == len(r.q) - 1 and first.param == pytest.approx(r.fraction, abs=0.02)
    flipped = {f.joint for f in first.flips}
    assert "wrist_2_joint" in flipped and abs(first.flips[0].to_value - first.flips[0].from_value) > 1.0
    assert "'wrist_3_joint' at 6.2" in first.note and "reaches its limit 6.2832" in first.note
    assert "jump to another branch: 'wrist_2_joint'" in r.detail and f"path parameter {first.param:.4f}" in r.detail


def test_a_passage_through_the_wrist_singularity_names_wrist_2_and_is_not_cut() -> None:
    chain = ur5()
    singular = np.array([0.3, -1.2, 1.5, -1.8, 0.0, 0.4])
    Ts = chain.fk(singular)  # type: ignore[attr-defined]
    T0, T1 = Ts.copy(), Ts.copy()
    T0[:3, 3] -= [0.05, 0, 0]
    T1[:3, 3] += [0.05, 0, 0]
    seed = singular + [0, 0, 0, 0, 0.05, 0]
    solver = make_solver("analytic", chain)
    q0 = nearest(chain, solver.solve(T0, seed).solutions, seed)  # type: ignore[arg-type]
    r = cart.compute_cartesian(chain, solver, q0, [cart.line_segment(T0, T1)], OPTS)  # type: ignore[arg-type]
    assert r.fraction == 1.0 and not r.relative_jumps and not r.absolute_jumps
    assert len(r.branch_switches) == 1
    passage = r.branch_switches[0]
    assert not passage.jump and passage.flips[0].joint == "wrist_2_joint"
    assert np.sign(passage.flips[0].from_value) != np.sign(passage.flips[0].to_value) or 0.0 in (
        passage.flips[0].from_value,
        passage.flips[0].to_value,
    )


def test_locked_panda_is_solved_in_closed_form_with_the_joint_constant() -> None:
    panda = erd("panda_description/urdf/panda.urdf")
    spec = PathSpec(line="0,0.1,-0.1", relative=True)
    done = plan_cartesian(
        panda, "panda_link0", "panda_hand", None, spec, cart.CartesianOptions(), "auto", locks={"panda_joint7": 0.785}
    )
    assert done.solver_how.startswith("analytic") and done.result.closed_form and done.result.fraction == 1.0
    traj = done.trajectory
    assert traj.joint_names[-1] == "panda_joint7" and len(traj.joint_names) == 7
    assert np.all(traj.positions[:, 6] == 0.785)
    whole = load_chain(panda, "panda_link0", "panda_hand")
    ends = whole.fk(traj.positions[-1])
    np.testing.assert_allclose(ends[:3, 3], whole.fk(traj.positions[0])[:3, 3] + [0, 0.1, -0.1], atol=1e-5)


def test_a_lock_that_leaves_no_closed_form_steps_with_lm_and_says_so() -> None:
    panda = erd("panda_description/urdf/panda.urdf")
    spec = PathSpec(line="0,0.05,0", relative=True)
    done = plan_cartesian(
        panda, "panda_link0", "panda_hand", None, spec, cart.CartesianOptions(), "auto", locks={"panda_joint1": 0.0}
    )
    assert done.solver_how.startswith("lm (iterative; no closed form") and not done.result.closed_form
    assert np.all(done.trajectory.positions[:, 0] == 0.0)


@pytest.mark.parametrize(
    ("lock", "what"),
    [
        ("panda_joint8=0", "did you mean"),
        ("panda_joint7=9", "outside its limits"),
        ("panda_joint7", "not JOINT=VALUE"),
        ("panda_joint7=x", "is not a number"),
        ("panda_joint7=0,panda_joint7=1", "twice"),
    ],
)
def test_bad_locks_exit_2_with_a_message(tmp_path: Path, lock: str, what: str) -> None:
    panda = erd("panda_description/urdf/panda.urdf")
    out = tmp_path / "p.csv"
    args = ["traj", "cartesian", str(panda), "--base", "panda_link0", "--tip", "panda_hand"]
    code, text = invoke(*args, "--line", "0,0.05,0", "--relative", "--lock", lock, "-o", str(out))
    assert code == 2 and what in text and not out.exists()


def test_cli_report_json_and_start_with_every_joint(tmp_path: Path) -> None:
    panda = erd("panda_description/urdf/panda.urdf")
    out, report = tmp_path / "p.csv", tmp_path / "r.json"
    args = ["traj", "cartesian", str(panda), "--base", "panda_link0", "--tip", "panda_hand", "--line", "0,0.05,0"]
    start = "0,-0.785,0,-2.356,0,1.571,0.785"
    code, text = invoke(
        *args, "--relative", "--lock", "panda_joint7=0.785", "--start", start, "-o", str(out), "--report", str(report)
    )
    assert code == 0, text
    doc = json.loads(report.read_text())
    assert doc["schema_version"] == 1 and doc["locked"] == {"panda_joint7": 0.785} and doc["closed_form"]
    assert doc["fraction"] == 1.0 and doc["branch_switches"] == [] and doc["stopped"] is None
    assert len(doc["chain"]["joints"]) == 7 and doc["start"]["positions"][6] == 0.785
    code, text = invoke(
        *args, "--relative", "--lock", "panda_joint7=0.3", "--start", start, "-o", str(tmp_path / "b.csv")
    )
    assert code == 2 and "--lock holds it at 0.3" in text


def test_a_jump_exits_2_and_its_report_names_the_joint(tmp_path: Path) -> None:
    """The CLI's text and JSON for the wrist_3 twist (a jump to another branch)."""
    urdf = erd("ur_description/urdf/ur5_robot.urdf")
    waypoints = tmp_path / "w.csv"
    chain = ur5()
    qa = np.array([0.3, -1.2, 1.5, -1.8, 0.8, 5.0])
    T0 = chain.fk(qa)  # type: ignore[attr-defined]
    rows = ["x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad"]
    for angle in (1.0, 2.0):
        R = T0[:3, :3] @ axis_angle_batch(np.array([0, 0, 1.0]), np.array([angle]))[0]
        pitch = math.atan2(-R[2, 0], math.hypot(R[0, 0], R[1, 0]))
        roll, yaw = math.atan2(R[2, 1], R[2, 2]), math.atan2(R[1, 0], R[0, 0])
        rows.append(",".join(repr(float(v)) for v in (*T0[:3, 3], roll, pitch, yaw)))
    waypoints.write_text("\n".join(rows) + "\n")
    report = tmp_path / "r.json"
    start = ",".join(repr(float(v)) for v in qa)
    args = ["traj", "cartesian", str(urdf), "--waypoints", str(waypoints), "--start", start]
    code, text = invoke(*args, "--eef-step-rad", "0.01", "-o", str(tmp_path / "o.csv"), "--report", str(report))
    assert code == 2 and "jump to another branch" in text and "wrist_3_joint" in text
    doc = json.loads(report.read_text())
    assert doc["stopped"]["reason"] == "jump" and doc["branch_switches"][0]["jump"]
    assert "wrist_2_joint" in {f["joint"] for f in doc["branch_switches"][0]["flips"]}
