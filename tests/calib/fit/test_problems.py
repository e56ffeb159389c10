"""Each measurement kind's residuals: zero at the truth, and a Jacobian equal to plain central differences."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.calib.choices import Setup
from armtool.calib.fit.problems import Problem
from armtool.calib.inputs.conventions import PoseFrame
from armtool.model.chain import Chain
from tests.calib.synthetic import make_measured, make_problem

KINDS = [
    ("pose", Setup.EYE_IN_HAND, PoseFrame.SENSOR_IN_TARGET),
    ("pose", Setup.EYE_TO_HAND, PoseFrame.TARGET_IN_SENSOR),
    ("point", Setup.EYE_TO_HAND, PoseFrame.SENSOR_IN_TARGET),
    ("point", Setup.EYE_IN_HAND, PoseFrame.SENSOR_IN_TARGET),
]


@pytest.mark.parametrize(("kind", "setup", "frame"), KINDS)
def test_measured_residuals_vanish_at_the_truth(clean_chain: Chain, kind: str, setup: Setup, frame: PoseFrame) -> None:
    m = make_measured(clean_chain, kind, n=12, setup=setup, frame=frame, noise_mm=0.0, noise_deg=0.0)
    problem = m.measurements.problem(m.model.with_frames(m.L, m.R), m.samples)
    assert np.abs(problem.raw(m.truth.x)).max() < 1e-12
    assert np.abs(problem.raw(np.zeros(m.model.size))).max() > 1e-4  # the injected errors show


@pytest.mark.parametrize(("kind", "setup", "frame"), KINDS)
def test_jacobian_equals_central_differences(clean_chain: Chain, kind: str, setup: Setup, frame: PoseFrame) -> None:
    m = make_measured(clean_chain, kind, n=9, setup=setup, frame=frame)
    problem = m.measurements.problem(m.model.with_frames(m.L, m.R), m.samples)
    problem = problem.with_sigma(np.array([1e-3, 2e-3])[: len(problem.blocks)])  # weights matter
    x = np.random.default_rng(1).normal(size=m.model.size) * 1e-3
    free = [i for i in range(m.model.size) if i in problem.frame_parameters() or i >= 12]
    _assert_central_differences(problem, x, free, 1e-6)


def _assert_central_differences(problem: Problem, x: np.ndarray, free: list[int], tolerance: float) -> None:
    J = problem.jacobian(x, free)
    for col, i in enumerate(free):
        plus, minus = x.copy(), x.copy()
        plus[i] += 1e-6
        minus[i] -= 1e-6
        numeric = (problem.residuals(plus) - problem.residuals(minus)) / 2e-6
        assert np.allclose(J[:, col], numeric, atol=tolerance * max(1.0, float(np.abs(numeric).max()))), i


def test_corner_jacobian_equals_central_differences(clean_chain: Chain) -> None:
    p = make_problem(clean_chain, n=8)
    problem = p.measurements.problem(p.model, p.samples)
    problem = problem.with_model(problem.model.with_frames(*problem.start_frames({})))
    x = np.random.default_rng(2).normal(size=p.model.size) * 1e-3
    _assert_central_differences(problem, x, list(range(p.model.size)), 1e-4)


def test_a_point_does_not_make_its_own_rotation_a_parameter(clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "point", n=10)
    problem = m.measurements.problem(m.model, m.samples)
    names = [m.model.params[i].name for i in problem.frame_parameters()]
    assert names == [f"tracker_in_flange.{c}" for c in ("tx", "ty", "tz", "rx", "ry", "rz")] + [
        f"point_in_base.{c}" for c in ("tx", "ty", "tz")
    ]


def test_a_sample_bad_in_position_alone_stands_out_in_its_block(clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "pose", n=10, noise_mm=0.1, noise_deg=0.02)
    problem = m.measurements.problem(m.model.with_frames(m.L, m.R), m.samples).with_sigma(
        np.array([1e-4, np.radians(0.02)])
    )
    problem.measured[3, :3, 3] += 0.002  # 2 mm, rotation untouched
    problem = problem.with_model(problem.model)  # re-derive what the file states
    z = problem.block_rms(m.truth.x)
    assert z[3, 0] > 5 and z[3, 1] < 3
