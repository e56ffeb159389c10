"""What a calibration writes: calibration.yaml (everything a person or driver needs), a residual
plot, and the numbers the terminal report shows."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from armtool.calib import se3
from armtool.calib.choices import Setup
from armtool.calib.fit import CalibrationResult
from armtool.calib.se3 import Array

SCHEMA = "armtool-calibration/1"


def _pose(T: Array) -> dict[str, list[float]]:
    return {"xyz": [round(float(v), 9) for v in T[:3, 3]], "rpy": [round(float(v), 9) for v in se3.rpy_of(T[:3, :3])]}


def _num(v: float) -> float | None:
    return None if not math.isfinite(v) else round(float(v), 12)


def calibration_document(result: CalibrationResult, dataset: str, urdf: str) -> dict[str, Any]:
    model = result.model
    L, R = result.fitted_frames()
    sigma = dict(zip(result.free, result.sigma))
    free = set(result.free)
    frames: dict[str, Any]
    if model.setup is Setup.EYE_TO_HAND:
        frames = {"camera_in_base": _pose(se3.inv(L)), "tag_in_flange": _pose(R)}
    else:
        frames = {"camera_in_flange": _pose(se3.inv(L)), "tag_in_base": _pose(R)}
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
        joints[j.name] = entry
    ident = result.identifiability
    return {
        "format": SCHEMA,
        "dataset": dataset,
        "urdf": urdf,
        "setup": model.setup.value,
        "frames": frames,
        "conventions": "origin_new = origin · SE3(exp(r), t) · motion(zero_offset); the reading q maps to gain·q + zero_offset",
        "in_urdf": "origin corrections and zero offsets are already folded into calibrated.urdf: do not apply them again; "
        "gains are not (a URDF cannot hold them): apply gain·q in the driver if it differs from 1",
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
        "metrics": {
            "fit_rms_px": {"hand_eye_only": _num(result.fit_rms_px[0]), "calibrated": _num(result.fit_rms_px[1])},
            "holdout_rms_px": {
                "hand_eye_only": _num(result.holdout_rms_px[0]),
                "calibrated": _num(result.holdout_rms_px[1]),
            },
            "holdout_without_outliers_rms_px": {
                "hand_eye_only": _num(result.holdout_inlier_rms_px[0]),
                "calibrated": _num(result.holdout_inlier_rms_px[1]),
            },
        },
        "outliers": dict(result.outliers),
        "rejected": dict(result.rejected),
        "samples": [
            {
                "id": r.sample_id,
                "role": r.role,
                "hand_eye_only_px": _num(r.before_px),
                "calibrated_px": _num(r.after_px),
                **({"note": r.note} if r.note else {}),
            }
            for r in result.residuals
        ],
        "warnings": list(result.warnings),
    }


# What `calibrate fit --format json` prints: the document without the per-joint and per-sample detail.
SUMMARY_KEYS = ("setup", "frames", "identifiability", "zero_offsets", "metrics", "outliers", "rejected", "warnings")


def json_summary(document: dict[str, Any]) -> dict[str, Any]:
    """The JSON summary of a calibration document (`schema_version` 1)."""
    summary = {k: document[k] for k in SUMMARY_KEYS}
    summary["schema_version"] = 1
    if "against_truth" in document:
        summary["against_truth"] = document["against_truth"]
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


def residual_plot_png(result: CalibrationResult) -> bytes:
    """Per-sample corner RMS before (hand-eye only, grey) and after (blue); outliers in red."""
    import cv2

    rows = [r for r in result.residuals if r.role != "rejected"]
    W, H = 1100, 480
    x0, y0, x1, y1 = 70, 40, W - 20, H - 70
    img = np.full((H, W, 3), 255, np.uint8)
    font = cv2.FONT_HERSHEY_SIMPLEX
    cv2.rectangle(img, (x0, y0), (x1, y1), (0, 0, 0), 1)
    values = [v for r in rows for v in (r.before_px, r.after_px) if math.isfinite(v) and v > 0]
    lo = math.floor(math.log10(min(values))) if values else -2
    hi = math.ceil(math.log10(max(values))) if values else 1
    hi = max(hi, lo + 1)

    def ypos(v: float) -> int:
        v = max(v, 10**lo)
        return int(y1 - (math.log10(v) - lo) / (hi - lo) * (y1 - y0))

    for d in range(lo, hi + 1):
        y = ypos(10**d)
        cv2.line(img, (x0, y), (x1, y), (225, 225, 225), 1)
        cv2.putText(img, f"{10**d:g}", (8, y + 4), font, 0.4, (0, 0, 0), 1, cv2.LINE_AA)
    step = (x1 - x0) / max(len(rows), 1)
    for k, r in enumerate(rows):
        xa = int(x0 + k * step + step * 0.15)
        w = max(1, int(step * 0.35))
        if math.isfinite(r.before_px):
            cv2.rectangle(img, (xa, ypos(r.before_px)), (xa + w, y1), (170, 170, 170), -1)
        color = (40, 39, 214) if r.role == "outlier" else ((44, 160, 44) if r.role == "holdout" else (180, 119, 31))
        if math.isfinite(r.after_px):
            cv2.rectangle(img, (xa + w, ypos(r.after_px)), (xa + 2 * w, y1), color, -1)
    cv2.putText(
        img,
        "corner RMS per sample (px, log): grey hand-eye only, blue calibrated, green held out, red outlier",
        (x0, y1 + 40),
        font,
        0.45,
        (0, 0, 0),
        1,
        cv2.LINE_AA,
    )
    ok, buf = cv2.imencode(".png", img)
    return bytes(buf) if ok else b""
