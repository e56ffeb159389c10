"""Which parameters the pose set can tell apart, and why the others cannot be.

The identification Jacobian (pixels per unit of each candidate parameter, evaluated on the
dataset's poses) is column-scaled to unit norm and reduced in priority order (measurement frames,
then zero offsets, origin rotations, origin translations, gains): a parameter is kept when its
column has a component of at least `tolerance` outside the span of the columns kept before it.
That is QR with a fixed pivot order, so the choice is explainable: each dropped parameter is
regressed on the kept ones and reported with the ones it trades against.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.params import ParamKind
from armtool.calib.model.se3 import Array


@dataclass
class Identifiability:
    kept: list[int]
    dropped: dict[int, str]  # parameter index -> why
    condition_number: float  # of the column-scaled Jacobian of the kept parameters
    observability_index: float  # O1 = (σ1…σp)^(1/p) / √m, same Jacobian
    singular_values: Array = field(default_factory=lambda: np.zeros(0))


def _priority(model: CalibModel, i: int) -> tuple[int, int]:
    """Frames first (always needed), then zero offsets, origin rotations, origin translations, gains, joint terms."""
    p = model.params[i]
    if p.kind is ParamKind.ORIGIN:
        return (2 if p.is_rotation else 3), i
    return {ParamKind.FRAME: 0, ParamKind.OFFSET: 1, ParamKind.GAIN: 4, ParamKind.COMPLIANCE: 5, ParamKind.HARMONIC: 6}[
        p.kind
    ], i


def analyse(model: CalibModel, J: Array, candidates: list[int], tolerance: float = 1e-6) -> Identifiability:
    """J has one column per candidate (same order as `candidates`)."""
    norms = np.linalg.norm(J, axis=0)
    order = sorted(range(len(candidates)), key=lambda k: _priority(model, candidates[k]))
    basis: list[Array] = []  # orthonormal basis of the kept columns
    kept_cols: list[int] = []
    dropped_cols: list[int] = []
    for k in order:
        if norms[k] <= 1e-12 * max(1.0, float(norms.max())):
            dropped_cols.append(k)
            continue
        v = J[:, k] / norms[k]
        for b in basis:  # twice for numerical safety (Gram-Schmidt with re-orthogonalisation)
            v = v - (b @ v) * b
        for b in basis:
            v = v - (b @ v) * b
        residual = float(np.linalg.norm(v))
        if residual > tolerance:
            basis.append(v / residual)
            kept_cols.append(k)
        else:
            dropped_cols.append(k)
    kept_cols.sort()
    scaled = J[:, kept_cols] / norms[kept_cols]
    dropped: dict[int, str] = {}
    for k in dropped_cols:
        idx = candidates[k]
        dropped[idx] = _explain(model, J, norms, candidates, kept_cols, k, scaled)
    s = np.linalg.svd(scaled, compute_uv=False) if kept_cols else np.zeros(0)
    cond = float(s[0] / s[-1]) if s.size and s[-1] > 0 else math.inf
    o1 = float(np.exp(np.mean(np.log(np.maximum(s, 1e-300)))) / math.sqrt(J.shape[0])) if s.size else 0.0
    return Identifiability([candidates[k] for k in kept_cols], dropped, cond, o1, s)


def _explain(
    model: CalibModel, J: Array, norms: Array, candidates: list[int], kept_cols: list[int], k: int, scaled: Array
) -> str:
    p = model.params[candidates[k]]
    if norms[k] <= 1e-12 * max(1.0, float(norms.max())):
        return f"{p.describe()} does not change any measurement"
    coef, *_ = np.linalg.lstsq(scaled, J[:, k] / norms[k], rcond=None)
    top = np.argsort(-np.abs(coef))
    partners = []
    frames_seen = set()
    for t in top[:6]:
        if abs(coef[t]) < 0.2:
            break
        q = model.params[candidates[kept_cols[t]]]
        if q.kind is ParamKind.FRAME:  # one mention per frame is enough
            if q.group in frames_seen:
                continue
            frames_seen.add(q.group)
            partners.append(f"the {q.group} frame")
        else:
            partners.append(q.describe())
        if len(partners) == 2:
            break
    if not partners:
        return f"{p.describe()} is a combination of several kept parameters"
    return f"{p.describe()} trades against " + " and ".join(partners)
