"""Which combinations of the kinematic parameters the data determine to a stated precision, and
the subspace the fit moves them in.

Why: rank is not precision. The QR analysis (`identify`) drops the parameters that trade exactly
against others, but a combination that is only nearly redundant passes it and is then fitted
with a σ as large as its value: on a real UR5 measured by a laser tracker (one point, so the
flange's orientation is barely observed), `wrist_2_joint`'s origin z came out +53 ± 59 mm and
`tool0` of the calibrated URDF 21 mm and 36° from the nominal arm's, while the measured point was
right to 0.1 mm. A tool 100 mm longer would then be predicted 61 mm off.

How: the noise-weighted identification Jacobian of the parameters QR kept, at the nominal robot.
The measurement frames are always fitted, so a kinematic combination is judged with the frames
free: their columns are projected out (J⊥ = (I − P_frames) J_kinematic, whose inverse Gram matrix
is the kinematic parameters' covariance with the frames fitted along). Each column is scaled by
its parameter's stated precision (`Precision`), and in the SVD J⊥·D = U·S·Vᵀ the combination v_k
has σ_k = 1 / s_k precision units. Those with σ_k ≤ 1 are determined; the others are held at
nominal: the fit moves the kinematic parameters only in span(D·V_determined), frames free (a
truncated SVD in the scaled basis, solved in that basis' coordinates).

Why truncate rather than regularise (a ridge, which shrinks every combination by s²/(s² + λ²)):
the calibrated URDF then changes only along combinations determined to the stated precision,
exactly, and each held one can be named with its σ; a ridge moves every combination a little and
leaves nothing a report can state.

Why 1 mm and 0.1° (`DEFAULT_PRECISION`): fitting a combination costs its σ², holding it at nominal
costs its true error squared, so a combination is worth fitting when it is determined better than
the errors a calibration is for: assembly offsets of 0.5–3 mm and 0.05–0.3° in joint origins. On
the UR5 tracker data the gap is wide (determined combinations σ ≤ 0.08 mm-equivalents at 1000
poses, the next 9 and 108 mm), and on the FR3's camera poses (0.64 mm noise) every combination
that QR keeps is within 0.41 mm: a precision of 0.1 mm and 0.01° would hold 12 of its 22 and cost
held-out accuracy that its cross-validation shows is real (docs/benchmarks.md).
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

    length_m: float = 1e-3
    angle_rad: float = math.radians(0.1)
    gain: float = 1e-3  # 0.1 % of transmission ratio

    def of(self, p: Parameter) -> float:
        """The precision of one parameter, in its unit."""
        return {"m": self.length_m, "rad": self.angle_rad, "1": self.gain}[p.unit]

    def describe(self) -> str:
        return f"{self.length_m * 1e3:g} mm, {math.degrees(self.angle_rad):g}°, gain {self.gain:g}"


DEFAULT_PRECISION = Precision()


@dataclass(frozen=True)
class Held:
    """A combination of kinematic parameters held at nominal: the data determine it to σ precision
    units only (σ > 1). `weights` is its unit vector in precision units, largest first."""

    sigma: float
    weights: tuple[tuple[int, float], ...]  # (parameter index, component)

    def parameter_sigma(self, model: CalibModel, precision: Precision) -> list[tuple[str, float]]:
        """The σ each parameter would have along this combination, in its unit (m, rad, 1), largest first."""
        out = [(model.params[i].name, self.sigma * abs(w) * precision.of(model.params[i])) for i, w in self.weights]
        return out

    def describe(self, model: CalibModel, precision: Precision, terms: int = 3) -> str:
        """'wrist_3_joint.origin.rx ±30.6°, wrist_3_joint.origin.ty ±16.3 mm (σ 355 × the precision)'."""
        parts = []
        for (name, value), (i, _w) in zip(self.parameter_sigma(model, precision)[:terms], self.weights):
            unit = model.params[i].unit
            text = (
                f"±{value * 1e3:.3g} mm"
                if unit == "m"
                else (f"±{math.degrees(value):.3g}°" if unit == "rad" else f"±{value:.3g}")
            )
            parts.append(f"{name} {text}")
        return ", ".join(parts) + f" (σ {self.sigma:.3g} × the precision)"


@dataclass(frozen=True)
class Subspace:
    """What a fit moves: the frame parameters of `free` each on its own, its kinematic parameters
    only along `directions` (unit vectors in precision units): x[kinematic] = nominal + D·V·z."""

    free: list[int]
    kinematic: NDArray[np.bool_]  # (len(free),) which of `free` are kinematic (the others: frames)
    directions: Array  # (kinematic count, d): V, orthonormal columns in precision units
    scale: Array  # (kinematic count,): D, each kinematic parameter's precision in its unit
    held: list[Held] = field(default_factory=list)
    precision: Precision = DEFAULT_PRECISION

    @property
    def dimension(self) -> int:
        """How many coordinates the fit moves: the frame parameters and the determined combinations."""
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
        """x with its kinematic correction from `nominal` projected on the determined combinations
        (orthogonally in precision units); the frames as they are."""
        out: Array = x.copy()
        rows = np.asarray(self.free)[self.kinematic]
        V = self.directions
        scaled = (x[rows] - nominal[rows]) / self.scale
        out[rows] = nominal[rows] + self.scale * (V @ (V.T @ scaled))
        return out


def everything(model: CalibModel, free: list[int], precision: Precision = DEFAULT_PRECISION) -> Subspace:
    """Every parameter of `free` moves on its own (no combination held)."""
    kinematic = np.array([model.params[i].kind is not ParamKind.FRAME for i in free], dtype=bool)
    scale = np.array([precision.of(model.params[i]) for i, k in zip(free, kinematic) if k])
    return Subspace(list(free), kinematic, np.eye(int(kinematic.sum())), scale, [], precision)


def determined(model: CalibModel, J: Array, free: list[int], precision: Precision = DEFAULT_PRECISION) -> Subspace:
    """The combinations of `free`'s kinematic parameters that J (noise-weighted, one column per
    parameter of `free`, at the nominal robot) determines to `precision`, with the frames free."""
    kinematic = np.array([model.params[i].kind is not ParamKind.FRAME for i in free], dtype=bool)
    scale = np.array([precision.of(model.params[i]) for i, k in zip(free, kinematic) if k])
    K = J[:, kinematic]
    F = J[:, ~kinematic]
    if F.shape[1]:
        basis, _ = np.linalg.qr(F)
        K = K - basis @ (basis.T @ K)
    if K.shape[1] == 0:
        return Subspace(list(free), kinematic, np.zeros((0, 0)), scale, [], precision)
    _u, s, Vt = np.linalg.svd(K * scale, full_matrices=False)
    with np.errstate(divide="ignore"):
        sigma = np.where(s > 0, 1.0 / s, math.inf)
    keep = sigma <= 1.0
    rows = np.asarray(free)[kinematic]
    held = []
    for k in np.flatnonzero(~keep):
        v = Vt[k]
        order = np.argsort(-np.abs(v))
        weights = tuple((int(rows[j]), float(v[j])) for j in order if abs(v[j]) >= 0.05)
        held.append(Held(float(sigma[k]), weights))
    held.sort(key=lambda h: h.sigma)
    return Subspace(list(free), kinematic, Vt[keep].T.copy(), scale, held, precision)
