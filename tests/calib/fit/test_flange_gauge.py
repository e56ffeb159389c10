"""Where the measurements cannot see the flange, it is put nearest the nominal arm's: the
flange's turn about one tracked point goes back to nominal, so does the whole arm's shift against
its base (the tracker's registration following), every prediction stays, and the frame the arm
carries (reflector, camera on the flange) is never moved."""

from __future__ import annotations

import math

import numpy as np

from armtool.calib.choices import Setup
from armtool.calib.fit.calibration import FitOptions, calibrate
from armtool.calib.fit.determined import Precision
from armtool.calib.fit.flange_gauge import flange_deviation, nearest_nominal_flange
from armtool.calib.model import se3
from armtool.model.chain import load_chain
from tests.calib.synthetic import make_measured
from tests.ik.robots import erd


def _ur5():  # type: ignore[no-untyped-def]
    return load_chain(erd("ur_description/urdf/ur5_robot.urdf"), "base_link", "tool0")


def _largest_angle(model, a, b, Q) -> float:  # type: ignore[no-untyped-def]
    """The largest angle (°) between the flanges of parameter vectors a and b over the poses Q."""
    Ra, Rb = model.flange(a, Q)[:, :3, :3], model.flange(b, Q)[:, :3, :3]
    return math.degrees(float(np.linalg.norm(se3.log3_batch(np.swapaxes(Ra, -1, -2) @ Rb), axis=-1).max()))


def test_a_turn_about_the_tracked_point_goes_back_to_nominal_and_the_points_stay() -> None:
    # A reflector 31 mm out along a UR5's wrist_3 axis, as on the real tracker data: turning the
    # flange about that axis (wrist_3's zero offset) moves the point by a micrometre per degree.
    m = make_measured(
        _ur5(), "point", n=200, setup=Setup.EYE_TO_HAND, noise_mm=0.03, seed=4, point=np.array([1e-4, 2e-4, 0.031])
    )
    result = calibrate(m.model, m.measurements, m.samples, FitOptions(folds=0))
    model = result.model
    problem = m.measurements.problem(model, m.samples).with_sigma(np.array([3e-5]))
    turned = result.x.copy()
    turned[model.layout.offset(5)] += math.radians(0.5)
    candidates = model.indices(FitOptions().families)
    x, gauge = nearest_nominal_flange(problem, turned, candidates, Precision())
    assert _largest_angle(model, turned, result.x, problem.Q) > 0.49  # the turn is there
    assert _largest_angle(model, x, result.x, problem.Q) < 0.02  # and undone: the fit's own flange again
    assert gauge.after.mean_deg < gauge.before.mean_deg
    assert gauge.chi2_change <= 1.0
    carried = model.layout.frames[6:]  # the reflector in the flange (eye-to-hand: the right frame)
    assert np.array_equal(x[carried], turned[carried])
    moved = problem.raw(x) - problem.raw(turned)
    assert np.abs(moved).max() < 3e-6  # 3 µm: the measurements as they were
    # the fit reports what it did, on its own result
    assert result.flange_gauge is not None
    assert result.flange_gauge.after.mean_deg <= result.flange_gauge.before.mean_deg
    assert abs(result.flange_gauge.after.mean_deg - flange_deviation(problem, result.x).mean_deg) < 1e-9


def test_the_whole_arm_shifted_against_its_base_goes_back_and_the_tracker_follows() -> None:
    # The tracker sees the arm, never its base_link: the shoulder 1 mm higher with the tracker's
    # registration 1 mm lower predicts every point alike. The flange nearest nominal undoes it.
    m = make_measured(
        _ur5(), "point", n=200, setup=Setup.EYE_TO_HAND, noise_mm=0.03, seed=5, point=np.array([1e-4, 2e-4, 0.031])
    )
    result = calibrate(m.model, m.measurements, m.samples, FitOptions(folds=0))
    model = result.model
    problem = m.measurements.problem(model, m.samples).with_sigma(np.array([3e-5]))
    shifted = result.x.copy()
    # shoulder_lift's origin moved along the base's z axis (its correction is in the joint's frame)
    up = model.chain.joints[1].origin[:3, :3].T @ np.array([0.0, 0.0, 1.0])
    shifted[model.layout.origin(1)[:3]] += 1e-3 * up
    shifted[model.layout.frames[2]] -= 1e-3  # the tracker's registration the other way
    assert np.abs(problem.raw(shifted) - problem.raw(result.x)).max() < 3e-6
    x, gauge = nearest_nominal_flange(problem, shifted, model.indices(FitOptions().families), Precision())
    assert gauge.before.mean_mm > 0.9
    distance = np.linalg.norm(
        model.flange(x, problem.Q)[:, :3, 3] - model.flange(result.x, problem.Q)[:, :3, 3], axis=1
    )
    assert distance.max() < 1e-4  # the fit's own flange again, to 0.1 mm
    assert abs(x[model.layout.frames[2]] - result.x[model.layout.frames[2]]) < 1e-4  # the tracker came back
    carried = model.layout.frames[6:]
    assert np.array_equal(x[carried], shifted[carried])
    assert np.abs(problem.raw(x) - problem.raw(shifted)).max() < 3e-6


def test_measured_poses_see_the_flange_and_the_camera_never_moves() -> None:
    # A camera on the flange measures 6-D poses: its turn with the flange is the mount's, which the
    # camera frame carries, so nothing the poses cannot see is left to choose.
    m = make_measured(_ur5(), "pose", n=60, setup=Setup.EYE_IN_HAND, seed=1)
    result = calibrate(m.model, m.measurements, m.samples, FitOptions(folds=0))
    model = result.model
    problem = m.measurements.problem(model, m.samples).with_sigma(np.array([5e-5, math.radians(0.01)]))
    x, gauge = nearest_nominal_flange(problem, result.x, model.indices(FitOptions().families), Precision())
    camera = model.layout.frames[:6]  # camera_in_flange (eye-in-hand: the left frame)
    assert np.array_equal(x[camera], result.x[camera])
    assert gauge.chi2_change <= 1.0
    assert np.abs(model.flange(x, problem.Q) - model.flange(result.x, problem.Q))[:, :3, 3].max() < 1e-4
