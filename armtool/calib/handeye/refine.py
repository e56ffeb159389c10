"""The joint refinement: both hand-eye frames (and, optionally, the intrinsics) by the corners' reprojection error.

The closed forms fit motions, not what the camera saw. This fit minimises the pixel distance
between each detected corner and where the frames predict it, π(C_i p_k) with
C_i = X⁻¹ G_i⁻¹ Z (`armtool.calib.handeye.views`), over every corner of every image, weighted by
how the corners really err:

* Two noises. A corner errs by the detector's noise (σ_px, each coordinate alone), and a whole
  image errs together by the controller's error on its flange pose (σ_t per axis, σ_r per axis of
  rotation: a robot's pose is off by tenths of a millimetre to millimetres, which moves every
  corner of the image alike). Plain least squares on the pixels takes the second for the first:
  it fits its own images better than the true frames do, and predicts held-out images 5-7 % worse
  than the best closed form when the flange errors matter (benchmarks/handeye_bench.py: 0.3 mm and
  0.03°, or 1 mm and 0.1°, per axis). So each image's residuals are whitened by their covariance
  σ_px² I + J_δ S J_δᵀ, with J_δ the corners' derivative by that image's flange pose error and
  S = diag(σ_t² I, σ_r² I) (generalised least squares; Woodbury's identity makes the 2P × 2P
  whitening a rank-6 correction per image). With σ_t = σ_r = 0 it is plain least squares.
* The noises are estimated from the data: first (`estimate_noise`) σ_px from each image's own IPPE
  fit (corner noise alone), σ_t and σ_r from the images' flange pose errors against the start;
  then, after each of ROUNDS rounds, all three by maximum likelihood (`fit_noise`).
* Parameters: corrections of X and Z on the right, X₀ · SE3(exp(r), t) (`se3.delta`), and with
  `intrinsics` fx, fy, cx, cy and every distortion coefficient the intrinsics file has (its
  distortion model, as it gives it).
* Jacobian: analytic. OpenCV's `projectPoints` gives each pixel's derivative by the camera-frame
  point and by the intrinsics; a correction of X moves the point by −(v + ω × q), one of Z by
  R_C (v + ω × p); the right Jacobian of SO(3) maps the parameters onto those twists.
* Robust: SciPy's `least_squares` with a soft-L1 loss, knee at KNEE σ of the whitened residuals.
  Before each round, images that stand out (above max(OUTLIER_FACTOR × the median, the median +
  OUTLIER_MADS × 1.4826 × MAD) of all images) are left out, and named: by their flange pose error
  against the frames in its expected spread (`outlier_images`: a pose row that belongs to another
  image, a board turned the wrong way) or by their own IPPE fit (a bad detection).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from armtool.calib.choices import Setup
from armtool.calib.fit.handeye import skews
from armtool.calib.handeye.views import Observations
from armtool.calib.model import se3
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError

KNEE = 3.0  # the robust loss's knee, in σ of the whitened residuals
LOSS = "soft_l1"
ROUNDS = 3
OUTLIER_FACTOR = 3.0
OUTLIER_MADS = 8.0
MIN_IMAGES = 3  # fewer cannot determine two frames
BEHIND_PX = 1e4  # the residual of a corner the frames put behind the camera
CHI2_3_MEDIAN = 2.3660  # median of a χ² with 3 degrees of freedom
MIN_PIXEL_PX = 0.01


@dataclass(frozen=True)
class Noise:
    """How the corners err: the detector per coordinate, the controller per flange pose axis."""

    pixel_px: float
    position_m: float
    rotation_rad: float


@dataclass(frozen=True)
class Refined:
    """The refined frames and camera, how well they explain each image, and their uncertainty."""

    X: Array
    Z: Array
    camera: CameraModel
    rms_px: float  # over every corner of the images kept
    image_rms_px: Array  # (N,) each image's RMS at the solution, outliers too
    outliers: NDArray[np.intp]  # images left out of the last round
    noise: Noise
    sigma_X: tuple[Array, Array]  # 1σ of X's position (m, along X's own axes) and rotation (rad)
    sigma_Z: tuple[Array, Array]
    sigma_intrinsics: Array  # 1σ of fx, fy, cx, cy, distortion (px, coefficient), empty when held fixed


class Reprojection:
    """The residuals (predicted − detected pixel, per coordinate), their Jacobian by the parameters,
    and with `whiten` set each image's residuals whitened by their covariance (module docstring)."""

    def __init__(self, obs: Observations, X0: Array, Z0: Array, camera: CameraModel, intrinsics: bool) -> None:
        self.obs, self.X0, self.Z0, self.camera0 = obs, X0, Z0, camera
        self.intrinsics = intrinsics
        K = camera.K
        self.x0 = np.zeros(12)
        if intrinsics:
            self.x0 = np.concatenate([self.x0, [K[0, 0], K[1, 1], K[0, 2], K[1, 2]], camera.dist])
        self._last: tuple[bytes, Array, Array, Array, NDArray[np.bool_], Array] | None = None
        self._weights: list[tuple[NDArray[np.intp], Array, Array]] | None = None
        self._scale = 1.0

    def unpack(self, x: Array) -> tuple[Array, Array, CameraModel]:
        X, Z = self.X0 @ se3.delta(x[:6]), self.Z0 @ se3.delta(x[6:12])
        if not self.intrinsics:
            return X, Z, self.camera0
        K = np.array(self.camera0.K)
        K[0, 0], K[1, 1], K[0, 2], K[1, 2] = x[12:16]
        cam = self.camera0
        return X, Z, CameraModel(K, x[16:], cam.width, cam.height)

    def _project(self, x: Array) -> tuple[Array, Array, Array, NDArray[np.bool_], Array]:
        """(camera-frame points (M, 3), pixels (M, 2), OpenCV's Jacobian (M, 2, k), in front (M,), C (N, 4, 4))."""
        import cv2

        key = x.tobytes()
        if self._last is not None and self._last[0] == key:
            return self._last[1:]
        X, Z, cam = self.unpack(x)
        C = se3.inv(X) @ se3.inv(self.obs.G) @ Z
        Ci = C[self.obs.image]
        q = np.einsum("mij,mj->mi", Ci[:, :3, :3], self.obs.points) + Ci[:, :3, 3]
        front = q[:, 2] > 1e-6
        px, J = cv2.projectPoints(q.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), cam.K, cam.dist)
        out = (
            q,
            np.asarray(px, dtype=np.float64).reshape(-1, 2),
            np.asarray(J, dtype=np.float64).reshape(len(q), 2, -1),
            front,
            C,
        )
        self._last = (key, *out)
        return out

    def pixel_residuals(self, x: Array) -> Array:
        """Predicted − detected pixels (M, 2); BEHIND_PX where a corner is behind the camera."""
        _q, px, _J, front, _C = self._project(x)
        r = px - self.obs.pixels
        r[~front] = BEHIND_PX
        return r

    def residuals(self, x: Array) -> Array:
        return self._whitened(self.pixel_residuals(x).reshape(-1, 1))[:, 0]

    def jacobian(self, x: Array) -> Array:
        q, _px, J, front, C = self._project(x)
        Rc = C[self.obs.image, :3, :3]
        dq = J[:, :, 3:6]  # d pixel / d camera-frame point (OpenCV's d/d tvec)
        # X · (v, ω): q → q − (v + ω × q);  Z · (v, ω): q → q + R_C (v + ω × p).
        cols = [
            -dq @ se3.exp3(x[3:6]).T,
            dq @ skews(q) @ right_jacobian(x[3:6]),
            dq @ Rc @ se3.exp3(x[9:12]).T,
            -(dq @ Rc) @ skews(self.obs.points) @ right_jacobian(x[9:12]),
        ]
        if self.intrinsics:
            cols.append(J[:, :, 6 : 10 + len(self.camera0.dist)])
        out: Array = np.concatenate(cols, axis=2)
        out[~front] = 0.0
        return self._whitened(out.reshape(2 * len(q), -1))

    def flange_jacobian(self, x: Array) -> Array:
        """(M, 2, 6): each corner's derivative by its image's flange pose error (v, ω), on the
        flange's right (the reported pose F = F_true · SE3(exp(ω), v))."""
        q, _px, J, _front, C = self._project(x)
        X, Z, _cam = self.unpack(x)
        dq = J[:, :, 3:6]
        if self.obs.setup is Setup.EYE_IN_HAND:  # C_true = (X⁻¹ Δ⁻¹ X) C: a twist −Ad(X⁻¹)·δ on C's left
            twist = dq @ np.concatenate([np.broadcast_to(np.eye(3), q.shape + (3,)), -skews(q)], axis=2)
            out: Array = -twist @ adjoint(se3.inv(X))
            return out
        # eye-to-hand: C_true = C (Z⁻¹ Δ Z): a twist Ad(Z⁻¹)·δ on C's right
        Rc = C[self.obs.image, :3, :3]
        p = self.obs.points
        twist = (dq @ Rc) @ np.concatenate([np.broadcast_to(np.eye(3), p.shape + (3,)), -skews(p)], axis=2)
        right: Array = twist @ adjoint(se3.inv(Z))
        return right

    def whiten(self, x: Array, noise: Noise) -> None:
        """Whiten each image's residuals by σ_px² I + J_δ S J_δᵀ at x (held until the next call)."""
        Jd = self.flange_jacobian(x) * np.array([noise.position_m] * 3 + [noise.rotation_rad] * 3)
        weights = []
        for i in range(self.obs.count):
            rows = np.flatnonzero(self.obs.image == i)
            rows = np.stack([2 * rows, 2 * rows + 1], axis=1).reshape(-1)
            Q, R = np.linalg.qr(Jd[self.obs.image == i].reshape(-1, 6))
            s2 = noise.pixel_px**2
            B = np.eye(R.shape[0]) - R @ np.linalg.solve(s2 * np.eye(6) + R.T @ R, R.T)
            L = np.linalg.cholesky(B + 1e-15 * np.eye(len(B)))
            weights.append((rows, Q, L.T - np.eye(len(B))))
        self._weights, self._scale = weights, noise.pixel_px

    def _whitened(self, M: Array) -> Array:
        """W M for residuals or Jacobian rows M (2M, k): per image (1/σ)(M + Q (Lᵀ − I) Qᵀ M)."""
        if self._weights is None:
            return M
        out = M.copy()
        for rows, Q, correction in self._weights:
            block = M[rows]
            out[rows] = block + Q @ (correction @ (Q.T @ block))
        scaled: Array = out / self._scale
        return scaled


def adjoint(T: Array) -> Array:
    """Ad_T for twists (v, ω): T exp(ξ) T⁻¹ = exp(Ad_T ξ)."""
    R, t = T[:3, :3], T[:3, 3]
    out = np.zeros((6, 6))
    out[:3, :3], out[:3, 3:], out[3:, 3:] = R, se3.skew(t) @ R, R
    return out


def right_jacobian(r: Array) -> Array:
    """J_r(r) with exp3(r + δ) = exp3(r) · exp3(J_r(r) δ) to first order."""
    theta = float(np.linalg.norm(r))
    K = se3.skew(r)
    if theta < 1e-6:
        return np.eye(3) - 0.5 * K + (K @ K) / 6.0
    out: Array = np.eye(3) - (1.0 - math.cos(theta)) / theta**2 * K + (theta - math.sin(theta)) / theta**3 * (K @ K)
    return out


def image_rms(residuals: Array, image: NDArray[np.intp], count: int) -> Array:
    """Each image's reprojection RMS (px) from per-corner residuals (M, 2); NaN for an image without corners."""
    sq = np.bincount(image, weights=np.sum(residuals**2, axis=1), minlength=count)
    n = np.bincount(image, minlength=count)
    with np.errstate(invalid="ignore", divide="ignore"):
        out: Array = np.sqrt(sq / n)
    return out


def stands_out(score: Array) -> NDArray[np.intp]:
    """The entries of `score` (one per image) that stand out from the others' (module docstring)."""
    finite = np.isfinite(score)
    if finite.sum() < 2:
        return np.zeros(0, dtype=np.intp)
    median = float(np.median(score[finite]))
    mad = 1.4826 * float(np.median(np.abs(score[finite] - median)))
    limit = max(OUTLIER_FACTOR * median, median + OUTLIER_MADS * mad)
    return np.flatnonzero(~(score <= limit))


def outlier_images(problem: Reprojection, x: Array, noise: Noise) -> NDArray[np.intp]:
    """The images whose own IPPE fit stands out (a bad detection), or whose flange pose error
    against the frames does (a pose row of another image, a board turned the wrong way), measured
    in its expected spread: e_iᵀ (S + σ_px² (J_δᵀ J_δ)⁻¹)⁻¹ e_i, the controller's noise plus what the
    image's own corners leave uncertain (a far, tilted board's depth is off by millimetres)."""
    obs = problem.obs
    X, Z, _cam = problem.unpack(x)
    errors = obs.flange_errors(X, Z)
    Jd = problem.flange_jacobian(x)
    JtJ = np.zeros((obs.count, 6, 6))
    np.add.at(JtJ, obs.image, np.einsum("mki,mkj->mij", Jd, Jd))
    S = np.diag([noise.position_m**2] * 3 + [noise.rotation_rad**2] * 3)
    expected = S + noise.pixel_px**2 * np.linalg.pinv(JtJ)
    distance = np.sqrt(np.einsum("ni,ni->n", errors, np.linalg.solve(expected, errors[..., None])[..., 0]))
    return np.union1d(stands_out(distance), stands_out(obs.pnp_rms_px))


def estimate_noise(obs: Observations, X: Array, Z: Array) -> Noise:
    """σ_px from each image's own IPPE fit (6 pose parameters per image removed), σ_t and σ_r from the
    images' flange pose errors against the frames (medians, robust to a few bad images)."""
    errors = obs.flange_errors(X, Z)
    position = math.sqrt(float(np.median(np.sum(errors[:, :3] ** 2, axis=1))) / CHI2_3_MEDIAN)
    rotation = math.sqrt(float(np.median(np.sum(errors[:, 3:] ** 2, axis=1))) / CHI2_3_MEDIAN)
    return Noise(max(obs.pixel_noise_px, MIN_PIXEL_PX), position, rotation)


def fit_noise(problem: Reprojection, x: Array, start: Noise) -> Noise:
    """The noises (σ_px, σ_t, σ_r) that make the residuals at x most likely under the model's
    per-image covariance σ_px² I + J_δ S J_δᵀ (a Gaussian likelihood over the kept images, maximised
    over the logarithms of the three from `start`). Why not the flange errors against the IPPE poses
    alone (`estimate_noise`): those carry IPPE's own depth error, which at 0.5-1 m made σ_t 0.19 mm
    where the flange poses were exact to 0.01 mm, and the fit then trusted the images too little."""
    from scipy.optimize import minimize

    r = problem.pixel_residuals(x)
    Jd = problem.flange_jacobian(x)
    image, count = problem.obs.image, problem.obs.count
    n = 2.0 * np.bincount(image, minlength=count)
    rr = np.bincount(image, weights=np.sum(r * r, axis=1), minlength=count)
    JtJ = np.zeros((count, 6, 6))
    np.add.at(JtJ, image, np.einsum("mki,mkj->mij", Jd, Jd))
    Jtr = np.zeros((count, 6))
    np.add.at(Jtr, image, np.einsum("mki,mk->mi", Jd, r))

    def cost(log_sigma: Array) -> float:
        s, t, w = np.exp(log_sigma)
        D = np.array([t, t, t, w, w, w])
        A = D[None, :, None] * JtJ * D[None, None, :]
        b = D[None, :] * Jtr
        M = s * s * np.eye(6) + A
        quad = (rr - np.einsum("ni,ni->n", b, np.linalg.solve(M, b[..., None])[..., 0])) / (s * s)
        logdet = n * math.log(s * s) + np.linalg.slogdet(np.eye(6) + A / (s * s))[1]
        return float(np.sum(quad + logdet))

    guess = np.log([start.pixel_px, max(start.position_m, 1e-6), max(start.rotation_rad, 1e-7)])
    found = minimize(cost, guess, method="Nelder-Mead", options={"xatol": 0.02, "fatol": 1e-3, "maxiter": 300})
    s, t, w = np.exp(found.x)
    return Noise(max(float(s), MIN_PIXEL_PX), float(t), float(w))


def refine(
    obs: Observations,
    X0: Array,
    Z0: Array,
    camera: CameraModel,
    *,
    intrinsics: bool = False,
    max_nfev: int | None = None,
    rounds: int = ROUNDS,
    fit_noises: bool = True,
) -> Refined:
    """Both frames (and with `intrinsics` the camera) refined from the start (X0, Z0), robustly
    (`fit_noises` False: the noises stay the first estimate, which is faster and good enough to
    tell a right convention from a wrong one)."""
    from scipy.optimize import least_squares

    if obs.count < MIN_IMAGES:
        raise ArmtoolError(f"{obs.count} usable images cannot determine the two frames", hint="take 15-40 images")
    full = Reprojection(obs, X0, Z0, camera, intrinsics)
    x = full.x0
    noise = estimate_noise(obs, X0, Z0)
    outliers = _outliers(full, x, noise)
    for round_ in range(rounds):
        kept = np.setdiff1d(np.arange(obs.count), outliers)
        problem = Reprojection(obs.subset(kept), X0, Z0, camera, intrinsics)
        problem.whiten(x, noise)
        x = least_squares(
            problem.residuals, x, jac=problem.jacobian, loss=LOSS, f_scale=KNEE, x_scale="jac", max_nfev=max_nfev
        ).x
        if fit_noises:
            noise = fit_noise(problem, x, noise)
        if round_ < rounds - 1:
            outliers = _outliers(full, x, noise)
    problem = Reprojection(obs.subset(kept), X0, Z0, camera, intrinsics)
    problem.whiten(x, noise)
    X, Z, cam = problem.unpack(x)
    pixels = problem.pixel_residuals(x)
    all_rms = image_rms(full.pixel_residuals(x), obs.image, obs.count)
    rms = float(np.sqrt(np.mean(np.sum(pixels**2, axis=1))))
    return Refined(X, Z, cam, rms, all_rms, outliers, noise, *_uncertainty(problem, x))


def _outliers(problem: Reprojection, x: Array, noise: Noise) -> NDArray[np.intp]:
    found = outlier_images(problem, x, noise)
    return found if problem.obs.count - len(found) >= MIN_IMAGES else np.zeros(0, dtype=np.intp)


def _uncertainty(problem: Reprojection, x: Array) -> tuple[tuple[Array, Array], tuple[Array, Array], Array]:
    """1σ of the parameters from the Gauss–Newton covariance (JᵀJ)⁻¹ of the whitened residuals,
    scaled by their mean square when it is above 1 (the noises explain them less well than assumed)."""
    J, r = problem.jacobian(x), problem.residuals(x)
    dof = max(len(r) - J.shape[1], 1)
    try:
        cov = max(float(r @ r) / dof, 1.0) * np.linalg.inv(J.T @ J)
    except np.linalg.LinAlgError:
        cov = np.full((J.shape[1], J.shape[1]), np.inf)
    s = np.sqrt(np.abs(np.diag(cov)))
    return (s[0:3], s[3:6]), (s[6:9], s[9:12]), s[12:]


def reprojection_residuals(obs: Observations, X: Array, Z: Array, camera: CameraModel) -> Array:
    """Predicted − detected pixels (M, 2) of every corner; NaN where the frames put it behind the camera."""
    problem = Reprojection(obs, X, Z, camera, False)
    _q, px, _J, front, _C = problem._project(problem.x0)
    out: Array = px - obs.pixels
    out[~front] = np.nan
    return out
