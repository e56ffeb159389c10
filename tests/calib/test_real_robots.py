"""Calibration on real arms from example-robot-data: the classical parameter count and the accuracy."""

from __future__ import annotations

import pytest

from armtool.calib.fit import calibrate
from armtool.calib.truth import score
from armtool.ik.chain import load_chain
from tests.calib.synthetic import make_problem
from tests.ik.robots import erd

CASES = {  # robot: (file, base, flange, identifiable = 4 per revolute joint + 6)
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "base_link", "tool0", 30),
    "panda": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_link8", 34),
}


@pytest.mark.parametrize("robot", sorted(CASES))
def test_real_arm_calibrates_to_the_truth(robot: str) -> None:
    path, base, flange, count = CASES[robot]
    chain = load_chain(erd(path), base, flange)
    p = make_problem(chain, n=40, seed=11)
    result = calibrate(p.model, p.camera, p.samples, p.observations, p.size_m)
    assert len(result.free) == count
    after = score(result.model, result.x, p.truth)
    assert after.position_rms_mm < 0.15 and after.rotation_rms_deg < 0.03
