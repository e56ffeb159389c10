"""Closed-form AX = XB (Park & Martin 1994) to start the fit near the answer.

OpenCV 5 no longer exposes `calibrateHandEye` to Python, and the fit only needs a start within a
few degrees and centimetres, so the classic closed form is enough: rotation from the rotation
vectors of the motion pairs, then translation by linear least squares.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from armtool.calib.choices import Setup
from armtool.calib.model import se3
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError


def solve_ax_xb(As: Sequence[Array], Bs: Sequence[Array]) -> Array:
    """X with A_k X = X B_k for every motion pair (A_k, B_k), in the least-squares sense."""
    alphas, betas = [], []
    for A, B in zip(As, Bs):
        a, b = se3.log3(A[:3, :3]), se3.log3(B[:3, :3])
        # Pairs with little rotation carry no rotation information and amplify noise.
        if np.linalg.norm(a) > 0.05 and np.linalg.norm(b) > 0.05:
            alphas.append(a)
            betas.append(b)
    if len(alphas) < 2:
        raise ArmtoolError(
            "the poses rotate the flange too little to start the fit",
            hint="take poses that turn the wrist by tens of degrees about different axes, or give hints: in dataset.yaml",
        )
    M = sum(np.outer(b, a) for a, b in zip(alphas, betas))
    # R = (MᵀM)^(-1/2) Mᵀ, through the SVD for stability; fix a reflection if noise made one.
    U, _, Vt = np.linalg.svd(np.asarray(M).T)
    R = U @ Vt
    if np.linalg.det(R) < 0:
        U[:, -1] *= -1
        R = U @ Vt
    lhs = np.vstack([A[:3, :3] - np.eye(3) for A in As])
    rhs = np.concatenate([R @ B[:3, 3] - A[:3, 3] for A, B in zip(As, Bs)])
    t, *_ = np.linalg.lstsq(lhs, rhs, rcond=None)
    return se3.make(R, t)


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
