"""Which combinations of the kinematic parameters the data determine, and the subspace the fit
moves them in: the calibrated URDF changes only what the measurements pin down.

Why: rank is not precision. The QR analysis (`identify`) drops the parameters that trade exactly
against others, but a combination that is only nearly redundant passes it and is then fitted
with a σ as large as its value: on a real UR5 measured by a laser tracker (one point, so the
flange's orientation is barely observed), `wrist_2_joint`'s origin z came out +53 ± 59 mm and
`tool0` of the calibrated URDF 21 mm and 36° from the nominal arm's, while the measured point was
right to 0.1 mm. A tool 100 mm longer would then be predicted 61 mm off.

How: the noise-weighted identification Jacobian of the parameters QR kept (QR judges rank at the
nominal robot, where exact redundancies are exact), taken at the fit so far: away from nominal a
redundancy that is exact there becomes a near one, and it is at the fitted robot that its σ is
what the fit will have (a simulated UR5 tracked on its wrist_3 axis: σ 0.7 precision units at
nominal, 2.3 at the fit, whose own σ of wrist_3's origin roll was 0.68°, more than 0.3°).
The measurement frames are always fitted, so a kinematic combination is judged with the frames
free: their columns are projected out (J⊥ = (I − P_frames)·J_kinematic, whose inverse Gram matrix
is the kinematic parameters' covariance with the frames fitted along). Each column is scaled by
its parameter's stated precision (`Precision`), and in the SVD J⊥·D = U·S·Vᵀ the combination v_k
has σ_k = 1 / s_k precision units. Those with σ_k ≤ 1 are determined; the others are held at
nominal: the fit moves the kinematic parameters only in span(D·V_determined), frames free (a
truncated SVD in the scaled basis, solved in its coordinates). Once fitted, `flange_gauge` sets
what changes no measurement, where it turns the flange, nearest the nominal arm's flange. Each held combination is reported
with its σ and its least-squares value from the fit so far, in σ (one Gauss–Newton step along
it, so that a flat valley the fit has not crept along yet still counts).

Why truncate rather than regularise (a ridge, which shrinks every combination by s²/(s² + λ²)):
the calibrated URDF then changes only along the combinations kept, exactly, and each held one can
be named with its σ; a ridge moves every combination a little and leaves nothing a report can
state.

Why 3 mm and 0.3° (`DEFAULT_PRECISION`): fitting a combination costs its σ², holding it at
nominal costs its true error squared, so a combination is worth fitting when it is determined
better than the errors a calibration is for: assembly offsets of 0.5–3 mm and 0.05–0.3° in joint
origins, the largest of them taken so as not to hold a real one. Measured, σ in units of 3 mm
and 0.3°: the UR5 tracker data's held combinations have σ 4.2 and 39 at 1000 poses (11–630 on
50-pose subsets), the determined ones ≤ 0.03, judged at nominal (14 and 134 at the fit, the
same two held, `--params origins,offsets`); on simulated SO-101 tag data (40 poses, 3–6 cm
between axes, seeds 0–3) 1 mm and 0.1° held combinations of σ 0.44–0.68 here and left the URDF
0.34, 0.48, 0.87 and 0.044 mm off, where 3 mm and 0.3° hold none in seeds 0, 1 and 3
(0.022–0.025 mm) and one of σ 1.7 in seed 2 (0.50 mm; 0.46 fitting it); on a simulated UR5 with
the tracked point on the wrist_3 axis (200 poses, seeds 0–3) the two held ones (σ 1.4–2.3) leave
the flange 0.45–0.83° from the truth, against 0.96–1.77° fitting everything and 0.79–1.04° for
the nominal arm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.params import Parameter, ParamKind
from armtool.calib.model.se3 import Array


@dataclass(frozen=True)
class Precision:
    """How well a combination must be determined to be fitted, per parameter unit."""

    length_m: float = 3e-3
    angle_rad: float = math.radians(0.3)
    gain: float = 3e-3  # 0.3 % of transmission ratio

    def of(self, p: Parameter) -> float:
        """The precision of one parameter, in its unit."""
        return {"m": self.length_m, "rad": self.angle_rad, "1": self.gain}[p.unit]

    def describe(self) -> str:
        return f"{self.length_m * 1e3:g} mm and {math.degrees(self.angle_rad):g}°"


DEFAULT_PRECISION = Precision()


@dataclass(frozen=True)
class Combination:
    """A combination of kinematic parameters: its σ and least-squares value in precision units
    along its unit vector `weights` (in precision units, largest components first)."""

    sigma: float
    value: float
    weights: tuple[tuple[int, float], ...]  # (parameter index, component)

    @property
    def significance(self) -> float:
        """|value| / σ: how many σ the data put it from nominal."""
        return abs(self.value) / self.sigma if self.sigma > 0 else math.inf

    def parameter_sigma(self, model: CalibModel, precision: Precision) -> list[tuple[Parameter, float]]:
        """The σ each parameter has along this combination, in its unit (m, rad, 1), largest first."""
        return [(model.params[i], self.sigma * abs(w) * precision.of(model.params[i])) for i, w in self.weights]

    def describe(self, model: CalibModel, precision: Precision, terms: int = 3) -> str:
        """'wrist_3_joint.origin.rx ±30.6°, wrist_3_joint.origin.tx ±16.3 mm, … (σ 118 × the precision, 0.0 σ from nominal)'."""
        parts = []
        for p, value in self.parameter_sigma(model, precision)[:terms]:
            if p.unit == "m":
                parts.append(f"{p.name} ±{value * 1e3:.3g} mm")
            elif p.unit == "rad":
                parts.append(f"{p.name} ±{math.degrees(value):.3g}°")
            else:
                parts.append(f"{p.name} ±{value:.3g}")
        more = ", …" if len(self.weights) > terms else ""
        return (
            ", ".join(parts) + more + f" (σ {self.sigma:.3g} × the precision, {self.significance:.1f} σ from nominal)"
        )


@dataclass(frozen=True)
class Subspace:
    """What a fit moves: the frame parameters of `free` each on its own, its kinematic parameters
    only along `directions` (unit vectors in precision units): x[kinematic] = nominal + D·V·z."""

    free: list[int]
    kinematic: NDArray[np.bool_]  # (len(free),) which of `free` are kinematic (the others: frames)
    directions: Array  # (kinematic count, d): V, orthonormal columns in precision units
    scale: Array  # (kinematic count,): D, each kinematic parameter's precision in its unit
    held: list[Combination] = field(default_factory=list)  # held at nominal
    precision: Precision = DEFAULT_PRECISION

    @property
    def dimension(self) -> int:
        """How many coordinates the fit moves: the frame parameters and the fitted combinations."""
        return int((~self.kinematic).sum()) + int(self.directions.shape[1])

    @property
    def basis(self) -> Array:
        """(len(free), dimension): x[free] = x0[free] + basis · z, frames first."""
        frames = np.flatnonzero(~self.kinematic)
        out = np.zeros((len(self.free), self.dimension))
        out[frames, np.arange(frames.size)] = 1.0
        out[np.flatnonzero(self.kinematic), frames.size :] = self.scale[:, None] * self.directions
        return out

    def project(self, x: Array, nominal: Array) -> Array:
        """x with its kinematic correction from `nominal` projected on the fitted combinations
        (orthogonally in precision units); the frames as they are."""
        out: Array = x.copy()
        rows = np.asarray(self.free)[self.kinematic]
        V = self.directions
        scaled = (x[rows] - nominal[rows]) / self.scale
        out[rows] = nominal[rows] + self.scale * (V @ (V.T @ scaled))
        return out


def determined(
    model: CalibModel,
    J: Array,
    free: list[int],
    precision: Precision = DEFAULT_PRECISION,
    residuals: Array | None = None,
    correction: Array | None = None,
) -> Subspace:
    """The combinations of `free`'s kinematic parameters to fit, from J (noise-weighted, one column
    per parameter of `free`, at the fit so far), with the frames free: those with σ ≤ 1
    precision unit. `residuals` (noise-weighted, J's rows) and `correction` (x − nominal over
    `free`) are the fit so far: they give each held combination's value, for the report."""
    kinematic = np.array([model.params[i].kind is not ParamKind.FRAME for i in free], dtype=bool)
    scale = np.array([precision.of(model.params[i]) for i, k in zip(free, kinematic) if k])
    K, F = J[:, kinematic], J[:, ~kinematic]
    r = np.zeros(J.shape[0]) if residuals is None else residuals
    if F.shape[1]:
        Q, _ = np.linalg.qr(F)
        K = K - Q @ (Q.T @ K)
        r = r - Q @ (Q.T @ r)
    if K.shape[1] == 0:
        return Subspace(list(free), kinematic, np.zeros((0, 0)), scale, [], precision)
    U, s, Vt = np.linalg.svd(K * scale, full_matrices=False)
    with np.errstate(divide="ignore"):
        sigma = np.where(s > 0, 1.0 / s, math.inf)
    now = np.zeros(len(s)) if correction is None else Vt @ (correction[kinematic] / scale)
    value = now - (U.T @ r) * sigma  # one Gauss–Newton step along each combination
    keep = sigma <= 1.0
    rows = np.asarray(free)[kinematic]

    def combination(k: int) -> Combination:
        order = np.argsort(-np.abs(Vt[k]))
        weights = tuple((int(rows[j]), float(Vt[k, j])) for j in order if abs(Vt[k, j]) >= 0.05)
        return Combination(float(sigma[k]), float(value[k]), weights)

    held = sorted((combination(int(k)) for k in np.flatnonzero(~keep)), key=lambda c: c.sigma)
    return Subspace(list(free), kinematic, Vt[keep].T.copy(), scale, held, precision)
