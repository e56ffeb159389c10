"""What a calibration writes: calibration.yaml (everything a person or driver needs) and the
numbers the terminal report shows (the figure is `plot`'s)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from armtool.calib.apply import TERMS_URDF
from armtool.calib.fit.calibration import CalibrationResult, SampleResidual
from armtool.calib.fit.crossval import Candidate
from armtool.calib.fit.determined import Combination, Subspace
from armtool.calib.fit.flange_gauge import FlangeDeviation, FlangeGauge
from armtool.calib.fit.problems import POSITION, Block
from armtool.calib.model import se3
from armtool.calib.model.params import ParamKind
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
    frames = frames_section(result, sigma)
    joints = joints_section(result, result.x, sigma, result.candidate)
    terms = result.joint_terms
    fitted_terms = [t for t in model.terms if t.kind.value in (terms.candidate if terms else result.candidate).kinds]
    document: dict[str, Any] = {
        "format": SCHEMA,
        "dataset": dataset,
        "urdf": urdf,
        "setup": model.setup.value,
        "frames": frames,
        "conventions": "origin_new = origin · SE3(exp(r), t) · motion(zero_offset); the reading q maps to gain·q + zero_offset",
        "in_urdf": _in_urdf(result, fitted_terms),
        "fitted": result.candidate.name,
        "joints": joints,
        "joint_terms": joint_terms_section(result),
        "zero_offsets": zero_offsets_section(result),
        "identifiability": identifiability_section(result),
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


def _in_urdf(result: CalibrationResult, fitted_terms: list[Any]) -> str:
    text = "origin corrections and zero offsets are already folded into calibrated.urdf: do not apply them again"
    terms = result.joint_terms
    if terms is None:
        return text
    what = ", ".join(t.family.value for t in fitted_terms)
    return (
        text + f"; calibrated.urdf is {result.candidate.name} fitted alone, to be read as it is (no gains, no joint "
        f"terms). The chosen set, {terms.candidate.name}, is in joint_terms: a URDF cannot hold its {what}, so its "
        f"geometry is in {TERMS_URDF}, right with its frames and fed gain·q + Σ p·f(q) − mean_correction for each "
        "joint's reading q (`calibrate apply`); read at the readings as they are, it is the arm on average over the "
        "fit's poses (its zero offsets, with the mean correction, are in it; docs/calibrate.md)"
    )


def joints_section(
    result: CalibrationResult, x: Array, sigma: dict[int, float], candidate: Candidate
) -> dict[str, Any]:
    """Per joint: the origin correction, zero offset and gain of `x` with their σ, and the joint
    terms `candidate` fitted."""
    model = result.model
    offsets = {z.joint: z for z in result.zero_offsets}

    def value(i: int) -> float:
        return round(float(x[i]), 12)

    def sigma_of(i: int) -> float | None:
        return _num(sigma[i]) if i in sigma else None

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
        if z is not None and candidate == result.candidate:  # the analysis is of calibrated.urdf's fit
            entry["zero_offset_physical"] = z.physical
            entry["zero_offset_uncertainty"] = _num(z.uncertainty_rad)
        entry["gain"] = round(1.0 + float(x[gain]), 12)
        entry["sigma_gain"] = sigma_of(gain)
        for k, term in enumerate(model.terms):  # compliance, harmonics: not in the URDF either
            if term.kind.value not in candidate.kinds:  # tried by the k-fold, not chosen: nothing fitted
                continue
            indices = model.layout.term(k, j_index)
            sigmas = np.array([sigma.get(i, math.nan) for i in indices])
            entry.update(term.report(j_index, x[indices], sigmas))
        joints[j.name] = entry
    return joints


def _with_mean_corrections(joints: dict[str, Any], result: CalibrationResult) -> dict[str, Any]:
    """Each joint's `mean_correction` (what its gain and terms add on average over the fit's
    readings, rad or m) and the zero offset calibrated_with_terms.urdf holds with it."""
    terms = result.joint_terms
    assert terms is not None
    mean = terms.mean_correction if terms.mean_correction is not None else np.zeros(len(joints))
    for (_name, entry), m in zip(joints.items(), mean):
        entry["mean_correction"] = round(float(m), 12)
        entry["zero_offset_in_urdf"] = round(float(entry["zero_offset"] + m), 12)
    return joints


def joint_terms_section(result: CalibrationResult) -> dict[str, Any] | None:
    """The chosen set with its joint terms, when calibrated.urdf holds only its URDF rung: its own
    geometry (calibrated_with_terms.urdf), frames, terms, what of the terms the data do not
    determine, and figures."""
    terms = result.joint_terms
    if terms is None:
        return None
    model = result.model
    sigma = dict(zip(terms.free, (float(v) for v in terms.sigma)))
    out: dict[str, Any] = {
        "fitted": terms.candidate.name,
        "urdf": TERMS_URDF,
        "meaning": f"the k-fold chose {terms.candidate.name}, which a URDF cannot hold: calibrated.urdf is "
        f"{result.candidate.name} fitted alone, to be read as it is with the frames above; {TERMS_URDF} is this "
        "set's own geometry, right with these frames and fed gain·q + Σ p·f(q) − mean_correction for each joint's "
        "reading q (`calibrate apply`); read at the readings as they are, it is the arm on average over the fit's "
        "poses: each joint's mean_correction is in its zero offset (docs/calibrate.md)",
        "frames": frames_section(result, sigma, terms.x),
        "joints": _with_mean_corrections(joints_section(result, terms.x, sigma, terms.candidate), result),
        "base_link": model.chain.base,
        "flange_link": model.chain.tip,
        "terms": _term_values(result, terms.x, terms.candidate),
        "dropped": [
            {"parameter": model.params[i].name, "reason": why}
            for i, why in terms.identifiability.dropped.items()
            if model.params[i].kind in (ParamKind.COMPLIANCE, ParamKind.HARMONIC)
        ],
        "held": [_combination(result, c, terms.subspace) for c in terms.subspace.held],
        "flange_gauge": flange_gauge_section(terms.flange_gauge),
    }
    for b in result.blocks:
        before, after = terms.fit.rms[b.name]
        out[f"fit_rms_{_key(b)}"] = {"hand_eye_only": _num(before), "calibrated": _num(after)}
    cv = result.crossval
    if cv is not None:
        for b in result.blocks:
            out[f"heldout_rms_{_key(b)}"] = _num(cv.score_of(terms.candidate.name).rms[b.name])
        if cv.nested_terms is not None:
            n = cv.nested_terms
            for b in result.blocks:
                out[f"nested_heldout_rms_{_key(b)}"] = _num(n.rms[b.name])
                out[f"nested_heldout_max_{_key(b)}"] = _num(n.maximum[b.name])
                out[f"nested_heldout_mean_{_key(b)}"] = _num(float(np.nanmean(n.per_sample[b.name])))
    return out


def _term_values(result: CalibrationResult, x: Array, candidate: Candidate) -> dict[str, Any]:
    """Each fitted term's parameters per joint, in its components' order and in rad: what
    `calibrate apply` reads back (`joints` shows them in the units a person reads)."""
    model = result.model
    out: dict[str, Any] = {}
    for k, term in enumerate(model.terms):
        if term.kind.value not in candidate.kinds:
            continue
        out[term.family.value] = {
            "components": list(term.components),
            "unit": "rad",
            "joints": {
                j.name: [round(float(v), 15) for v in x[model.layout.term(k, i)]]
                for i, j in enumerate(model.chain.joints)
            },
        }
    return out


def identifiability_section(result: CalibrationResult) -> dict[str, Any]:
    """What the data determine: the parameters QR keeps (rank), the combinations of them fitted and
    those held with their σ (`fit/determined.py`), the parameters dropped and why, and where the
    flange was put along what the data leave free (`fit/flange_gauge.py`)."""
    model, ident, subspace = result.model, result.identifiability, result.subspace
    held = subspace.held if subspace else []
    out: dict[str, Any] = {
        "identified": subspace.dimension if subspace else len(result.free),
        "identifiable_by_rank": len(result.free),
        "candidates": len(result.free) + len(ident.dropped),
        "precision": subspace.precision.describe() if subspace else None,
        "meaning": "identified counts what the fit moved: the frame parameters and the combinations of the "
        "identifiable ones determined to the precision (sigma at most the precision); held lists the others, which "
        "the fit did not move. Along them and the dropped parameters, which change no measurement, calibrated.urdf "
        "is then set where its flange is nearest the nominal arm's over the fit's poses, the measurements as they "
        "were (flange_gauge). The sigmas in `joints` are those of the fit that held them",
        "condition_number": _num(ident.condition_number),
        "observability_index": _num(ident.observability_index),
        "identified_parameters": [model.params[i].name for i in result.free],
        "held": [_combination(result, c) for c in held],
        "flange_gauge": flange_gauge_section(result.flange_gauge),
        "dropped": [{"parameter": model.params[i].name, "reason": why} for i, why in ident.dropped.items()],
    }
    return out


def flange_gauge_section(gauge: FlangeGauge | None) -> dict[str, Any] | None:
    """The flange from the nominal arm's over the fit's poses, before and after it was put nearest
    nominal where the data leave the geometry free, and what that cost the fit (χ²)."""
    if gauge is None:
        return None

    def deviation(d: FlangeDeviation) -> dict[str, float | None]:
        return {
            "mean_mm": _num(d.mean_mm),
            "max_mm": _num(d.max_mm),
            "mean_deg": _num(d.mean_deg),
            "max_deg": _num(d.max_deg),
        }

    return {
        "free_combinations": gauge.directions,
        "before": deviation(gauge.before),
        "after": deviation(gauge.after),
        "chi2_change": _num(gauge.chi2_change),
        "meaning": "the flange link's pose against the nominal arm's at the fit's poses: before, as the fit left "
        "it; after, moved along what the data do not determine (free_combinations) to where it is nearest the "
        "nominal arm's; what the data determine stays (docs/calibrate.md)",
    }


def _combination(result: CalibrationResult, c: Combination, subspace: Subspace | None = None) -> dict[str, Any]:
    """A combination: its σ in precision units, its value in σ, and each parameter's σ along it."""
    subspace = subspace or result.subspace
    assert subspace is not None
    sigmas: dict[str, float | None] = {}
    for p, value in c.parameter_sigma(result.model, subspace.precision):
        key = f"{p.name}_{'mm' if p.unit == 'm' else ('deg' if p.unit == 'rad' else '1')}"
        sigmas[key] = _num(value * 1e3 if p.unit == "m" else (math.degrees(value) if p.unit == "rad" else value))
    return {
        "sigma_in_precision_units": _num(c.sigma),
        "sigmas_from_nominal": _num(c.significance),
        "parameter_sigma": sigmas,
    }


def frames_section(result: CalibrationResult, sigma: dict[int, float], x: Array | None = None) -> dict[str, Any]:
    """The two fitted placements (`camera_in_flange`, `board_in_base`, …) of `x` (default: the
    result's) with each correction component's σ in the frame's own axes (mm, °); a measured
    point is only a position."""
    model = result.model
    L, R = model.frames(result.x if x is None else x)
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
    for optional in ("against_truth", "measurement_conventions", "joint_terms"):
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
