"""Score a calibration against a simulated dataset's truth, as research/calibration.md §3 does.

Flange poses of the calibrated model and of the true robot are compared on validation poses the
fit never saw, after the best rigid registration of base and tool (the base and tool gauge are
not observable, and a hand-eye-only calibration is exactly that registration): position error
of the flange origin and rotation angle, RMS and max.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.optimize import least_squares

from armtool.calib.model import se3
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError

if TYPE_CHECKING:
    from armtool.calib.fit.calibration import CalibrationResult


@dataclass(frozen=True)
class PoseErrors:
    position_rms_mm: float
    position_max_mm: float
    rotation_rms_deg: float
    rotation_max_deg: float


@dataclass(frozen=True)
class Truth:
    x: Array  # true parameter vector (kinematic part; frames zero)
    validation: Array  # (M, n) joint vectors
    bad_samples: dict[str, str]


def load_truth(dataset: Path, model: CalibModel) -> Truth:
    """The truth `simulate` kept apart; ArmtoolError when it is missing or not as written."""
    import yaml

    from armtool.yamlload import safe_load

    path = dataset / "truth" / "truth.yaml"
    if not path.is_file():
        raise ArmtoolError(
            "no truth/truth.yaml", str(path), "only datasets made by `armtool calibrate simulate` have a truth"
        )
    try:
        doc = safe_load(path.read_text(encoding="utf-8"))
        x = np.zeros(model.size)
        parts = model.split(x)
        for i, name in enumerate(model.chain.joint_names):
            j = doc["joints"][name]
            parts.origin[i, :3] = j["origin_t_m"]
            parts.origin[i, 3:] = j["origin_r_rad"]
            parts.offset[i] = j["offset_rad"]
        rows = (dataset / "truth" / "validation.csv").read_text(encoding="utf-8").strip().splitlines()
        header = rows[0].split(",")
        order = [header.index(n) for n in model.chain.joint_names]
        Q = np.array([[float(r.split(",")[c]) for c in order] for r in rows[1:]], dtype=float).reshape(
            -1, model.chain.n
        )
        bad = {str(key): str(v) for key, v in (doc.get("bad_samples") or {}).items()}
    except (
        OSError,
        UnicodeDecodeError,
        yaml.YAMLError,
        RecursionError,
        KeyError,
        IndexError,
        TypeError,
        ValueError,
        AttributeError,
    ) as exc:
        raise ArmtoolError(
            f"the truth files are not as `calibrate simulate` wrote them ({type(exc).__name__}: {str(exc)[:80]})",
            str(path.parent),
        ) from None
    if not (np.isfinite(x).all() and np.isfinite(Q).all()) or len(Q) == 0:
        raise ArmtoolError("the truth files hold no validation pose or non-finite values", str(path.parent))
    return Truth(x, Q, bad)


def registered_errors(F_est: Array, F_true: Array) -> PoseErrors:
    """Errors of B · F_est · T against F_true with the base B and tool T that fit best."""

    def residual(v: Array) -> Array:
        B, T = se3.delta(v[:6]), se3.delta(v[6:])
        G = B @ F_est @ T
        dp = (G[:, :3, 3] - F_true[:, :3, 3]).ravel()
        dr = np.concatenate([se3.log3(G[i, :3, :3].T @ F_true[i, :3, :3]) for i in range(len(G))])
        return np.concatenate([dp, 0.1 * dr])  # 0.1 m per rad: both matter at the flange

    res = least_squares(residual, np.zeros(12), method="lm")
    B, T = se3.delta(res.x[:6]), se3.delta(res.x[6:])
    G = B @ F_est @ T
    dp = np.linalg.norm(G[:, :3, 3] - F_true[:, :3, 3], axis=1) * 1e3
    da = np.array([math.degrees(np.linalg.norm(se3.log3(G[i, :3, :3].T @ F_true[i, :3, :3]))) for i in range(len(G))])
    return PoseErrors(float(np.sqrt(np.mean(dp**2))), float(dp.max()), float(np.sqrt(np.mean(da**2))), float(da.max()))


def score(model: CalibModel, x: Array, truth: Truth) -> PoseErrors:
    return registered_errors(model.flange(x, truth.validation), model.flange(truth.x, truth.validation))


def has_truth(dataset: Path) -> bool:
    """Only datasets made by `calibrate simulate` have a truth to score against."""
    return (dataset / "truth" / "truth.yaml").is_file()


def truth_scores(dataset: Path, result: CalibrationResult) -> dict[str, Any]:
    """calibration.yaml's `against_truth`: errors of the hand-eye-only and the calibrated robot
    against the known true robot on its validation poses, and which injected bad samples the fit
    named. ArmtoolError when the truth files are missing or not as written."""
    truth = load_truth(dataset, result.model)
    before, after = score(result.model, result.x_handeye, truth), score(result.model, result.x, truth)
    return {
        "validation_poses": int(len(truth.validation)),
        "hand_eye_only": before.__dict__,
        "calibrated": after.__dict__,
        "improvement": before.position_rms_mm / after.position_rms_mm if after.position_rms_mm > 0 else math.inf,
        "bad_samples": truth.bad_samples,
        "bad_samples_named": sorted(set(truth.bad_samples) & set(result.outliers)),
    }
