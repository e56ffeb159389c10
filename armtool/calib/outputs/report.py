"""What a calibration writes: calibration.yaml (everything a person or driver needs) and the
numbers the terminal report shows (the figure is `plot`'s)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from armtool.calib.fit.calibration import CalibrationResult, SampleResidual
from armtool.calib.fit.problems import POSITION, Block
from armtool.calib.model import se3
from armtool.calib.model.se3 import Array

if TYPE_CHECKING:
    from armtool.calib.fit.convention_check import ConventionCheck
    from armtool.calib.fit.verdict import Verdict

SCHEMA = "armtool-calibration/1"


def _pose(T: Array) -> dict[str, list[float]]:
    return {"xyz": [round(float(v), 9) for v in T[:3, 3]], "rpy": [round(float(v), 9) for v in se3.rpy_of(T[:3, :3])]}


def _num(v: float) -> float | None:
    return None if not math.isfinite(v) else round(float(v), 12)


def calibration_document(
    result: CalibrationResult,
    dataset: str,
    urdf: str,
    verdict: Verdict | None = None,
    conventions: ConventionCheck | None = None,
) -> dict[str, Any]:
    model = result.model
    sigma = dict(zip(result.free, result.sigma))
    free = set(result.free)
    frames = frames_section(result, sigma)
    offsets = {z.joint: z for z in result.zero_offsets}

    def value(i: int) -> float:
        return round(float(result.x[i]), 12)

    def sigma_of(i: int) -> float | None:
        return _num(sigma[i]) if i in free else None

    joints: dict[str, Any] = {}
    for j_index, j in enumerate(model.chain.joints):
        origin, offset, gain = model.layout.origin(j_index), model.layout.offset(j_index), model.layout.gain(j_index)
        entry: dict[str, Any] = {}
        for label, indices in (("origin_translation_m", origin[:3]), ("origin_rotation_rad", origin[3:])):
            entry[label] = [value(i) for i in indices]
            entry[label.replace("origin_", "sigma_")] = [sigma_of(i) for i in indices]
        entry["zero_offset"] = value(offset)
        entry["sigma_zero_offset"] = sigma_of(offset)
        z = offsets.get(j.name)
        if z is not None:
            entry["zero_offset_physical"] = z.physical
            entry["zero_offset_uncertainty"] = _num(z.uncertainty_rad)
        entry["gain"] = round(1.0 + float(result.x[gain]), 12)
        entry["sigma_gain"] = sigma_of(gain)
        for k, term in enumerate(model.terms):  # compliance, harmonics: not in the URDF either
            indices = model.layout.term(k, j_index)
            sigmas = np.array([sigma[i] if i in free else math.nan for i in indices])
            entry.update(term.report(j_index, result.x[indices], sigmas))
        joints[j.name] = entry
    ident = result.identifiability
    document: dict[str, Any] = {
        "format": SCHEMA,
        "dataset": dataset,
        "urdf": urdf,
        "setup": model.setup.value,
        "frames": frames,
        "conventions": "origin_new = origin · SE3(exp(r), t) · motion(zero_offset); the reading q maps to gain·q + zero_offset",
        "in_urdf": "origin corrections and zero offsets are already folded into calibrated.urdf: do not apply them again; "
        "gains are not (a URDF cannot hold them): apply gain·q in the driver if it differs from 1"
        + (
            "; nor are the joint terms (" + ", ".join(t.family.value for t in model.terms) + "): they add "
            "Σ p·f(q) to each joint's angle, see docs/calibrate.md"
            if model.terms
            else ""
        ),
        "fitted": result.candidate.name,
        "joints": joints,
        "zero_offsets": zero_offsets_section(result),
        "identifiability": {
            "identified": len(result.free),
            "candidates": len(result.free) + len(ident.dropped),
            "condition_number": _num(ident.condition_number),
            "observability_index": _num(ident.observability_index),
            "identified_parameters": [model.params[i].name for i in result.free],
            "dropped": [{"parameter": model.params[i].name, "reason": why} for i, why in ident.dropped.items()],
        },
        "noise": {f"{b.name}_{b.unit}": _num(result.noise.get(b.name, math.nan)) for b in result.blocks},
        "metrics": _metrics(result),
        "cross_validation": crossval_section(result),
        "verdict": _verdict(verdict),
        "outliers": dict(result.outliers),
        "rejected": dict(result.rejected),
        "samples": [_sample(result, r) for r in result.residuals],
        "warnings": list(result.warnings),
    }
    if conventions is not None:
        document["measurement_conventions"] = {
            "declared": conventions.declared.describe(),
            "readings_tried": conventions.tried,
            "better_reading": conventions.better.describe() if conventions.better else None,
            "fix": conventions.fix() or None,
            "note": conventions.message(),
        }
    return document


def frames_section(result: CalibrationResult, sigma: dict[int, float]) -> dict[str, Any]:
    """The two fitted placements (`camera_in_flange`, `board_in_base`, …) with each correction
    component's σ in the frame's own axes (mm, °); a measured point is only a position."""
    model = result.model
    L, R = result.fitted_frames()
    sensor, target = model.frame_names()
    point = result.blocks == (POSITION,)

    def sigmas(indices: list[int]) -> dict[str, list[float | None]]:
        out = [sigma.get(i) for i in indices]
        mm = [None if v is None else _num(v * 1e3) for v in out[:3]]
        deg = [None if v is None else _num(math.degrees(v)) for v in out[3:]]
        return {"sigma_xyz_mm": mm} if point and indices[0] >= 6 else {"sigma_xyz_mm": mm, "sigma_rotation_deg": deg}

    frames = model.layout.frames
    left = {**_pose(se3.inv(L)), **sigmas(frames[:6])}
    right = {"xyz": _pose(R)["xyz"], **sigmas(frames[6:])} if point else {**_pose(R), **sigmas(frames[6:])}
    return {sensor: left, target: right}


def _key(block: Block) -> str:
    return block.unit


def _metrics(result: CalibrationResult) -> dict[str, Any]:
    """fit_rms_px (or _mm and _deg), holdout_rms_…, holdout_without_outliers_rms_…: hand-eye only and calibrated."""
    out: dict[str, Any] = {}
    sets = (("fit", result.fit), ("holdout", result.holdout), ("holdout_without_outliers", result.holdout_inliers))
    for label, comparison in sets:
        for b in result.blocks:
            pair = comparison.rms[b.name] if comparison is not None else (math.nan, math.nan)
            out[f"{label}_rms_{_key(b)}"] = {"hand_eye_only": _num(pair[0]), "calibrated": _num(pair[1])}
    for b in result.blocks:
        pair = result.fit.maximum[b.name] if result.fit is not None else (math.nan, math.nan)
        out[f"fit_max_{_key(b)}"] = {"hand_eye_only": _num(pair[0]), "calibrated": _num(pair[1])}
    return out


def crossval_section(result: CalibrationResult) -> dict[str, Any] | None:
    """The k-fold scores of every candidate, the choice, and the nested held-out residual."""
    cv = result.crossval
    if cv is None:
        return None
    candidates = []
    for score in cv.scores:
        entry: dict[str, Any] = {
            "name": score.candidate.name,
            "parameters": _num(score.parameters),
            "score": _num(score.loss),
        }
        for b in result.blocks:
            entry[f"heldout_rms_{_key(b)}"] = _num(score.rms[b.name])
            entry[f"heldout_max_{_key(b)}"] = _num(score.maximum[b.name])
            entry[f"heldout_without_outliers_rms_{_key(b)}"] = _num(score.inlier_rms[b.name])
        if score.failed:
            entry["failed_folds"] = score.failed
        candidates.append(entry)
    out: dict[str, Any] = {
        "folds": cv.folds,
        "samples": cv.samples,
        "score": "mean soft-L1 loss of each held-out sample's noise-weighted RMS residual (lower is better)",
        "candidates": candidates,
        "chosen": cv.chosen.name,
        "fitted": result.candidate.name,
    }
    if cv.nested is not None:
        n = cv.nested
        nested: dict[str, Any] = {
            "meaning": "each outer training set chose its parameter set by its own inner k-fold and was scored on the "
            "outer fold: the held-out residual of the whole procedure",
            "chosen_per_fold": n.chosen,
            "samples": n.samples,
            "inliers": n.inliers,
        }
        for b in result.blocks:
            nested[f"heldout_rms_{_key(b)}"] = {
                "hand_eye_only": _num(n.hand_eye_rms[b.name]),
                "calibrated": _num(n.rms[b.name]),
            }
            nested[f"heldout_max_{_key(b)}"] = {
                "hand_eye_only": _num(n.hand_eye_maximum[b.name]),
                "calibrated": _num(n.maximum[b.name]),
            }
            nested[f"heldout_without_outliers_rms_{_key(b)}"] = _num(n.inlier_rms[b.name])
        out["nested"] = nested
    return out


def _verdict(verdict: Verdict | None) -> dict[str, Any] | None:
    if verdict is None:
        return None
    return {
        "improves_on_nominal": verdict.improves,
        "cross_validated": verdict.checked,
        "summary": verdict.summary,
        "advice": verdict.advice or None,
        "poses_needed": verdict.poses_needed,
    }


def _sample(result: CalibrationResult, r: SampleResidual) -> dict[str, Any]:
    out: dict[str, Any] = {"id": r.sample_id, "role": r.role}
    for b in result.blocks:
        out[f"hand_eye_only_{_key(b)}"] = _num(r.before.get(b.name, math.nan))
        out[f"calibrated_{_key(b)}"] = _num(r.after.get(b.name, math.nan))
        if r.cross_validated:
            out[f"cross_validated_{_key(b)}"] = _num(r.cross_validated.get(b.name, math.nan))
    if r.note:
        out["note"] = r.note
    return out


# What `calibrate fit --format json` prints: the document without the per-joint and per-sample detail.
SUMMARY_KEYS = (
    "setup",
    "frames",
    "fitted",
    "identifiability",
    "zero_offsets",
    "noise",
    "metrics",
    "cross_validation",
    "verdict",
    "outliers",
    "rejected",
    "warnings",
)


def json_summary(document: dict[str, Any]) -> dict[str, Any]:
    """The JSON summary of a calibration document (`schema_version` 1)."""
    summary = {k: document[k] for k in SUMMARY_KEYS}
    summary["schema_version"] = 1
    for optional in ("against_truth", "measurement_conventions"):
        if optional in document:
            summary[optional] = document[optional]
    return summary


def zero_offsets_section(result: CalibrationResult) -> dict[str, Any]:
    """Per revolute joint: whether its fitted zero offset is a physical encoder correction."""
    out: dict[str, Any] = {
        "meaning": "physical: true means the value can be used to re-zero the encoder (uncertainty = noise and the origin "
        "errors it cannot be told from); physical: false means it only balances origin errors the data cannot separate "
        "from it: it is correct inside calibrated.urdf, not as an encoder correction",
    }
    for z in result.zero_offsets:
        out[z.joint] = {
            "value_deg": round(math.degrees(z.value_rad), 6),
            "uncertainty_deg": _num(round(math.degrees(z.uncertainty_rad), 6)),
            "physical": z.physical,
            "trades_with": [
                {
                    "parameter": p.parameter,
                    ("deg_per_mm" if p.unit == "m" else "deg_per_deg"): round(
                        math.degrees(p.coefficient) * 1e-3 if p.unit == "m" else p.coefficient, 6
                    ),
                }
                for p in z.partners[:5]
            ],
            "note": z.note,
        }
    return out
