"""`dls`: damped least squares, Δq = Jᵀ(JJᵀ + λ²I)⁻¹e, with variable damping.

The classic Jacobian method that stays stable near singularities (Wampler 1986; Nakamura &
Hanafusa 1986), with the damping of Chiaverini (1997) and Maciejewski & Klein: no damping
while the smallest singular value σ_min of J is at least `singular_region` (ε), and inside
that region

    λ² = (1 − (σ_min/ε)²) · λ_max²,

which rises smoothly from 0 at σ_min = ε to `lambda_max`² as σ_min → 0. Through the SVD
J = Σ σ_i u_i v_iᵀ the step is Σ σ_i/(σ_i² + λ²) · (u_iᵀe) v_i: the pseudo-inverse step far
from singularities, and a step whose gain 1/σ is capped at 1/(2λ) near them, where the plain
inverse would send the arm flying. The same sum serves chains with fewer than six joints,
whose JJᵀ is singular everywhere.

Each step is scaled down so that no joint moves more than `max_step` (rad or m), then
projected onto the joint limits (continuous joints wrap to [-π, π)). The loop runs from the
seed until the pose is within the tolerance or the time is up, with no restarts: this is the
method as textbooks give it, and `armtool ik-bench` shows what it achieves next to solvers that
search. One exception to "until the time is up": when the projected step no longer moves any
joint (the arm pressed against its limits at a fixed point), it returns at once with reason
"stalled at the joint limits", since further iterations would repeat the same state.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np
import pinocchio as pin
from scipy.linalg import lapack

from armtool.errors import ArmtoolError
from armtool.ik.solver import Array, Solver


def damped_step(J: Array, e: Array, lambda_max: float, singular_region: float, max_step: float) -> tuple[Array, float]:
    """One damped least-squares step for the 6×n Jacobian J and pose error e, and the λ² used.

    Δq = Σ σ_i/(σ_i² + λ²) (u_iᵀe) v_i = Jᵀ(JJᵀ + λ²I)⁻¹e (for λ > 0), scaled so that
    max|Δq_i| ≤ max_step.
    """
    U, s, Vt, info = lapack.dgesvd(J, compute_uv=1, full_matrices=0)
    if info != 0:  # LAPACK did not converge: no step is safer than a wrong one
        return np.zeros(J.shape[1]), math.inf
    sigma_min = float(s[-1])
    lam2 = 0.0 if sigma_min >= singular_region else (1.0 - (sigma_min / singular_region) ** 2) * lambda_max**2
    denom = s * s + lam2
    gain = np.divide(s, denom, out=np.zeros_like(s), where=denom > 0.0)  # σ = λ = 0: that direction gets no motion
    dq = Vt.T @ (gain * (U.T @ e))
    largest = float(np.abs(dq).max())
    if largest > max_step:
        dq *= max_step / largest
    return dq, lam2


class DampedLeastSquares(Solver):
    name = "dls"
    summary = "damped least squares with variable damping near singularities (Chiaverini), no restarts"
    options: ClassVar[dict[str, Any]] = {
        "lambda_max": 0.05,  # damping at a singularity (σ_min = 0)
        "singular_region": 0.05,  # σ_min below which damping starts
        "max_step": 0.5,  # largest joint motion per step, rad or m
    }

    def __init__(
        self, chain: Any, timeout: float = 0.005, tolerance: float = 1e-5, seed: int | None = 0, **options: Any
    ) -> None:
        super().__init__(chain, timeout, tolerance, seed, **options)
        for key in self.options:
            value = self.opts[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
                raise ArmtoolError(
                    f"solver 'dls' option {key} must be a number ≥ 0, got {value!r}",
                    hint=f"default: {self.options[key]}",
                )
        if not self.opts["max_step"] > 0:
            raise ArmtoolError("solver 'dls' option max_step must be > 0", hint=f"default: {self.options['max_step']}")

    def call(self, prepared: tuple[Array, Array]) -> tuple[Array, bool, int, str]:
        target, seed = prepared
        chain = self.chain
        clock = self.clock
        deadline = clock() + self.timeout
        fk_jacobian = chain.fk_jacobian
        log3 = pin.log3
        lam_max = float(self.opts["lambda_max"])
        region = float(self.opts["singular_region"])
        max_step = float(self.opts["max_step"])
        tol = self.tolerance
        lower, upper, cont = chain.lower, chain.upper, chain.continuous
        wrap_any = bool(cont.any())
        p_target = np.ascontiguousarray(target[:3, 3])
        R_target = np.ascontiguousarray(target[:3, :3])
        e = np.empty(6)
        q = chain.clamp(np.asarray(seed, dtype=float).copy())
        iterations = 0
        while True:
            T, J = fk_jacobian(q)
            np.subtract(p_target, T[:3, 3], out=e[:3])
            e[3:] = log3(R_target @ T[:3, :3].T)
            if float(np.abs(e).max()) < tol:
                return q, True, iterations, ""
            if clock() > deadline:
                return q, False, iterations, "timeout"
            iterations += 1
            dq, _ = damped_step(J, e, lam_max, region, max_step)
            q_raw = q + dq
            q_new = np.minimum(np.maximum(q_raw, lower), upper)
            if wrap_any:
                q_new = np.where(cont, (q_raw + math.pi) % (2 * math.pi) - math.pi, q_new)
            if not (q_new != q).any():
                return q, False, iterations, "stalled at the joint limits"
            q = q_new
