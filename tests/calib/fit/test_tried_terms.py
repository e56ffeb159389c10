"""The default choice tries the joint terms (compliance, harmonics) after the geometry and keeps
one only where held-out poses ask for it: a simulated UR5 tracked by a laser tracker, with and
without a joint that yields to gravity."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.calib.choices import Setup
from armtool.calib.fit.calibration import CalibrationResult, FitOptions, calibrate
from armtool.calib.fit.measurements import PointMeasurements
from armtool.calib.inputs.dataset import Sample
from armtool.calib.model import se3
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.params import Family
from armtool.calib.model.terms.compliance import Compliance
from armtool.calib.model.terms.registry import build_terms
from armtool.model.chain import load_chain
from armtool.model.load import urdf_text
from tests.ik.robots import erd

UR5 = erd("ur_description/urdf/ur5_robot.urdf")


def _fit(stiffness_knm: list[float], options: FitOptions, seed: int = 7) -> CalibrationResult:
    """A UR5 with origins and zero offsets slightly off and the given joint stiffnesses (0: rigid),
    150 poses of one point 30 mm out on the flange, 0.02 mm noise; fitted by `options` on a model
    that carries both joint terms, as `calibrate fit` builds it with the default --params."""
    chain = load_chain(UR5, "base_link", "tool0")
    terms = build_terms([Family.COMPLIANCE, Family.HARMONICS], chain, lambda: urdf_text(UR5))
    rng = np.random.default_rng(seed)
    L = se3.inv(se3.xyz_rpy([1.5, 0.4, 0.3], [0.0, 0.1, 2.0]))
    R = se3.make(t=np.array([0.0, 0.0, 0.03]))
    truth = CalibModel(chain, Setup.EYE_TO_HAND, L, R, sensor="tracker", target="point", terms=terms)
    x = np.zeros(truth.size)
    parts = truth.split(x)
    parts.origin[:, :3] = rng.normal(scale=2e-4, size=(chain.n, 3))
    parts.offset[:] = rng.normal(scale=2e-4, size=chain.n)
    compliance = terms[0]
    assert isinstance(compliance, Compliance)
    k = np.array(stiffness_knm) * 1e3
    parts.terms[0][:, 0] = np.divide(compliance.max_torque_nm, k, out=np.zeros(chain.n), where=k != 0)
    Q = chain.random(rng, 150)
    Q[:, 1] = rng.uniform(-2.8, -0.3, size=len(Q))  # the arm held up and out, as a tracker grid does
    points = truth.tag_in_camera(x, Q)[:, :3, 3] + rng.normal(scale=2e-5, size=(len(Q), 3))
    measurements = PointMeasurements({str(i): p for i, p in enumerate(points)}, "tracker", "point", "points.csv")
    samples = [Sample(str(i), i + 2, q, None) for i, q in enumerate(Q)]
    nominal = CalibModel(chain, Setup.EYE_TO_HAND, np.eye(4), np.eye(4), sensor="tracker", target="point", terms=terms)
    return calibrate(nominal, measurements, samples, options)


DEFAULT = FitOptions(folds=3, nested=False)  # the default --params: the joint terms are tried


def test_a_joint_that_yields_to_gravity_is_chosen_by_the_default_k_fold() -> None:
    result = _fit([0, 28, 23, 0, 0, 0], DEFAULT)
    assert [c.name for c in result.candidates][-2:] == [
        "origins + offsets + compliance",
        "origins + offsets + compliance + harmonics",
    ]
    assert result.joint_terms is not None and "compliance" in result.joint_terms.candidate.kinds
    assert result.candidate.name == "origins + offsets"  # what calibrated.urdf holds: the geometry fitted alone
    assert not any("negative" in w for w in result.warnings)


def test_a_rigid_arm_keeps_to_geometry() -> None:
    result = _fit([0, 0, 0, 0, 0, 0], DEFAULT)
    assert result.candidate.name == "origins + offsets" and result.joint_terms is None


def test_a_plain_or_explicit_fit_fits_only_what_was_asked() -> None:
    plain = _fit([0, 28, 23, 0, 0, 0], FitOptions(folds=0))
    assert plain.candidate.name == "origins + offsets"
    explicit = _fit([0, 28, 23, 0, 0, 0], FitOptions(folds=3, nested=False, families_explicit=True))
    assert [c.name for c in explicit.candidates][-1] == "origins + offsets"


@pytest.mark.parametrize("elbow", [-23.0])
def test_a_joint_yielding_against_gravity_is_called_unphysical(elbow: float) -> None:
    options = FitOptions(families=(Family.ORIGINS, Family.OFFSETS, Family.COMPLIANCE), folds=0)
    result = _fit([0, 28, elbow, 0, 0, 0], options)
    warned = [w for w in result.warnings if "negative" in w]
    assert len(warned) == 1 and warned[0].startswith("elbow_joint.") and "not a physical stiffness" in warned[0]
