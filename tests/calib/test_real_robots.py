"""Calibration on real arms from example-robot-data: the classical parameter count and the accuracy."""

from __future__ import annotations

import pytest

from armtool.calib.fit.calibration import FitOptions, calibrate
from armtool.calib.simulation.truth import score
from armtool.model.chain import load_chain
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
    result = calibrate(p.model, p.measurements, p.samples, FitOptions(folds=0))
    assert len(result.free) == count
    after = score(result.model, result.x, p.truth)
    assert after.position_rms_mm < 0.15 and after.rotation_rms_deg < 0.03


def test_every_bad_sample_is_named_on_rendered_images(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """UR5, 40 rendered images, six bad rows (5° reading errors, mislabeled images). With seed 0
    the earlier rule (max(2 px, 5 × median)) missed a wrist reading error here."""
    import numpy as np

    from armtool.calib.fit.measurements import CornerMeasurements
    from armtool.calib.inputs.dataset import load_dataset
    from armtool.calib.inputs.observations import observe
    from armtool.calib.model.calib_model import CalibModel
    from armtool.calib.model.camera import load_intrinsics
    from armtool.calib.simulation.simulate import SimulationSpec, simulate
    from armtool.calib.simulation.truth import load_truth
    from armtool.calib.targets.apriltag import tag_object_points

    path, base, flange, _ = CASES["ur5"]
    out = tmp_path / "ds"
    simulate(erd(path), out, base, flange, SimulationSpec(samples=40, validation=5, seed=0, bad_samples=6))
    ds = load_dataset(out)
    chain = load_chain(ds.urdf, ds.base_link, ds.flange_link)
    camera = load_intrinsics(ds.intrinsics)
    model = CalibModel(chain, ds.setup, np.eye(4), np.eye(4))
    result = calibrate(
        model,
        CornerMeasurements(camera, observe(ds, camera), tag_object_points(ds.size_m)),
        ds.samples,
        FitOptions(folds=0),
    )
    truth = load_truth(out, model)
    assert len(truth.bad_samples) == 6
    assert set(result.outliers) == set(truth.bad_samples)
