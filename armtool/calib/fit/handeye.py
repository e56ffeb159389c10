"""Closed-form hand-eye AX = XB: the five classic methods, and the start of the fit's measurement frames.

OpenCV 5 no longer exposes `calibrateHandEye` to Python, so the methods it offered are written
here with NumPy, a few lines each, from their papers:

* Tsai & Lenz 1989 ("A new technique for fully autonomous and efficient 3D robotics hand/eye
  calibration"): rotation from the modified Rodrigues vectors 2 sin(θ/2)·axis, by linear least squares;
* Park & Martin 1994 ("Robot sensor calibration: solving AX = XB on the Euclidean group"): the
  rotation that best maps the rotation vectors of B onto those of A (an orthogonal Procrustes problem);
* Horaud & Dornaika 1995 ("Hand-eye calibration"): the unit quaternion with q_A·q_X = q_X·q_B, the
  null vector of the stacked quaternion product matrices;
* Andreff, Horaud & Espiau 2001 ("Robot hand-eye calibration using structure-from-motion"): the
  rotation as the null vector of the Kronecker form (R_A ⊗ I − I ⊗ R_Bᵀ) vec R = 0, made a rotation;
* Daniilidis 1999 ("Hand-eye calibration using dual quaternions"): rotation and translation at once,
  from the two-dimensional null space of the stacked dual-quaternion equations.

All but Daniilidis's take the translation from (R_A − I) t_X = R_X t_B − t_A by least squares.
Motion pairs that turn less than MIN_PAIR_ROTATION carry no rotation information and amplify
noise: they are left out of every rotation estimate.
"""

from __future__ import annotations

from collections.abc import Sequence
from enum import Enum

import numpy as np

from armtool.calib.choices import Setup
from armtool.calib.model import se3
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError


class AxXbMethod(str, Enum):
    """The closed-form AX = XB methods (OpenCV's CALIB_HAND_EYE_* names, lower case)."""

    TSAI = "tsai"
    PARK = "park"
    HORAUD = "horaud"
    ANDREFF = "andreff"
    DANIILIDIS = "daniilidis"


MIN_PAIR_ROTATION = 0.05  # rad: a motion pair that turns less tells nothing about the rotation


def motion_pairs(G: Sequence[Array] | Array, C: Sequence[Array] | Array) -> tuple[Array, Array]:
    """(A, B) of every pair i < j of poses with G_i X C_i = Z: A = G_j⁻¹ G_i, B = C_j C_i⁻¹, so that
    A X = X B (as OpenCV pairs them: all pairs, not only neighbours)."""
    Gs, Cs = np.asarray(G, dtype=np.float64), np.asarray(C, dtype=np.float64)
    i, j = np.triu_indices(len(Gs), k=1)
    A = se3.inv(Gs[j]) @ Gs[i]
    B = Cs[j] @ se3.inv(Cs[i])
    return A, B


def solve_ax_xb(
    As: Sequence[Array] | Array, Bs: Sequence[Array] | Array, method: AxXbMethod = AxXbMethod.PARK
) -> Array:
    """X with A_k X = X B_k for every motion pair (A_k, B_k), in the least-squares sense of `method`."""
    A, B = np.asarray(As, dtype=np.float64).reshape(-1, 4, 4), np.asarray(Bs, dtype=np.float64).reshape(-1, 4, 4)
    a, b = se3.log3_batch(A[:, :3, :3]), se3.log3_batch(B[:, :3, :3])
    turning = (np.linalg.norm(a, axis=1) > MIN_PAIR_ROTATION) & (np.linalg.norm(b, axis=1) > MIN_PAIR_ROTATION)
    if int(turning.sum()) < 2:
        raise ArmtoolError(
            "the poses rotate the flange too little to start the fit",
            hint="take poses that turn the wrist by tens of degrees about different axes, or give hints: in dataset.yaml",
        )
    if method is AxXbMethod.DANIILIDIS:
        return _daniilidis(A[turning], B[turning])
    R = _ROTATION[method](A[turning], B[turning], a[turning], b[turning])
    return se3.make(R, _translation(A, B, R))


def _translation(A: Array, B: Array, R: Array) -> Array:
    """t_X from (R_A − I) t_X = R_X t_B − t_A over every pair, by least squares."""
    lhs = (A[:, :3, :3] - np.eye(3)).reshape(-1, 3)
    rhs = (B[:, :3, 3] @ R.T - A[:, :3, 3]).reshape(-1)
    t: Array = np.linalg.lstsq(lhs, rhs, rcond=None)[0]
    return t


def nearest_rotation(M: Array) -> Array:
    """The rotation nearest to a 3×3 matrix (Frobenius norm), through the SVD; a reflection is turned back."""
    U, _s, Vt = np.linalg.svd(M)
    R: Array = U @ np.diag([1.0, 1.0, float(np.sign(np.linalg.det(U @ Vt))) or 1.0]) @ Vt
    return R


def _park(A: Array, B: Array, a: Array, b: Array) -> Array:
    """R maximising Σ aᵀ R b: R = (MᵀM)^(−1/2) Mᵀ with M = Σ b aᵀ, through the SVD for stability."""
    return nearest_rotation(a.T @ b)


def _tsai(A: Array, B: Array, a: Array, b: Array) -> Array:
    """skew(P_A + P_B) P' = P_B − P_A with P = 2 sin(θ/2)·axis; then P_X = 2P'/√(1 + |P'|²)."""
    pa = 2.0 * np.sin(np.linalg.norm(a, axis=1) / 2)[:, None] * a / np.linalg.norm(a, axis=1)[:, None]
    pb = 2.0 * np.sin(np.linalg.norm(b, axis=1) / 2)[:, None] * b / np.linalg.norm(b, axis=1)[:, None]
    prime = np.linalg.lstsq(skews(pa + pb).reshape(-1, 3), (pb - pa).reshape(-1), rcond=None)[0]
    p = 2.0 * prime / np.sqrt(1.0 + prime @ prime)
    R = (1.0 - (p @ p) / 2.0) * np.eye(3) + 0.5 * (np.outer(p, p) + np.sqrt(max(4.0 - p @ p, 0.0)) * se3.skew(p))
    return nearest_rotation(R)


def _horaud(A: Array, B: Array, a: Array, b: Array) -> Array:
    """The unit quaternion q with q_A q = q q_B: the null vector of the stacked L(q_A) − R(q_B)."""
    M = _left(quaternions(A[:, :3, :3])) - _right(quaternions(B[:, :3, :3]))
    return rotation_of(_null_vectors(M, 1)[0])


def _andreff(A: Array, B: Array, a: Array, b: Array) -> Array:
    """vec R (row by row) as the null vector of the stacked R_A ⊗ I − I ⊗ R_Bᵀ, scaled to det 1 and
    made a rotation."""
    n, eye = len(A), np.eye(3)
    M = np.einsum("nij,kl->nikjl", A[:, :3, :3], eye) - np.einsum("ij,nlk->nikjl", eye, B[:, :3, :3])
    R = _null_vectors(M.reshape(n, 9, 9), 1)[0].reshape(3, 3)
    return nearest_rotation(R * np.sign(np.linalg.det(R)))


def _daniilidis(A: Array, B: Array) -> Array:
    """Daniilidis's SVD: each pair gives S (6×8) with S (q; q') = 0 for the dual quaternion of X;
    its two smallest right singular vectors span the solutions, and the unit-norm and
    orthogonality constraints pick the combination."""
    (a, a_), (b, b_) = dual_quaternions(A), dual_quaternions(B)
    S = np.zeros((len(A), 6, 8))
    S[:, :3, 0], S[:, :3, 1:4] = (a - b)[:, 1:], skews(a[:, 1:] + b[:, 1:])
    S[:, 3:, 0], S[:, 3:, 1:4] = (a_ - b_)[:, 1:], skews(a_[:, 1:] + b_[:, 1:])
    S[:, 3:, 4], S[:, 3:, 5:8] = (a - b)[:, 1:], skews(a[:, 1:] + b[:, 1:])
    v1, v2 = _null_vectors(S, 2)
    u1, w1, u2, w2 = v1[:4], v1[4:], v2[:4], v2[4:]
    # λ1 v1 + λ2 v2 with |q| = 1 and q·q' = 0: s = λ1/λ2 solves s² u1·w1 + s (u1·w2 + u2·w1) + u2·w2 = 0.
    qa, qb, qc = u1 @ w1, u1 @ w2 + u2 @ w1, u2 @ w2
    if abs(qa) < 1e-12:
        roots = [-qc / qb] if abs(qb) > 1e-12 else [0.0]
    else:
        disc = np.sqrt(max(qb * qb - 4 * qa * qc, 0.0))
        roots = [(-qb + disc) / (2 * qa), (-qb - disc) / (2 * qa)]
    norms = [s * s * (u1 @ u1) + 2 * s * (u1 @ u2) + u2 @ u2 for s in roots]
    s = roots[int(np.argmax(norms))]
    l2 = 1.0 / np.sqrt(max(norms), dtype=np.float64)
    x = s * l2 * v1 + l2 * v2
    q, q_ = x[:4], x[4:]
    t = (_left(q_[None]) @ (q * np.array([1.0, -1.0, -1.0, -1.0])))[0, 1:] * 2.0
    return se3.make(rotation_of(q), t)


_ROTATION = {AxXbMethod.TSAI: _tsai, AxXbMethod.PARK: _park, AxXbMethod.HORAUD: _horaud, AxXbMethod.ANDREFF: _andreff}


def _null_vectors(M: Array, count: int) -> Array:
    """The `count` right singular vectors of the stacked blocks M (n, r, c) with the smallest singular
    values, smallest last: the eigenvectors of Σ MᵀM (c × c, cheaper than the SVD of the stack)."""
    _w, V = np.linalg.eigh(np.einsum("nri,nrj->ij", M, M))
    out: Array = V[:, :count][:, ::-1].T
    return out


def skews(v: Array) -> Array:
    """[v]× of many vectors (..., 3): (..., 3, 3)."""
    out = np.zeros((*v.shape, 3))
    out[..., 0, 1], out[..., 0, 2], out[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    out[..., 1, 0], out[..., 2, 0], out[..., 2, 1] = v[..., 2], -v[..., 1], v[..., 0]
    return out


def quaternions(R: Array) -> Array:
    """Unit quaternions (w, x, y, z) of rotations (N, 3, 3), w ≥ 0 (SciPy's conversion)."""
    from scipy.spatial.transform import Rotation

    q = np.asarray(Rotation.from_matrix(R).as_quat(scalar_first=True), dtype=np.float64).reshape(-1, 4)
    out: Array = q * np.where(q[:, :1] < 0, -1.0, 1.0)
    return out


def rotation_of(q: Array) -> Array:
    """The rotation of a quaternion (w, x, y, z), of any norm."""
    from scipy.spatial.transform import Rotation

    R: Array = np.asarray(Rotation.from_quat(np.asarray(q, dtype=np.float64), scalar_first=True).as_matrix())
    return R


def dual_quaternions(T: Array) -> tuple[Array, Array]:
    """(q, q') (N, 4 each) of rigid transforms (N, 4, 4): q the rotation's unit quaternion (w ≥ 0),
    q' = ½ (0, t) q."""
    q = quaternions(T[:, :3, :3])
    t = np.concatenate([np.zeros((len(T), 1)), T[:, :3, 3]], axis=1)
    return q, 0.5 * np.einsum("nij,nj->ni", _left(t), q)


def _left(q: Array) -> Array:
    """L(q) (N, 4, 4) with q·p = L(q) p, quaternions (N, 4) as (w, x, y, z)."""
    w, x, y, z = q.T
    return np.stack(
        [np.stack(r, axis=-1) for r in ([w, -x, -y, -z], [x, w, -z, y], [y, z, w, -x], [z, -y, x, w])], axis=1
    )


def _right(q: Array) -> Array:
    """R(q) (N, 4, 4) with p·q = R(q) p."""
    w, x, y, z = q.T
    return np.stack(
        [np.stack(r, axis=-1) for r in ([w, -x, -y, -z], [x, w, z, -y], [y, -z, w, x], [z, y, -x, w])], axis=1
    )


def average_pose(Ts: Sequence[Array]) -> Array:
    """Chordal mean of rotations (projected back onto SO(3)) and mean of translations."""
    Rs = np.stack([T[:3, :3] for T in Ts]).sum(axis=0)
    U, _, Vt = np.linalg.svd(Rs)
    R = U @ np.diag([1.0, 1.0, np.linalg.det(U @ Vt)]) @ Vt
    return se3.make(R, np.mean([T[:3, 3] for T in Ts], axis=0))


def initial_frames(setup: Setup, flanges: Sequence[Array], tags_in_camera: Sequence[Array]) -> tuple[Array, Array]:
    """(L, R) with cMt_i ≈ L · F_i^±1 · R, from per-image PnP poses and nominal flange poses."""
    F = [T if setup is Setup.EYE_TO_HAND else se3.inv(T) for T in flanges]
    C = list(tags_in_camera)
    As, Bs = [], []
    # All pairs against a few anchors: robust to a bad image without O(N²) pairs.
    anchors = range(0, len(C), max(1, len(C) // 6))
    for i in anchors:
        for j in range(len(C)):
            if i != j:
                # C_i = L F_i R  ⇒  (F_i⁻¹ F_j) R = R (C_i⁻¹ C_j)
                As.append(se3.inv(F[i]) @ F[j])
                Bs.append(se3.inv(C[i]) @ C[j])
    R = solve_ax_xb(As, Bs)
    L = average_pose([C[i] @ se3.inv(R) @ se3.inv(F[i]) for i in range(len(C))])
    return L, R


def kabsch(a: Array, b: Array) -> Array:
    """The rigid transform T (4×4) with b_i ≈ T · a_i for point sets a, b (N, 3), least squares."""
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    U, _s, Vt = np.linalg.svd((a - ca).T @ (b - cb))
    D = np.diag([1.0, 1.0, float(np.sign(np.linalg.det(Vt.T @ U.T))) or 1.0])
    R = Vt.T @ D @ U.T
    return se3.make(R, cb - R @ ca)


def initial_point_frames(setup: Setup, flanges: Array, points: Array, rounds: int = 100) -> tuple[Array, Array]:
    """(L, R) with p_i ≈ L · F_i^±1 · R's origin, from nominal flange poses (N, 4, 4) and measured
    points (N, 3): the sensor frame L by Kabsch, the point (R, a translation) by linear least
    squares, alternated from the point at the flange (or base) origin until they settle.

    Why alternate: each is a closed form when the other is known, and a reflector sits within
    centimetres of the flange, so the first Kabsch is already close."""
    G = flanges if setup is Setup.EYE_TO_HAND else se3.inv(flanges)
    spread = np.linalg.svd(G[:, :3, 3] - G[:, :3, 3].mean(axis=0), compute_uv=False)
    if len(points) < 3 or spread[0] < 1e-3 or spread[1] < 1e-2 * spread[0]:
        raise ArmtoolError(
            "the flange positions do not span a plane: the sensor frame cannot be started from the points",
            hint="move the arm so that the flange visits positions spread in at least two directions, or give hints: in dataset.yaml",
        )
    p: Array = np.zeros(3)
    L = np.eye(4)
    A = G[:, :3, :3].reshape(-1, 3)
    for _round in range(rounds):
        L = kabsch(G[:, :3, :3] @ p + G[:, :3, 3], points)
        local = (points - L[:3, 3]) @ L[:3, :3]  # R_Lᵀ (p_i − t_L), row by row
        new = np.asarray(np.linalg.lstsq(A, (local - G[:, :3, 3]).reshape(-1), rcond=None)[0], dtype=np.float64)
        done = float(np.linalg.norm(new - p)) < 1e-9
        p = new
        if done:
            break
    return L, se3.make(t=p)
