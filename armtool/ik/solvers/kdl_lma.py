"""`kdl-lma`: Orocos KDL's `ChainIkSolverPos_LMA` (Levenberg–Marquardt, no joint limits).

What it reproduces: orocos_kdl 1.4/1.5 `orocos_kdl/src/chainiksolverpos_lma.cpp` (Erwin
Aertbeliën, 2012) with its default parameters: weights L = diag(1, 1, 1, 0.01, 0.01, 0.01),
eps = 1e-5 (here: option `eps`, by default the tolerance), maxiter = 500, eps_joints = 1e-15. The driver loop is the one
TRAC-IK's benchmark uses for KDL: `q = result; rc = CartToJnt(q, pose, result)` from the seed
until rc >= 0 or the timeout.

One CartToJnt call, with Δ = L·diff(FK(q), target) (the weighted 6-vector error) and
J_w = L·J (J: 6×n [v; ω] in the base frame at the tip):
  • if ‖Δ‖ < eps at the start: success without iterating. λ = 10, v = 2.
  • per iteration: J_w = U S Vᵀ (thin SVD); Δq = V diag(σ/(σ² + λ)) Uᵀ Δ; g = J_wᵀ Δ.
    Stop (E_INCREMENT_JOINTS_TOO_SMALL) if max|Δq| < eps_joints; stop
    (E_GRADIENT_JOINTS_TOO_SMALL) if gᵀg < eps_joints².
    ρ = (‖Δ‖² − ‖Δ_new‖²) / (Δqᵀ(λ Δq + g)) with Δ_new at q + Δq.
    ρ > 0: accept; success if ‖Δ_new‖ < eps; else recompute J_w and λ ← λ·max(1/3, 1 − (2ρ − 1)³), v = 2.
    ρ ≤ 0: reject; λ ← λ·v, v ← 2v.
  • after maxiter iterations: E_MAX_ITERATIONS_EXCEEDED, q is the last accepted point.
No joint limits anywhere: q may leave them (and is not wrapped).

Differences from the C++ that do not change the iterates: after a rejected step the SVD and
Uᵀ Δ are reused (J_w and Δ are unchanged, KDL recomputes the same SVD); LAPACK's dgesvd
replaces Eigen's JacobiSVD (same factorisation up to rounding and column signs). One
deliberate difference: the clock is also checked inside a call, because one 500-iteration
call costs ~10 ms in Python (about 1 ms in C++), and a solve must not overrun its timeout.

KDL's own success test is on the *weighted* error: ‖(Δp, 0.01·Δω)‖ < eps accepts rotation
errors up to 100·eps. Our verdict (`Solver.judge`: unweighted ‖Δp‖, ‖Δω‖ ≤ tolerance, q within
limits) rejects those, and rejects every answer outside the joint limits, which this solver
ignores: that is the point of offering it, to show users what KDL's LMA returns. To meet an
unweighted tolerance, pass eps = tolerance × min(weights) (1e-7 for the defaults).

Checked against liborocos-kdl 1.5.1 on Panda (1000 targets, seed mid-range, 5 ms): the same
final q on 99.7 % of targets. KDL reports success on 99 %; with eps = 1e-5 none pass a 1e-5
rotation tolerance (median rotation error 2e-4 rad) and 23 % lie outside the joint limits;
with eps = 1e-7, 76 % are verified.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np
import pinocchio as pin
from scipy.linalg import lapack

from armtool.errors import ArmtoolError
from armtool.ik.solver import Answer, Array, Solver
from armtool.model.chain import Chain

_SUCCESS, _STALLED, _MAX_ITER, _TIMEOUT, _MAX_CALLS = range(5)


class KdlLevenbergMarquardt(Solver):
    name = "kdl-lma"
    summary = "Orocos KDL ChainIkSolverPos_LMA (Levenberg–Marquardt, weighted error, ignores joint limits), looped until timeout"
    options: ClassVar[dict[str, Any]] = {
        "weights": (1.0, 1.0, 1.0, 0.01, 0.01, 0.01),  # L: task-space weights (x, y, z, rx, ry, rz)
        "max_iterations": 500,  # maxiter per CartToJnt call
        "eps_joints": 1e-15,  # stop a call when max|Δq| or ‖g‖ falls below this
        "max_calls": None,  # also stop after this many CartToJnt calls (an iteration budget that does not depend on CPU speed)
        "eps": None,  # KDL's eps on the weighted error norm; None: the tolerance (KDL's default 1e-5 = ours)
    }

    def __init__(
        self, chain: Chain, timeout: float = 0.005, tolerance: float = 1e-5, seed: int | None = 0, **options: Any
    ) -> None:
        super().__init__(chain, timeout, tolerance, seed, **options)
        weights = np.asarray(self.opts["weights"], dtype=float)
        if weights.shape != (6,) or not np.all(weights >= 0) or not np.any(weights > 0):
            raise ArmtoolError(
                f"weights must be 6 non-negative numbers (x, y, z, rx, ry, rz), got {self.opts['weights']!r}",
                hint="KDL's default: 1 1 1 0.01 0.01 0.01",
            )
        self._weights = weights

    def call(self, prepared: tuple[Array, Array]) -> tuple[Array, int, int, int]:
        """(q, status, iterations, CartToJnt calls): `answer` reads them."""
        target, seed = prepared
        chain = self.chain
        deadline = self.clock() + self.timeout
        clock = self.clock
        fk_jacobian = chain.fk_jacobian
        log3 = pin.log3
        dgesvd = lapack.dgesvd
        L = self._weights
        L_col = L[:, None]
        maxiter = int(self.opts["max_iterations"])
        eps_joints = float(self.opts["eps_joints"])
        eps_joints_sq = eps_joints * eps_joints
        max_calls = math.inf if self.opts["max_calls"] is None else int(self.opts["max_calls"])
        eps = self.tolerance if self.opts["eps"] is None else float(self.opts["eps"])
        p_target = np.ascontiguousarray(target[:3, 3])
        R_target = np.ascontiguousarray(target[:3, :3])

        def weighted_error(T: Array) -> Array:
            e = np.empty(6)
            np.subtract(p_target, T[:3, 3], out=e[:3])
            e[3:] = log3(R_target @ T[:3, :3].T)
            e *= L
            return e

        def cart_to_jnt(q: Array) -> tuple[int, Array, int]:
            """One KDL CartToJnt call from q: (status, q_out, iterations used)."""
            T, J = fk_jacobian(q)
            d = weighted_error(T)
            d_norm = math.sqrt(float(d @ d))
            if d_norm < eps:
                return _SUCCESS, q, 0
            Jw = L_col * J
            U, s, Vt, _ = dgesvd(Jw, compute_uv=1, full_matrices=0)
            U_d, grad = U.T @ d, Jw.T @ d
            lam, v = 10.0, 2.0
            for i in range(maxiter):
                dq = Vt.T @ (s / (s * s + lam) * U_d)
                if np.abs(dq).max() < eps_joints or float(grad @ grad) < eps_joints_sq:
                    return _STALLED, q, i + 1  # E_INCREMENT_JOINTS_TOO_SMALL / E_GRADIENT_JOINTS_TOO_SMALL
                q_new = q + dq
                T, J = fk_jacobian(q_new)
                d_new = weighted_error(T)
                d_new_norm = math.sqrt(float(d_new @ d_new))
                num = d_norm * d_norm - d_new_norm * d_new_norm
                denom = float(dq @ (lam * dq + grad))  # > 0 whenever dq ≠ 0; C++ would divide by zero regardless
                rho = num / denom if denom != 0.0 else (math.copysign(math.inf, num) if num != 0.0 else math.nan)
                if rho > 0:
                    q, d, d_norm = q_new, d_new, d_new_norm
                    if d_norm < eps:
                        return _SUCCESS, q, i + 1
                    Jw = L_col * J
                    U, s, Vt, _ = dgesvd(Jw, compute_uv=1, full_matrices=0)
                    U_d, grad = U.T @ d, Jw.T @ d
                    t = 2.0 * rho - 1.0
                    lam *= max(1.0 / 3.0, 1.0 - t * t * t)
                    v = 2.0
                else:  # rejected: J_w and Δ unchanged, so is their SVD (KDL recomputes it)
                    lam *= v
                    v *= 2.0
                if clock() >= deadline:
                    return _TIMEOUT, q, i + 1
            return _MAX_ITER, q, maxiter

        q = np.array(seed, dtype=float)
        iterations = 0
        calls = 0
        while True:  # TRAC-IK's benchmark loop: q = result; rc = CartToJnt(q, pose, result)
            status, q, used = cart_to_jnt(q)
            iterations += used
            calls += 1
            if status == _SUCCESS:
                return q, _SUCCESS, iterations, calls
            if status == _TIMEOUT or clock() >= deadline:
                return q, _TIMEOUT, iterations, calls
            if calls >= max_calls:
                return q, _MAX_CALLS, iterations, calls

    def answer(self, raw: tuple[Array, int, int, int]) -> Answer:
        q, status, iterations, calls = raw
        if status == _SUCCESS:
            return Answer(q, True, iterations)
        if status == _TIMEOUT:
            return Answer(q, False, iterations, "timeout")
        return Answer(q, False, iterations, f"no convergence in {calls} calls (max_calls)")

    def rejected_claim(self, answer: Answer) -> str:
        return _own_success_reason(self.chain, np.asarray(answer.q, dtype=float))


def _own_success_reason(chain: Chain, q: Array) -> str:
    """Why KDL's own success can still fail our verification."""
    if not chain.within_limits(q):
        return "converged outside the joint limits (LMA ignores them)"
    return "KDL's test weights rotation by 0.01: it stops at up to 100× the rotation tolerance (eps=1e-7 meets it)"
