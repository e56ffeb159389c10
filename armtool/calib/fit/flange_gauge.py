"""Where the measurements cannot see the flange, the flange nearest the nominal arm's.

Why: one tracked point (a laser tracker's reflector, a mocap marker) has no orientation, so the
flange's turn about it changes no measurement. Several joint parameters can turn it so (a last
origin rotation with the zero offset about the same axis, two wrist origins together), and which
of them QR keeps (`identify`, a fixed priority order) and which it holds at nominal is a choice
the data do not make: on the real UR5 tracker grid (1000 poses) that choice left tool0 0.705°
from the nominal arm's on average, where an equally good URDF has it 0.339° away. A tool the data
never saw is predicted from the flange, so what the data cannot see should stay nominal at the
flange (issue 28: "point data leaves the flange orientation nominal").

How: over every origin component and zero offset of the fitted set (the first joint's origin,
the base's placement, excepted) and the registration's components, the noise-weighted measurement
Jacobian, each column scaled by its precision (`Precision`); its combinations with σ above one
precision unit change no measurement by more than the noise. Along them Gauss–Newton steps
minimise the flange's mean squared distance from the nominal arm's over the fit's poses (position
in units of the length precision, orientation of the angle precision), with a small ridge so that
a direction that barely moves the flange is not taken far. A step is kept only while the fit's χ²
rises by at most 1 (one standard deviation), halved otherwise.

Why the registration follows: the frame fixed to the base (the tracker, or the camera of
eye-to-hand; the target of eye-in-hand) places the whole arm in the measurements' frame, and no
measurement sees where the arm sits on its base_link. Held as fitted, it left the UR5's tool0
1.87 mm from the nominal arm's on average, most of it the whole arm shifted against base_link;
following, 0.90 mm (benchmarks/calib_real.py prints the gauge's before and after).

Why the carried frame stays: a change of the flange that the frame on it can absorb (a camera or
a board turned with it, the reflector moved with it) is a choice between the robot and the mount,
and the mount is what hand-eye calibration is for. Letting the camera follow put the real FR3's
camera 3.4 mm from its mount drawing's height, against 0.1 mm as fitted. So 6-D measurements
(poses, tags, boards), which see the flange's turn about the target, leave it as it was fitted.

What it cannot do: the flange pose the data do determine stays. On the UR5 grid the points pin
tool0's tilt through the reflector's 34 mm lever: the nearest URDF still has it 0.82° and 2.2 mm
from nominal at the worst pose (benchmarks/calib_flange_bound.py finds the same with scipy).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from armtool.calib.fit.determined import Precision
from armtool.calib.fit.problems import Problem
from armtool.calib.model import se3
from armtool.calib.model.params import ParamKind
from armtool.calib.model.se3 import Array

_STEPS = 4  # Gauss–Newton steps at most (on the UR5 grid two settle it)
_HALVINGS = 6
_RIDGE = 1e-3  # per precision unit squared, against the mean squared flange distance
_CHI2_RISE = 1.0  # how much worse the fit may get: one standard deviation
_SETTLED = 1e-4  # a step that lowers the flange objective by less than this share ends the descent


@dataclass(frozen=True)
class FlangeDeviation:
    """The flange from the nominal arm's over a set of poses."""

    max_mm: float
    mean_mm: float
    max_deg: float
    mean_deg: float

    def describe(self) -> str:
        return f"{self.mean_mm:.2f} mm and {self.mean_deg:.3f}° on average, at most {self.max_mm:.2f} mm and {self.max_deg:.3f}°"


@dataclass(frozen=True)
class FlangeGauge:
    """What choosing the flange nearest nominal did: the flange before and after, over the fit's
    poses, how many combinations it chose along, and how much the fit's χ² changed."""

    before: FlangeDeviation
    after: FlangeDeviation
    directions: int
    chi2_change: float

    @property
    def moved(self) -> bool:
        return self.after.mean_deg < self.before.mean_deg or self.after.mean_mm < self.before.mean_mm


def flange_deviation(problem: Problem, x: Array) -> FlangeDeviation:
    """The flange of `x` against the nominal robot's at every pose of `problem`."""
    return _FlangeError.of(problem, Precision(length_m=1e-3, angle_rad=math.radians(1.0))).deviation(x)


@dataclass(frozen=True)
class _FlangeError:
    """The flange against the nominal robot's at every pose of `problem`, in precision units; the
    nominal flange computed once (each evaluation is a chain build over every pose)."""

    problem: Problem
    precision: Precision
    nominal: Array  # (N, 4, 4) the nominal robot's flange at the problem's poses

    @classmethod
    def of(cls, problem: Problem, precision: Precision) -> _FlangeError:
        return cls(problem, precision, problem.model.flange(np.zeros(problem.model.size), problem.Q))

    def of_flange(self, F: Array) -> Array:
        """(poses·6,) the position and rotation of the flanges F from the nominal ones."""
        position = (F[:, :3, 3] - self.nominal[:, :3, 3]) / self.precision.length_m
        turn = np.swapaxes(self.nominal[:, :3, :3], -1, -2) @ F[:, :3, :3]
        out: Array = np.concatenate([position, se3.log3_batch(turn) / self.precision.angle_rad], axis=1).ravel()
        return out

    def at(self, x: Array) -> Array:
        return self.of_flange(self.problem.model.flange(x, self.problem.Q))

    def objective(self, x: Array) -> float:
        """The mean squared flange error per pose."""
        e = self.at(x)
        return float(e @ e) / max(self.problem.samples, 1)

    def deviation(self, x: Array) -> FlangeDeviation:
        """In the units of `precision` (mm and ° for `flange_deviation`)."""
        error = self.at(x).reshape(-1, 6)
        distance, angle = np.linalg.norm(error[:, :3], axis=1), np.linalg.norm(error[:, 3:], axis=1)
        return FlangeDeviation(float(distance.max()), float(distance.mean()), float(angle.max()), float(angle.mean()))

    def jacobian(self, x: Array, indices: list[int]) -> tuple[Array, Array]:
        """The error (`at`) and its Jacobian (poses·6, len(indices)), from the flange's left twists:
        a twist (v, ω) moves the flange's origin p by v + ω × p and turns its rotation R into
        exp(ω)·R, which turns the rotation error φ = log(R_nomᵀ R) by J_r⁻¹(φ)·Rᵀω."""
        F, twists = self.problem.model.flange_twists(x, self.problem.Q, indices)  # (N, 4, 4), (N, 6, P)
        e = self.of_flange(F)
        phi = e.reshape(-1, 6)[:, 3:] * self.precision.angle_rad
        v, w = twists[:, :3], twists[:, 3:]
        p, R = F[:, :3, 3], F[:, :3, :3]
        position = v + np.cross(w, p[:, :, None], axis=1)
        rotation = _inverse_right_jacobian(phi) @ np.swapaxes(R, -1, -2) @ w
        out = np.concatenate([position / self.precision.length_m, rotation / self.precision.angle_rad], axis=1)
        return e, out.reshape(-1, len(indices))


def nearest_nominal_flange(
    problem: Problem, x: Array, candidates: Sequence[int], precision: Precision
) -> tuple[Array, FlangeGauge]:
    """`x` moved, along the combinations of `candidates`' origins and zero offsets that change no
    measurement of `problem` (its inliers, noise-weighted) by more than the noise, the
    registration following and the carried frame as it is, to where the flange is nearest the
    nominal arm's; the measurements as before
    (χ² within 1)."""
    model = problem.model
    base = set(model.layout.origin(0))
    kinematic = [
        i for i in candidates if model.params[i].kind in (ParamKind.ORIGIN, ParamKind.OFFSET) and i not in base
    ]
    registration = set(model.base_side_frame())
    following = [i for i in candidates if i in registration]
    before = flange_deviation(problem, x)
    if not kinematic or problem.samples == 0:
        return x, FlangeGauge(before, before, 0, 0.0)
    error = _FlangeError.of(problem, precision)
    scale = np.array([precision.of(model.params[i]) for i in kinematic])
    chi2_start = _chi2(problem, x)
    out, directions = x.copy(), 0
    start = now = error.objective(out)
    for _step in range(_STEPS):
        step, count = _step_along_free(problem, error, out, kinematic, following, scale, precision)
        directions = max(directions, count)
        if step is None:
            break
        for _halving in range(_HALVINGS):
            trial = out + step
            better = error.objective(trial)
            if better < now and _chi2(problem, trial) - chi2_start <= _CHI2_RISE:
                break
            step = step / 2
        else:
            break
        settled = better > now * (1.0 - _SETTLED)
        out, now = trial, better
        if settled:
            break
    if now >= start:
        return x, FlangeGauge(before, before, directions, 0.0)
    return out, FlangeGauge(before, flange_deviation(problem, out), directions, _chi2(problem, out) - chi2_start)


def _step_along_free(
    problem: Problem,
    error: _FlangeError,
    x: Array,
    kinematic: list[int],
    following: list[int],
    scale: Array,
    precision: Precision,
) -> tuple[Array | None, int]:
    """One Gauss–Newton step of the flange objective along the combinations of `kinematic` that
    change no measurement by more than the noise, the `following` frame components free to follow
    and the other frame as it is (σ above one precision unit), as a full parameter step; None when
    there are none."""
    moved = kinematic + following
    full_scale = np.concatenate([scale, [precision.of(problem.model.params[i]) for i in following]])
    K = problem.jacobian(x, moved)
    # Vt square; with fewer measurements than parameters the rest have s = 0 (then K is small)
    _, s, Vt = np.linalg.svd(K * full_scale, full_matrices=K.shape[0] < K.shape[1])
    s = np.concatenate([s, np.zeros(len(moved) - s.size)])
    free = Vt[s < 1.0].T
    # the flange does not depend on the frames: only the joints' part of a combination moves it
    joints = free[: len(kinematic)]
    if free.shape[1] == 0 or not np.any(np.abs(joints) > 1e-12):
        return None, 0
    e, E = error.jacobian(x, kinematic)
    poses = problem.samples
    A = (E @ (scale[:, None] * joints)) / math.sqrt(poses)
    b = e / math.sqrt(poses)
    z = np.linalg.solve(A.T @ A + _RIDGE * np.eye(A.shape[1]), -A.T @ b)
    step = np.zeros_like(x)
    step[moved] = full_scale * (free @ z)
    return step, int(free.shape[1])


def _inverse_right_jacobian(phi: Array) -> Array:
    """J_r⁻¹(φ) of SO(3) for each row of phi (N, 3): I + ½φ̂ + (1/θ² − (1 + cos θ)/(2θ sin θ)) φ̂²."""
    theta = np.linalg.norm(phi, axis=1)
    K = np.zeros((len(phi), 3, 3))
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -phi[:, 2], phi[:, 1], -phi[:, 0]
    K[:, 1, 0], K[:, 2, 0], K[:, 2, 1] = phi[:, 2], -phi[:, 1], phi[:, 0]
    small = theta < 1e-4
    t = np.where(small, 1.0, theta)
    c = np.where(small, 1.0 / 12.0, 1.0 / t**2 - (1.0 + np.cos(t)) / (2.0 * t * np.sin(t)))
    out: Array = np.eye(3) + 0.5 * K + c[:, None, None] * (K @ K)
    return out


def _chi2(problem: Problem, x: Array) -> float:
    r = problem.residuals(x)
    return float(r @ r)
