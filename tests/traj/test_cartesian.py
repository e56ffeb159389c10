"""Cartesian paths: the lecture's circle is followed completely and within 1 mm / 0.01 rad at every point
and joint midpoint; bad input is refused; a UR5 line through a wrist singularity jumps with lm (caught
by both rules) and not with the analytic solver's nearest solution."""

from __future__ import annotations

import math

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.ik.registry import make_solver
from armtool.ik.solver import rotation_error
from armtool.model.chain import load_chain
from armtool.traj import cartesian as cart

from .helpers import CLEAN_URDF, START


def clean() -> tuple[object, np.ndarray]:
    chain = load_chain(CLEAN_URDF, "base_link", "tool0")
    return chain, np.array([float(v) for v in START.split(",")])


def test_circle_is_complete_and_precise() -> None:
    chain, q0 = clean()
    T0 = chain.fk(q0)  # type: ignore[attr-defined]
    center = T0[:3, 3] + np.array([0, -0.1, 0])
    seg = cart.circle_segment(T0, center, np.array([1.0, 0, 0]), 2 * math.pi)
    r = cart.compute_cartesian(chain, make_solver("lm", chain), q0, [seg], cart.CartesianOptions(eef_step_m=0.01))  # type: ignore[arg-type]
    assert r.fraction == 1.0 and r.reason == "" and not r.relative_jumps and not r.absolute_jumps
    assert len(r.q) >= 63
    # independent check: every point and every joint midpoint within 1 mm / 0.01 rad of the circle
    for k in range(len(r.q) - 1):
        for q, lam in ((r.q[k], r.params[k]), ((r.q[k] + r.q[k + 1]) / 2, (r.params[k] + r.params[k + 1]) / 2)):
            T = chain.fk(q)  # type: ignore[attr-defined]
            ideal = seg.pose_at(float(lam))
            assert np.linalg.norm(T[:3, 3] - ideal[:3, 3]) <= 1e-3 + 1e-9
            assert np.linalg.norm(rotation_error(T[:3, :3], ideal[:3, :3])) <= 0.01
            assert abs(np.linalg.norm(T[:3, 3] - center) - 0.1) <= 1e-3 + 1e-9


def test_precision_check_inserts_points_on_coarse_steps() -> None:
    chain, q0 = clean()
    T0 = chain.fk(q0)  # type: ignore[attr-defined]
    seg = cart.circle_segment(T0, T0[:3, 3] + np.array([0, -0.1, 0]), np.array([1.0, 0, 0]), math.pi)
    r = cart.compute_cartesian(
        chain,
        make_solver("lm", chain),
        q0,
        [seg],  # type: ignore[arg-type]
        cart.CartesianOptions(eef_step_m=0.1, jump_factor=None),
    )
    assert r.fraction == 1.0 and r.inserted > 0 and r.max_deviation_m <= 1e-3
    assert len(r.midpoint_deviation_m) == len(r.q) - 1 and r.midpoint_deviation_m.max() == r.max_deviation_m


def test_zero_radius_and_collinear_arc_are_refused() -> None:
    chain, q0 = clean()
    T0 = chain.fk(q0)  # type: ignore[attr-defined]
    with pytest.raises(ArmtoolError, match="radius"):
        cart.circle_segment(T0, T0[:3, 3], np.array([1.0, 0, 0]), 1.0)
    p = T0[:3, 3]
    with pytest.raises(ArmtoolError, match="one line"):
        cart.arc_through(T0, p + [0.1, 0, 0], p + [0.2, 0, 0])


def test_arc_through_three_points_ends_at_the_end_point() -> None:
    chain, q0 = clean()
    T0 = chain.fk(q0)  # type: ignore[attr-defined]
    p = T0[:3, 3]
    seg = cart.arc_through(T0, p + [0, -0.05, 0.05], p + [0, -0.1, 0])
    np.testing.assert_allclose(seg.pose_at(1.0)[:3, 3], p + [0, -0.1, 0], atol=1e-9)
    np.testing.assert_allclose(seg.length_m, math.pi * 0.05, rtol=1e-9)


def _line(chain: object, q0: np.ndarray, offset: list[float], step: float = 0.01) -> cart.CartesianResult:
    T0 = chain.fk(q0)  # type: ignore[attr-defined]
    T1 = T0.copy()
    T1[:3, 3] += offset
    return cart.compute_cartesian(
        chain,  # type: ignore[arg-type]
        make_solver("lm", chain, timeout=0.005),  # type: ignore[arg-type]
        q0,
        [cart.line_segment(T0, T1)],
        cart.CartesianOptions(eef_step_m=step),
    )


def test_a_line_out_of_the_workspace_stops_as_unreachable() -> None:
    chain, q0 = clean()
    r = _line(chain, q0, [3.0, 0, 0], step=0.05)  # far outside the arm's reach
    assert 0 < r.fraction < 1 and r.reason == "unreachable"
    assert "out of the arm's workspace" in r.detail and "even with the joint limits ignored" in r.detail


def test_a_line_that_needs_a_joint_past_its_limit_names_the_joint() -> None:
    chain, q0 = clean()
    r = _line(chain, q0, [0, 0, -0.8])  # down: joint3 (±2.6 rad) folds until its limit
    assert 0 < r.fraction < 1 and r.reason == "joint limit"
    assert r.detail.startswith("joint 'joint3' would have to pass its limit 2.6 rad")


def test_a_path_started_at_a_singularity_says_so() -> None:
    from tests.ik.robots import erd

    chain = load_chain(erd("ur_description/urdf/ur5_robot.urdf"))
    r = _line(chain, np.array([0.0, -math.pi / 2, 0.0, -math.pi / 2, 0.0, 0.0]), [0.1, 0, 0])  # UR5 upright
    assert r.fraction == 0.0 and r.reason == "singularity" and "σ_min of the Jacobian" in r.detail


def test_ur5_wrist_flip_is_caught_by_both_rules_and_avoided_by_analytic() -> None:
    from tests.ik.robots import erd

    chain = load_chain(erd("ur_description/urdf/ur5_robot.urdf"))
    qa = np.array([0.3, -1.2, 1.5, -1.8, 0.15, 0.4])
    qb = qa.copy()
    qb[4] = -0.15  # wrist_2 through zero: the line passes by the wrist singularity
    seg = cart.line_segment(chain.fk(qa), chain.fk(qb))
    opts = cart.CartesianOptions(eef_step_m=0.002, eef_step_rad=0.01)
    lm = cart.compute_cartesian(chain, make_solver("lm", chain), qa, [seg], opts)
    assert lm.reason == "jump" and lm.relative_jumps and lm.absolute_jumps
    assert lm.relative_jumps[0] == lm.absolute_jumps[0] and lm.fraction < 1
    # the worst deviation is the achieved steps' (it was the cut-off flip's: 1581 mm / π rad)
    assert lm.max_deviation_m == lm.midpoint_deviation_m.max() <= opts.precision_m
    assert lm.max_deviation_rad == lm.midpoint_deviation_rad.max() <= opts.precision_rad
    assert len(lm.midpoint_deviation_m) == len(lm.q) - 1
    analytic = cart.compute_cartesian(chain, make_solver("analytic", chain), qa, [seg], opts)
    assert analytic.fraction == 1.0 and not analytic.relative_jumps and not analytic.absolute_jumps


def test_lecture_circle_about_the_start_reaches_it_by_a_line() -> None:
    chain, q0 = clean()
    T0 = chain.fk(q0)  # type: ignore[attr-defined]
    segs = cart.circle_about(T0, T0[:3, 3], 0.1, np.array([1.0, 0, 0]), 2 * math.pi)
    assert len(segs) == 2
    np.testing.assert_allclose(segs[0].pose_at(1.0)[:3, 3], T0[:3, 3] + [0, 0.1, 0], atol=1e-12)  # y + r cos 0
    np.testing.assert_allclose(segs[1].pose_at(0.25)[:3, 3], T0[:3, 3] + [0, 0, 0.1], atol=1e-12)  # z + r sin(π/2)
    with pytest.raises(ArmtoolError, match="radius"):
        cart.circle_about(T0, T0[:3, 3], 0.0, np.array([1.0, 0, 0]), 1.0)
