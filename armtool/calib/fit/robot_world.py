"""Closed-form robot-world hand-eye AX = ZB: both unknown frames at once, without motion pairs.

Each pose gives A_i X = Z B_i directly (for a camera on the flange looking at a fixed board: A_i
the flange in the base, X the camera in the flange, Z the board in the base, B_i the board's pose
in the camera inverted). OpenCV 5 no longer exposes `calibrateRobotWorldHandEye` to Python; its two
methods, a few lines each with NumPy, from their papers:

* Shah 2013 ("Solving the robot-world/hand-eye calibration problem using the Kronecker product"):
  vec R_Z = (R_A ⊗ R_B) vec R_X for every pose (row-major vec), so vec R_X and vec R_Z are the
  first right and left singular vectors of Σ R_A ⊗ R_B; each is scaled to det 1 and made a rotation;
* Li, Wang & Wu 2010 ("Simultaneous robot-world and hand-eye calibration using dual-quaternions and
  Kronecker product"): rotations and translations as one linear least-squares system,
  (R_A ⊗ I) vec R_X − (I ⊗ R_Bᵀ) vec R_Z = 0 and R_A t_X − (I ⊗ t_Bᵀ) vec R_Z − t_Z = −t_A.

Both then take the translations from R_A t_X − t_Z = R_Z t_B − t_A with the rotations made exact
(Li's own translations come from the system whose rotations were not yet rotations).
"""

from __future__ import annotations

from collections.abc import Sequence
from enum import Enum

import numpy as np

from armtool.calib.fit.handeye import nearest_rotation
from armtool.calib.model import se3
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError


class AxZbMethod(str, Enum):
    """The closed-form AX = ZB methods (OpenCV's CALIB_ROBOT_WORLD_HAND_EYE_* names, lower case)."""

    SHAH = "shah"
    LI = "li"


def solve_ax_zb(
    As: Sequence[Array] | Array, Bs: Sequence[Array] | Array, method: AxZbMethod = AxZbMethod.SHAH
) -> tuple[Array, Array]:
    """(X, Z) with A_i X = Z B_i for every pose, in the least-squares sense of `method`."""
    A, B = np.asarray(As, dtype=np.float64).reshape(-1, 4, 4), np.asarray(Bs, dtype=np.float64).reshape(-1, 4, 4)
    if len(A) < 3:
        raise ArmtoolError(f"{len(A)} poses cannot determine two frames", hint="take at least 3 poses, better 15-30")
    Ra, Rb = A[:, :3, :3], B[:, :3, :3]
    n, eye = len(A), np.eye(3)
    if method is AxZbMethod.SHAH:
        K = np.einsum("nij,nkl->ikjl", Ra, Rb).reshape(9, 9)  # Σ R_A ⊗ R_B
        U, _s, Vt = np.linalg.svd(K)
        Rx, Rz = _rotation(Vt[0].reshape(3, 3)), _rotation(U[:, 0].reshape(3, 3))
    else:
        M = np.zeros((n, 12, 24))
        M[:, :9, :9] = np.einsum("nij,kl->nikjl", Ra, eye).reshape(n, 9, 9)  # R_A ⊗ I
        M[:, :9, 9:18] = -np.einsum("ij,nlk->nikjl", eye, Rb).reshape(n, 9, 9)  # −I ⊗ R_Bᵀ
        M[:, 9:, 9:18] = -np.einsum("ij,nk->nijk", eye, B[:, :3, 3]).reshape(n, 3, 9)  # −I ⊗ t_Bᵀ
        M[:, 9:, 18:21], M[:, 9:, 21:24] = Ra, -eye
        rhs = np.concatenate([np.zeros((n, 9)), -A[:, :3, 3]], axis=1)
        x = np.linalg.lstsq(M.reshape(-1, 24), rhs.reshape(-1), rcond=None)[0]
        Rx, Rz = _rotation(x[:9].reshape(3, 3)), _rotation(x[9:18].reshape(3, 3))
    lhs = np.concatenate([Ra, -np.broadcast_to(eye, Ra.shape)], axis=2).reshape(-1, 6)
    rhs_t = (B[:, :3, 3] @ Rz.T - A[:, :3, 3]).reshape(-1)
    t = np.linalg.lstsq(lhs, rhs_t, rcond=None)[0]
    return se3.make(Rx, t[:3]), se3.make(Rz, t[3:])


def _rotation(M: Array) -> Array:
    """A rotation from a matrix known up to scale and sign: scaled to det 1, then the nearest rotation."""
    det = float(np.linalg.det(M))
    if abs(det) < 1e-12:
        raise ArmtoolError("the poses do not determine the rotations", hint="turn the flange about different axes")
    return nearest_rotation(M * (np.sign(det) / abs(det) ** (1.0 / 3.0)))
