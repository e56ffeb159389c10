"""Joint terms beyond geometry: compliance under gravity and harmonics of the joint angle move the
measurement as their parameters say, the gravity torques are the URDF's, and a fit recovers a
stiffness it was given."""

from __future__ import annotations

import math

import numpy as np
import pytest

from armtool.calib.choices import Setup
from armtool.calib.fit.calibration import FitOptions, calibrate
from armtool.calib.fit.measurements import PointMeasurements
from armtool.calib.inputs.dataset import Sample
from armtool.calib.model import se3
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.params import Family, ParamKind
from armtool.calib.model.terms.compliance import Compliance
from armtool.calib.model.terms.registry import TERMS, build_terms
from armtool.calib.outputs.report import calibration_document
from armtool.model.chain import Chain, load_chain
from armtool.model.load import urdf_text
from tests.calib.conftest import CLEAN_ARM
from tests.ik.robots import erd

BOTH = [Family.COMPLIANCE, Family.HARMONICS]


def test_every_term_family_is_registered_with_its_own_kind(clean_chain: Chain) -> None:
    terms = build_terms(BOTH, clean_chain, CLEAN_ARM.read_text)
    assert [t.family for t in terms] == BOTH == list(TERMS)
    assert [t.kind for t in terms] == [ParamKind.COMPLIANCE, ParamKind.HARMONIC]
    assert build_terms([Family.ORIGINS, Family.OFFSETS], clean_chain, CLEAN_ARM.read_text) == ()


def test_a_joint_term_is_a_turn_of_its_joint(clean_chain: Chain) -> None:
    # sin1 of joint 2 by 0.01 rad is joint 2 read 0.01·sin(q2) further.
    model = CalibModel(
        clean_chain, Setup.EYE_TO_HAND, np.eye(4), np.eye(4), terms=build_terms(BOTH, clean_chain, CLEAN_ARM.read_text)
    )
    x = np.zeros(model.size)
    x[model.layout.term(1, 2)[0]] = 0.01
    q = clean_chain.mid() + 0.4
    shifted = q.copy()
    shifted[2] += 0.01 * math.sin(q[2])
    assert np.allclose(model.flange(x, q[None])[0], clean_chain.fk(shifted), atol=1e-12)
    assert np.allclose(model.flange(model.urdf_part(x), q[None])[0], clean_chain.fk(q), atol=1e-12)


def test_gravity_torques_are_the_derivative_of_the_potential_energy() -> None:
    # An independent route to g(q): dV/dq of the URDF's masses, by central differences.
    import pinocchio as pin

    path = erd("ur_description/urdf/ur5_robot.urdf")
    chain = load_chain(path, "base_link", "tool0")
    text = urdf_text(path)
    compliance = Compliance(chain, text)
    model = pin.buildModelFromXML(text)
    data = model.createData()
    Q = chain.random(np.random.default_rng(1), 5)
    g = compliance.gravity(Q)
    for q, row in zip(Q, g):
        numeric = []
        for j in range(chain.n):
            energy = []
            for h in (1e-6, -1e-6):
                dq = q.copy()
                dq[j] += h
                energy.append(pin.computePotentialEnergy(model, data, dq))
            numeric.append((energy[0] - energy[1]) / 2e-6)
        assert np.allclose(row, numeric, atol=1e-5)
    assert compliance.max_torque_nm[0] < 1e-9  # the shoulder pan's axis is vertical: gravity never loads it
    assert compliance.max_torque_nm[1] > 50.0  # the shoulder lift carries the arm
    assert not compliance.regressors(Q)[:, 0].any()


def test_compliance_needs_the_inertials(tmp_path: object, clean_chain: Chain) -> None:
    from armtool.errors import ArmtoolError

    text = CLEAN_ARM.read_text()
    import re

    bare = re.sub(r"<inertial>.*?</inertial>", "", text, flags=re.DOTALL)
    with pytest.raises(ArmtoolError, match="needs the URDF's <inertial> masses"):
        Compliance(clean_chain, bare)


def _tracker(
    model: CalibModel, x: np.ndarray, Q: np.ndarray, noise_mm: float, rng: np.random.Generator
) -> PointMeasurements:
    points = model.tag_in_camera(x, Q)[:, :3, 3] + rng.normal(scale=noise_mm * 1e-3, size=(len(Q), 3))
    return PointMeasurements({str(k): p for k, p in enumerate(points)}, "tracker", "point", "points.csv")


def test_a_fit_recovers_the_stiffness_it_was_given_and_chooses_compliance() -> None:
    # A UR5 whose shoulder and elbow yield (28 and 23 kN·m/rad, a synthetic truth) and whose
    # origins are slightly off, seen by a tracker with 0.02 mm noise.
    path = erd("ur_description/urdf/ur5_robot.urdf")
    chain = load_chain(path, "base_link", "tool0")
    terms = build_terms([Family.COMPLIANCE], chain, lambda: urdf_text(path))
    rng = np.random.default_rng(7)
    L = se3.inv(se3.xyz_rpy([1.5, 0.4, 0.3], [0.0, 0.1, 2.0]))
    R = se3.make(t=np.array([0.0, 0.0, 0.03]))
    truth = CalibModel(chain, Setup.EYE_TO_HAND, L, R, sensor="tracker", target="point", terms=terms)
    x_true = np.zeros(truth.size)
    parts = truth.split(x_true)
    parts.origin[:, :3] = rng.normal(scale=2e-4, size=(chain.n, 3))
    parts.offset[:] = rng.normal(scale=2e-4, size=chain.n)
    compliance = terms[0]
    assert isinstance(compliance, Compliance)
    stiffness = np.array([0.0, 28e3, 23e3, 0.0, 0.0, 0.0])
    with np.errstate(divide="ignore"):
        parts.terms[0][:, 0] = np.where(
            stiffness > 0, compliance.max_torque_nm / np.where(stiffness > 0, stiffness, 1), 0
        )
    Q = chain.random(rng, 150)
    Q[:, 1] = rng.uniform(-2.8, -0.3, size=len(Q))  # the arm held up and out, as a tracker grid does
    measurements = _tracker(truth.with_frames(L, R), x_true, Q, 0.02, rng)
    samples = [Sample(str(k), k + 2, q, None) for k, q in enumerate(Q)]
    nominal = CalibModel(chain, Setup.EYE_TO_HAND, np.eye(4), np.eye(4), sensor="tracker", target="point", terms=terms)
    options = FitOptions(families=(Family.ORIGINS, Family.OFFSETS, Family.COMPLIANCE), folds=3, nested=False)
    result = calibrate(nominal, measurements, samples, options)
    # chosen with compliance, which a URDF cannot hold: calibrated.urdf is the geometry fitted alone
    assert result.joint_terms is not None and result.joint_terms.candidate.name == "origins + offsets + compliance"
    assert result.candidate.name == "origins + offsets"
    assert np.array_equal(nominal.urdf_part(result.x), result.x)
    joints = calibration_document(result, "ds", "ur5_robot.urdf")["joint_terms"]["joints"]
    for name, k in (("shoulder_lift_joint", 28.0), ("elbow_joint", 23.0)):
        fitted = joints[name]["stiffness_knm_per_rad"]
        assert fitted["value"] == pytest.approx(k, rel=0.1) and 0 < fitted["sigma"] < 0.1 * k
    assert "stiffness_knm_per_rad" not in joints["shoulder_pan_joint"]  # never loaded: not identified
    scores = {s.candidate.name: s for s in result.crossval.scores}  # type: ignore[union-attr]
    assert scores["origins + offsets + compliance"].rms["position"] < 0.5 * scores["origins + offsets"].rms["position"]


def test_harmonics_recover_a_once_per_turn_error(clean_chain: Chain) -> None:
    terms = build_terms([Family.HARMONICS], clean_chain, CLEAN_ARM.read_text)
    rng = np.random.default_rng(2)
    L = se3.inv(se3.xyz_rpy([1.4, 0.5, 0.9], [-2.1, 0.0, 1.9]))
    R = se3.make(t=np.array([0.01, 0.02, 0.05]))
    truth = CalibModel(clean_chain, Setup.EYE_TO_HAND, L, R, terms=terms)
    x_true = np.zeros(truth.size)
    truth.split(x_true).terms[0][1, 0] = math.radians(0.2)  # joint 2: 0.2° × sin q2
    Q = clean_chain.random(rng, 120)
    measurements = _tracker(truth, x_true, Q, 0.02, rng)
    samples = [Sample(str(k), k + 2, q, None) for k, q in enumerate(Q)]
    nominal = CalibModel(
        clean_chain, Setup.EYE_TO_HAND, np.eye(4), np.eye(4), sensor="tracker", target="point", terms=terms
    )
    options = FitOptions(families=(Family.ORIGINS, Family.OFFSETS, Family.HARMONICS), folds=3, nested=False)
    result = calibrate(nominal, measurements, samples, options)
    assert result.joint_terms is not None and result.joint_terms.candidate.name == "origins + offsets + harmonics"
    joint = calibration_document(result, "ds", "clean_arm.urdf")["joint_terms"]["joints"][clean_chain.joint_names[1]]
    assert joint["harmonics_deg"]["sin1"] == pytest.approx(0.2, abs=0.02)


def test_a_stiffness_is_given_only_where_the_sag_is_determined() -> None:
    # k = τmax/sag: a sag within 2 σ of zero gives a lower bound only (the UR5 tracker grid's elbow
    # with harmonics: 0.13 ± 0.12 mrad, which linear propagation wrote as 123 ± 119 kN·m/rad).
    path = erd("ur_description/urdf/ur5_robot.urdf")
    compliance = Compliance(load_chain(path, "base_link", "tool0"), urdf_text(path))
    shoulder, elbow = compliance.max_torque_nm[1], compliance.max_torque_nm[2]
    determined = compliance.report(1, np.array([1.6e-3]), np.array([0.1e-3]))
    assert determined["stiffness_knm_per_rad"]["value"] == pytest.approx(shoulder / 1.6e-3 / 1e3)
    assert determined["stiffness_knm_per_rad"]["sigma"] == pytest.approx(shoulder / 1.6e-3 / 1e3 / 16)
    assert "stiffness_min_knm_per_rad" not in determined
    undetermined = compliance.report(2, np.array([0.13e-3]), np.array([0.12e-3]))
    assert "stiffness_knm_per_rad" not in undetermined
    assert undetermined["stiffness_min_knm_per_rad"] == pytest.approx(elbow / 0.37e-3 / 1e3)
    assert undetermined["gravity_sag_rad"] == 0.13e-3 and undetermined["sigma_gravity_sag_rad"] == 0.12e-3
    # negative beyond 2 σ: a value, which the fit's report flags as no physical stiffness
    assert compliance.report(2, np.array([-0.47e-3]), np.array([0.05e-3]))["stiffness_knm_per_rad"]["value"] < 0
    not_fitted = compliance.report(2, np.array([0.0]), np.array([math.nan]))
    assert "stiffness_knm_per_rad" not in not_fitted and "stiffness_min_knm_per_rad" not in not_fitted
