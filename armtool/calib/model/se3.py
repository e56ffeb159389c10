"""Rigid transforms as 4×4 matrices, and the exponential map used for every small correction.

Corrections compose on the right, `T · SE3(exp(r), t)`, as FIGAROH and robot_calibration do:
adding to rpy angles is wrong away from zero. Vectorised over a leading axis where useful.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def skew(v: Array) -> Array:
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def exp3(r: Array) -> Array:
    """Rotation matrix of the rotation vector r (axis · angle, rad)."""
    angle = math.sqrt(float(r @ r))
    K = skew(r)
    if angle < 1e-8:
        return np.eye(3) + K + 0.5 * (K @ K)
    return np.eye(3) + (math.sin(angle) / angle) * K + ((1.0 - math.cos(angle)) / angle**2) * (K @ K)


def log3(R: Array) -> Array:
    """Rotation vector of a rotation matrix (inverse of exp3), stable near 0 and π."""
    cos = max(-1.0, min(1.0, (float(np.trace(R)) - 1.0) / 2.0))
    angle = math.acos(cos)
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    if angle < 1e-6:
        return 0.5 * w
    if math.pi - angle < 1e-4:  # near π: take the axis from the symmetric part
        B = 0.5 * (R + np.eye(3))
        axis = np.sqrt(np.clip(np.diag(B), 0.0, None))
        i = int(np.argmax(axis))
        axis[(i + 1) % 3] = math.copysign(axis[(i + 1) % 3], B[i, (i + 1) % 3]) if axis[i] else 0.0
        axis[(i + 2) % 3] = math.copysign(axis[(i + 2) % 3], B[i, (i + 2) % 3]) if axis[i] else 0.0
        axis /= np.linalg.norm(axis)
        if float(axis @ w) < 0:
            axis = -axis
        return angle * axis
    return (angle / (2.0 * math.sin(angle))) * w


def exp3_batch(r: Array) -> Array:
    """`exp3` of many rotation vectors r (..., 3): (..., 3, 3). Why: the fit's Jacobian evaluates
    the model for every perturbed parameter at once, and a Python loop over them was most of its time."""
    angle = np.sqrt(np.einsum("...i,...i->...", r, r))
    small = angle < 1e-8
    safe = np.where(small, 1.0, angle)
    a = np.where(small, 1.0, np.sin(safe) / safe)[..., None, None]
    b = np.where(small, 0.5, (1.0 - np.cos(safe)) / safe**2)[..., None, None]
    K = np.zeros((*r.shape[:-1], 3, 3))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -r[..., 2], r[..., 1], -r[..., 0]
    K[..., 1, 0], K[..., 2, 0], K[..., 2, 1] = r[..., 2], -r[..., 1], r[..., 0]
    out: Array = np.eye(3) + a * K + b * (K @ K)
    return out


def log3_batch(R: Array) -> Array:
    """`log3` of many rotation matrices (..., 3, 3): (..., 3); the same branches, vectorised."""
    cos = np.clip((np.trace(R, axis1=-2, axis2=-1) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(cos)
    w = np.stack([R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]], axis=-1)
    sin = np.sin(angle)
    factor = np.where(angle < 1e-6, 0.5, angle / (2.0 * np.where(sin > 1e-12, sin, 1.0)))
    out: Array = factor[..., None] * w
    near_pi = math.pi - angle < 1e-4
    if np.any(near_pi):
        flat_R, flat_out = R.reshape(-1, 3, 3), out.reshape(-1, 3)
        for k in np.flatnonzero(near_pi.ravel()):
            flat_out[k] = log3(flat_R[k])
        out = flat_out.reshape(out.shape)
    return out


def delta_batch(v: Array) -> Array:
    """`delta` of many corrections v (..., 6): (..., 4, 4)."""
    out = np.zeros((*v.shape[:-1], 4, 4))
    out[..., :3, :3] = exp3_batch(v[..., 3:6])
    out[..., :3, 3] = v[..., :3]
    out[..., 3, 3] = 1.0
    return out


def make(R: Array | None = None, t: Array | None = None) -> Array:
    T = np.eye(4)
    if R is not None:
        T[:3, :3] = R
    if t is not None:
        T[:3, 3] = t
    return T


def delta(v: Array) -> Array:
    """SE3(exp(r), t) for v = (tx, ty, tz, rx, ry, rz): the small correction applied on the right."""
    return make(exp3(np.asarray(v[3:6], dtype=float)), np.asarray(v[:3], dtype=float))


def inv(T: Array) -> Array:
    """Inverse of one (4,4) or many (N,4,4) rigid transforms."""
    R = T[..., :3, :3]
    t = T[..., :3, 3]
    out = np.zeros_like(T)
    Rt = np.swapaxes(R, -1, -2)
    out[..., :3, :3] = Rt
    out[..., :3, 3] = -np.einsum("...ij,...j->...i", Rt, t)
    out[..., 3, 3] = 1.0
    return out


def pose_difference(A: Array, B: Array) -> tuple[float, float]:
    """(translation distance in m, rotation angle in rad) between two poses."""
    dt = float(np.linalg.norm(A[:3, 3] - B[:3, 3]))
    angle = float(np.linalg.norm(log3(A[:3, :3].T @ B[:3, :3])))
    return dt, angle


def rpy_of(R: Array) -> Array:
    """URDF roll-pitch-yaw (R = Rz(yaw) Ry(pitch) Rx(roll)) of a rotation matrix."""
    pitch = math.atan2(-R[2, 0], math.hypot(R[0, 0], R[1, 0]))
    if abs(math.cos(pitch)) < 1e-10:  # gimbal lock: put everything in yaw
        return np.array([0.0, pitch, math.atan2(-R[0, 1], R[1, 1])])
    return np.array([math.atan2(R[2, 1], R[2, 2]), pitch, math.atan2(R[1, 0], R[0, 0])])


def xyz_rpy(xyz: list[float] | Array, rpy: list[float] | Array) -> Array:
    from armtool.model.chain import rpy_matrix

    return make(rpy_matrix(*[float(v) for v in rpy]), np.asarray(xyz, dtype=float))
