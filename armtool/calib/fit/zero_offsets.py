"""Which fitted zero offsets are physical encoder corrections, and which only balance the books.

A zero offset of joint j turns everything after joint j about its axis; a rigid error in the next
joint's `<origin>` can do exactly the same. With 6-D origin corrections the pose set can never
tell the two apart: the identifiability analysis keeps the offset and drops the origin components
it trades against, and the fitted offset then carries those origin errors too:

    fitted offset = encoder offset + Σ_k c_k · (origin error k that was dropped)

The coefficients c_k come straight from the identification Jacobian (the dropped columns regressed
on the kept ones; exact when the dropped column lies in their span). On a UR5 (links of 0.4 m) a
millimetre of a dropped translation moves an offset by about 0.14°; on a desktop arm with 3–6 cm
between axes, by 1–6°. The calibrated URDF is right either way (the whole correction is folded in
together), but re-zeroing an encoder on the second kind of number moves the arm by degrees.

The spread of an offset is how far origin errors of the size this very fit found (RMS of the
identified origin translations and rotations) can move it; together with its σ from the noise,
it is the offset's uncertainty, a one-σ-like scale (measured on simulated UR5 and Panda data, the
true error exceeded it in about one case in six). An offset is reported as a physical encoder
correction only when twice its uncertainty stays within `PHYSICAL_LIMIT_RAD`; otherwise it is
marked as not physically meaningful, with what it trades against.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from armtool.calib.fit.identify import Identifiability
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.params import ParamKind
from armtool.calib.model.se3 import Array

# A policy, not a measurement: an encoder re-zero that may be wrong by more than 1° can leave the
# arm worse than the zero drift it is meant to fix (servo encoders resolve 0.09°, industrial ones
# far less), so twice the uncertainty must stay within it.
PHYSICAL_LIMIT_RAD = math.radians(1.0)
_MIN_COEFFICIENT = 1e-3  # partners whose coefficient is below this (per unit) are not named
OriginUnit = Literal["m", "rad"]  # of an origin component: translation or rotation


@dataclass(frozen=True)
class Partner:
    parameter: str  # e.g. "elbow_flex.origin.ty"
    coefficient: float  # rad of offset per m (translation) or per rad (rotation) of the partner
    unit: OriginUnit

    def describe(self) -> str:
        if self.unit == "m":
            return f"{self.parameter} (1 mm there = {math.degrees(self.coefficient) * 1e-3:+.2f}°)"
        return f"{self.parameter} (0.1° there = {self.coefficient * 0.1:+.2f}°)"


@dataclass(frozen=True)
class ZeroOffset:
    joint: str
    value_rad: float
    identified: bool  # kept by the identifiability analysis
    sigma_rad: float  # from the measurement noise (nan when not identified)
    spread_rad: float  # how far origin errors of the fitted size can move it
    physical: bool
    partners: tuple[Partner, ...]
    note: str

    @property
    def uncertainty_rad(self) -> float:
        return math.hypot(self.sigma_rad, self.spread_rad) if self.identified else math.inf


def _rms(values: Array) -> float:
    return float(np.sqrt(np.mean(values**2))) if values.size else 0.0


def analyse_offsets(
    model: CalibModel, J: Array, candidates: list[int], ident: Identifiability, x: Array, sigma: dict[int, float]
) -> list[ZeroOffset]:
    """One entry per revolute joint's zero offset. `J` has one column per candidate (at the fit)."""
    kept = [candidates.index(i) for i in ident.kept]
    dropped = [candidates.index(i) for i in ident.dropped]
    C = np.linalg.lstsq(J[:, kept], J[:, dropped], rcond=None)[0] if kept and dropped else np.zeros((len(kept), 0))
    params = model.params
    origins = [i for i in ident.kept if params[i].kind is ParamKind.ORIGIN]
    origin_t = np.array([x[i] for i in origins if params[i].is_translation])
    origin_r = np.array([x[i] for i in origins if params[i].is_rotation])
    scale = {"m": _rms(origin_t), "rad": _rms(origin_r)}
    out: list[ZeroOffset] = []
    for j_index, joint in enumerate(model.chain.joints):
        if joint.kind == "prismatic":
            continue
        index = model.layout.offset(j_index)
        if index not in candidates:
            continue
        value = float(x[index])
        if index in ident.dropped:
            out.append(
                ZeroOffset(
                    joint.name,
                    value,
                    False,
                    math.nan,
                    math.inf,
                    False,
                    (),
                    f"not identified: {ident.dropped[index]}; no encoder correction can be read from this data",
                )
            )
            continue
        row = C[ident.kept.index(index)]
        coefficients = {candidates[dropped[k]]: float(row[k]) for k in range(len(dropped))}
        # The joint's own origin rotation about its axis is the same thing as its zero offset
        # (a link turned on its shaft is fixed by re-zeroing too): it is not a partner.
        own = model.layout.origin_rotation(j_index)
        c3 = np.array([coefficients.get(i, 0.0) for i in own])
        c3 = c3 - (c3 @ joint.axis) * joint.axis
        for axis_index, i in enumerate(own):
            if i in coefficients:
                coefficients[i] = float(c3[axis_index])
        partners = []
        spread2 = 0.0
        for i, c in coefficients.items():
            p = params[i]
            if p.kind is not ParamKind.ORIGIN or abs(c) < _MIN_COEFFICIENT:
                continue
            unit: OriginUnit = "m" if p.is_translation else "rad"
            partners.append(Partner(p.name, c, unit))
            spread2 += (c * scale[unit]) ** 2
        partners.sort(key=lambda q: -abs(q.coefficient) * (1e-3 if q.unit == "m" else math.radians(0.1)))
        s = float(sigma.get(index, math.nan))
        spread = math.sqrt(spread2)
        uncertainty = math.hypot(s, spread)
        physical = math.isfinite(uncertainty) and 2 * uncertainty <= PHYSICAL_LIMIT_RAD
        named = ", ".join(q.describe() for q in partners[:3])
        if physical:
            note = (
                f"±{math.degrees(uncertainty):.2f}° (noise and origin errors of the size found here"
                + (f"; trades against {named}" if partners else "")
                + ")"
            )
        else:
            size = (
                f"±{math.degrees(uncertainty):.1f}°"
                if uncertainty < math.pi
                else "without bound (a nearly degenerate combination)"
            )
            note = (
                f"not a physical encoder zero: the data cannot tell it from {named or 'other parameters'}; "
                f"origin errors of the size found here (RMS {scale['m'] * 1e3:.2f} mm, {math.degrees(scale['rad']):.2f}°) move it {size}. "
                "It is right only together with the origin corrections in calibrated.urdf: do not re-zero the encoder on it"
            )
        out.append(ZeroOffset(joint.name, value, True, s, spread, physical, tuple(partners), note))
    return out
