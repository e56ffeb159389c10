"""The fit recovers a known robot from exact corners, names bad samples, and refuses hopeless data."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from armtool.calib.choices import Setup
from armtool.calib.fit.calibration import FitOptions, calibrate
from armtool.calib.inputs.observations import Observation
from armtool.calib.model.params import Family
from armtool.calib.simulation.truth import score
from armtool.errors import ArmtoolError
from armtool.model.chain import Chain
from tests.calib.synthetic import make_problem

NO_CV = FitOptions(folds=0)  # the fit itself; choosing the parameter set is tested in test_crossval.py


@pytest.mark.parametrize("setup", list(Setup))
def test_recovers_the_true_robot(clean_chain: Chain, setup: Setup) -> None:
    p = make_problem(clean_chain, n=40, setup=setup)
    result = calibrate(p.model, p.measurements, p.samples, NO_CV)
    before = score(result.model, result.x_handeye, p.truth)
    after = score(result.model, result.x, p.truth)
    assert before.position_rms_mm > 2.0  # the injected errors matter
    assert after.position_rms_mm < 0.15 and after.position_max_mm < 0.4 and after.rotation_rms_deg < 0.03
    assert before.position_rms_mm / after.position_rms_mm > 25
    before_px, after_px = result.fit.rms["corner"]
    assert after_px < 0.15 < before_px
    assert not result.outliers


def test_classical_parameter_count(clean_chain: Chain) -> None:
    # 4 per revolute joint + 6 (Everett, Driels & Mooring), including the 12 frame parameters.
    p = make_problem(clean_chain, n=30)
    result = calibrate(p.model, p.measurements, p.samples, NO_CV)
    assert len(result.free) == 4 * clean_chain.n + 6
    reasons = list(result.identifiability.dropped.values())
    assert any("trades against the camera frame" in r for r in reasons)
    assert math.isfinite(result.identifiability.condition_number)


def test_bad_samples_are_named_and_do_not_hurt(clean_chain: Chain) -> None:
    p = make_problem(clean_chain, n=40, seed=3)
    samples = list(p.samples)
    q = samples[5].q.copy()
    q[2] += math.radians(5.0)
    samples[5] = replace(samples[5], q=q)
    obs = dict(p.observations)
    obs["9"] = Observation("9", p.observations["17"].corners_px)  # a mislabeled image
    result = calibrate(p.model, p.measured(obs), samples, NO_CV)
    assert set(result.outliers) == {"5", "9"}
    assert "row 7" in result.outliers["5"]
    after = score(result.model, result.x, p.truth)
    assert after.position_rms_mm < 0.15 and after.rotation_rms_deg < 0.03


def test_holdout_reports_unseen_samples(clean_chain: Chain) -> None:
    p = make_problem(clean_chain, n=40, seed=4)
    result = calibrate(p.model, p.measurements, p.samples, FitOptions(holdout=0.25, folds=0))
    roles = [r.role for r in result.residuals]
    assert roles.count("holdout") == 10
    before, after = result.holdout.rms["corner"]
    assert after < 0.2 < before


def test_rejected_detections_are_reported(clean_chain: Chain) -> None:
    p = make_problem(clean_chain, n=30, seed=5)
    obs = dict(p.observations)
    obs["3"] = Observation("3", None, "blurred")
    result = calibrate(p.model, p.measured(obs), p.samples, NO_CV)
    assert result.rejected == {"3": "blurred"}


def test_too_few_samples_is_a_clear_error(clean_chain: Chain) -> None:
    p = make_problem(clean_chain, n=6, seed=6)
    with pytest.raises(ArmtoolError, match="identifiable parameters"):
        calibrate(p.model, p.measurements, p.samples, NO_CV)


def test_a_joint_that_never_moves_is_reported(clean_chain: Chain) -> None:
    p = make_problem(clean_chain, n=30, seed=7, freeze_joint=3)
    options = FitOptions(families=(Family.ORIGINS, Family.OFFSETS, Family.GAINS), folds=0)
    result = calibrate(p.model, p.measurements, p.samples, options)
    names = [result.model.params[i].name for i in result.identifiability.dropped]
    assert "joint4.gain" in names  # a gain needs the joint to move
    assert any("joint 'joint4' moved only 0.0°" in w for w in result.warnings)


def test_params_restrict_the_fit(clean_chain: Chain) -> None:
    p = make_problem(clean_chain, n=30, seed=8)
    options = FitOptions(families=(Family.OFFSETS,), families_explicit=True, folds=0)
    result = calibrate(p.model, p.measurements, p.samples, options)
    assert {result.model.params[i].kind for i in result.free} == {"frame", "offset"}
    # Offsets alone cannot explain 6-D origin errors (research: 4.7 -> 4.3 mm on UR5).
    assert score(result.model, result.x, p.truth).position_rms_mm > 0.5


@pytest.mark.parametrize("joint", [0, 5])
def test_a_wrong_reading_on_any_joint_is_named(clean_chain: Chain, joint: int) -> None:
    # A wrist reading off by 5° moves the tag little in the image (~1 px once the robust fit has
    # half absorbed it): the outlier rule must still catch it, and flag nothing else.
    p = make_problem(clean_chain, n=40, seed=9)
    samples = list(p.samples)
    for k in (4, 21):
        q = samples[k].q.copy()
        q[joint] += math.radians(5.0)
        samples[k] = replace(samples[k], q=q)
    result = calibrate(p.model, p.measurements, samples, NO_CV)
    assert set(result.outliers) == {"4", "21"}


def test_the_options_requested_keep_the_default_families_unless_params_names_them() -> None:
    default = FitOptions.requested(None, holdout=0.2, seed=3, folds=4, select=False, nested=False)
    assert default == FitOptions(holdout=0.2, seed=3, folds=4, select=False, nested=False)
    assert default.families == (Family.ORIGINS, Family.OFFSETS) and not default.families_explicit
    named = FitOptions.requested("gains, origins,gains", holdout=0.0, seed=0, folds=5, select=True, nested=True)
    assert named.families == (Family.GAINS, Family.ORIGINS) and named.families_explicit
    with pytest.raises(ArmtoolError, match="unknown parameter family 'joints' in --params"):
        FitOptions.requested("joints", holdout=0.0, seed=0, folds=5, select=True, nested=True)
