"""`dls`: damped least squares, Δq = Jᵀ(JJᵀ + λ²I)⁻¹e, with variable damping.

The classic method that stays stable near singularities (Nakamura & Hanafusa 1986; variable
damping as in Chiaverini 1997): λ² = 0 while the smallest singular value σ_min of J is above
`singular_region`, rising smoothly to `lambda_max`² as σ_min → 0. Steps are limited to
`max_step` (rad or m) and projected onto the joint limits. No restarts: it shows what a plain
Jacobian method does on the robot, next to the solvers that search.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from armtool.ik.solver import Array, IKResult, Solver, pose_error


class DampedLeastSquares(Solver):
    name = "dls"
    summary = "damped least squares with variable damping near singularities, no restarts"
    options: ClassVar[dict[str, Any]] = {"lambda_max": 0.1, "singular_region": 0.05, "max_step": 0.5}

    def solve(self, target: Array, seed: Array) -> IKResult:
        chain = self.chain
        deadline = self.clock() + self.timeout
        lam_max2 = float(self.opts["lambda_max"]) ** 2
        eps = float(self.opts["singular_region"])
        max_step = float(self.opts["max_step"])
        goal = (0.5 * self.tolerance) ** 2
        eye_n = np.eye(chain.n)
        q = chain.clamp(np.asarray(seed, dtype=float).copy())
        iterations = 0
        while True:
            T, J = chain.fk_jacobian(q)
            e = pose_error(T, target)
            if float(e @ e) < goal:
                return self._result(q, target, iterations)
            if self.clock() > deadline:
                return self._result(q, target, iterations, "timeout")
            iterations += 1
            sigma_min = float(np.linalg.svd(J, compute_uv=False)[-1])
            lam2 = 0.0 if sigma_min >= eps else (1.0 - (sigma_min / eps) ** 2) * lam_max2
            # (JᵀJ + λ²I)⁻¹Jᵀe equals Jᵀ(JJᵀ + λ²I)⁻¹e and stays solvable for chains with n < 6.
            dq = np.linalg.solve(J.T @ J + (lam2 + 1e-12) * eye_n, J.T @ e)
            largest = float(np.abs(dq).max())
            if largest > max_step:
                dq *= max_step / largest
            q = q + dq
            q = np.where(chain.continuous, (q + math.pi) % (2 * math.pi) - math.pi, np.clip(q, chain.lower, chain.upper))
