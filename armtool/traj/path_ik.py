"""The IK of `traj cartesian`: each point solved from the previous one, with a solver built only
when it is needed.

Why: a Cartesian path steps 1 mm at a time, so each target is within a few iterations of its seed.
The `lm` solver's first try from the seed solves it, but building `lm` costs several times the
whole path (SciPy's LAPACK and k-d tree imports and a table of 32768 random poses, ~0.5 s of CPU,
used only for restarts). `PathIK` with `lm` runs that first try itself, the same iteration with the
same constants read off the `lm` class (damping λ = k·‖e‖² + λ̄, the tip's body Jacobian and
log6 error, joints held at a limit taken out of the step, success when both error norms are within
0.99·tolerance and the joints within their limits), and builds the real solver for a target only
when that try stalls, or when the seed is far enough for `lm` to start from its table instead
(`FAR`). The answer is then `lm`'s own, so the path is the same either way. Every other solver
(`analytic`'s nearest solution, `trac`, ...) is called directly for every point.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from armtool.ik.solver import IKResult, Solver
from armtool.model.chain import Chain
from armtool.traj.trajectory import Array


class PathIK:
    """`solve(target, seed) -> IKResult` for path following; the named solver is built on first need."""

    def __init__(self, chain: Chain, solver: str, tolerance: float = 1e-5) -> None:
        from armtool.ik.registry import make_solver

        self.chain, self.solver_name, self.tolerance = chain, solver, tolerance
        self._make: Callable[[], Solver] = lambda: make_solver(solver, chain, tolerance=tolerance)
        self.fallbacks = 0  # targets the first try did not solve (the real solver was asked)
        self._lm: _FirstTry | None = _FirstTry(chain, tolerance) if solver == "lm" else None
        # Any other solver now: one that does not apply to this arm (analytic) fails before the path.
        self._solver: Solver | None = None if self._lm is not None else self._make()

    @property
    def solver(self) -> Solver:
        if self._solver is None:
            self._solver = self._make()
        return self._solver

    def solve(self, target: Array, seed: Array) -> IKResult:
        if self._lm is not None:
            done = self._lm.solve(target, seed)
            if done is not None:
                return done
            self.fallbacks += 1
        return self.solver.solve(target, seed)


class _FirstTry:
    """`lm`'s first try from the seed (see armtool/ik/solvers/lm.py, `_solve`), or None where `lm`
    would go on: a stalled try, or a seed farther than `FAR` (lm then starts from its table)."""

    def __init__(self, chain: Chain, tolerance: float) -> None:
        from armtool.ik.solvers.lm import LevenbergMarquardt as LM

        self.chain, self.tolerance = chain, tolerance
        self.k = float(LM.options["error_damping"])
        self.bias = float(LM.options["damping_bias"])
        self.per_try = int(LM.options["max_iterations_per_try"])
        self.patience, self.progress, self.far = LM.FIRST_STALL, LM.PROGRESS, LM.FAR
        cont = chain.continuous
        self.lower = np.where(cont, -np.inf, chain.lower)
        self.upper = np.where(cont, np.inf, chain.upper)
        self.eye = np.eye(chain.n)

    def _error(self, q: Array, goal: Any) -> tuple[Any, Array, float]:
        pin, model, data, frame = self.chain._model()
        pin.computeJointJacobians(model, data, q)
        D = pin.updateFramePlacement(model, data, frame).actInv(goal)
        e = pin.log6(D).vector
        return D, e, float(e.dot(e))

    def solve(self, target: Array, seed: Array) -> IKResult | None:
        pin, model, data, frame = self.chain._model()
        goal = pin.SE3(np.asarray(target, dtype=float))
        lower, upper = self.lower, self.upper
        near = 2.0 * (0.99 * self.tolerance) ** 2
        q = np.minimum(np.maximum(np.asarray(seed, dtype=float), lower), upper)
        D, e, err = self._error(q, goal)
        if err > self.far:
            return None
        try_err, since = math.inf, 0
        for iterations in range(self.per_try + 1):
            if iterations:
                D, e, err = self._error(q, goal)
            if err < near:
                done = self._converged(q, D, e, iterations)
                if done is not None:
                    return done
            since = 0 if err < try_err * self.progress else since + 1
            try_err = min(try_err, err)
            if since >= self.patience or iterations >= self.per_try:
                return None
            J = pin.getFrameJacobian(model, data, frame, pin.LOCAL).reshape(6, -1)
            A = J.T @ J + (self.k * err + self.bias) * self.eye
            g = J.T @ e
            q_raw = q + np.linalg.solve(A, g)
            q_next = np.minimum(np.maximum(q_raw, lower), upper)
            blocked = (q_next == q) & (q_next != q_raw)  # held at a limit that the step pushes past
            if blocked.any():
                A[blocked, :] = 0.0
                A[:, blocked] = 0.0
                A[blocked, blocked] = 1.0
                g[blocked] = 0.0
                q_next = np.minimum(np.maximum(q + np.linalg.solve(A, g), lower), upper)
            q = q_next
        return None

    def _converged(self, q: Array, D: Any, e: Array, iterations: int) -> IKResult | None:
        t, w = D.translation, e[3:]
        pos2, rot2 = float(t.dot(t)), float(w.dot(w))
        tol2 = (0.99 * self.tolerance) ** 2
        if not (pos2 <= tol2 and rot2 <= tol2):
            return None
        chain = self.chain
        q = np.where(chain.continuous, (q + math.pi) % (2 * math.pi) - math.pi, q)
        if not (np.all(np.isfinite(q)) and chain.within_limits(q)):
            return None
        return IKResult(True, q, math.sqrt(pos2), math.sqrt(rot2), iterations)
