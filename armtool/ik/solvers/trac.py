"""`trac`: TRAC-IK's design (Beeson & Ames 2015) in Python.

TRAC-IK runs two solvers concurrently on the same target and returns the first success:
(a) KDL's Newton–Raphson with joint limits, which restarts from a random configuration
within the limits whenever it is stuck (the joints stop moving while the error stays), and
(b) an SQP with joint bounds (NLopt's SLSQP) minimizing the squared pose error, restarted
from random when it converges to a non-solution. Python threads share one interpreter lock,
so here the two are interleaved in time slices inside the same budget instead of running on
two cores: the design is TRAC-IK's, the concurrency is not.

Solve types as TRAC-IK's: `speed` returns the first solution; `distance`, `manip1` and
`manip2` keep searching until the timeout and return the solution closest to the seed, with
the largest √det(JJᵀ), or the largest σ_min/σ_max.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from armtool.errors import ArmtoolError
from armtool.ik.solver import Array, IKResult, Solver, pose_error, verify

SOLVE_TYPES = ("speed", "distance", "manip1", "manip2")


class TracIK(Solver):
    name = "trac"
    summary = "TRAC-IK's design: Newton with random restarts and a bounded SQP sharing the budget"
    options: ClassVar[dict[str, Any]] = {"solve_type": "speed", "nr_slice": 30, "sqp_iterations": 20}

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if self.opts["solve_type"] not in SOLVE_TYPES:
            raise ArmtoolError(f"unknown solve_type '{self.opts['solve_type']}'", hint="one of: " + ", ".join(SOLVE_TYPES))
        from scipy.optimize import minimize  # imported here, not inside a timed solve

        self._minimize = minimize

    # -- (a) KDL Newton-Raphson with joint limits, random restart when stuck --------------------
    def _nr_steps(self, q: Array, target: Array, steps: int, deadline: float) -> tuple[Array, bool, int]:
        chain = self.chain
        done = 0
        for _ in range(steps):
            if self.clock() > deadline:
                break
            T, J = chain.fk_jacobian(q)
            e = pose_error(T, target)
            if float(np.abs(e).max()) < 0.5 * self.tolerance:
                return q, True, done
            done += 1
            q_new = chain.clamp(q + np.linalg.pinv(J, rcond=1e-5) @ e)
            if float(np.abs(q_new - q).max()) < 1e-5:  # stuck (joints stopped moving): TRAC-IK randomizes
                q_new = chain.random(self.rng)
            q = q_new
        return q, False, done

    # -- (b) SQP with bounds on the squared error ------------------------------------------------
    def _sqp(self, q: Array, target: Array, deadline: float) -> tuple[Array, bool, int]:
        chain = self.chain

        def stop_at_deadline(_x: Array) -> None:
            if self.clock() > deadline:
                raise StopIteration

        def cost(x: Array) -> tuple[float, Array]:
            T, J = chain.fk_jacobian(x)
            e = pose_error(T, target)
            return 0.5 * float(e @ e), -(J.T @ e)

        bounds = list(zip(chain.lower, chain.upper))
        res = self._minimize(cost, q, jac=True, method="SLSQP", bounds=bounds, callback=stop_at_deadline,
                             options={"maxiter": int(self.opts["sqp_iterations"]), "ftol": 1e-14})
        x = np.asarray(res.x, dtype=float)
        T = chain.fk(x)
        ok = float(np.abs(pose_error(T, target)).max()) < 0.5 * self.tolerance
        return x, ok, int(res.nit)

    def _score(self, q: Array, seed: Array) -> float:
        kind = self.opts["solve_type"]
        if kind == "distance":
            return -float(np.linalg.norm(q - seed))
        s = np.linalg.svd(self.chain.jacobian(q), compute_uv=False)
        return float(np.prod(s)) if kind == "manip1" else float(s[-1] / s[0])

    def solve(self, target: Array, seed: Array) -> IKResult:
        chain = self.chain
        deadline = self.clock() + self.timeout
        seed = np.asarray(seed, dtype=float)
        q_nr = chain.clamp(seed.copy())
        q_sqp = chain.clamp(seed.copy())
        iterations = 0
        best: tuple[float, Array] | None = None
        speed = self.opts["solve_type"] == "speed"
        while self.clock() < deadline:
            for solver in ("nr", "sqp"):
                if solver == "nr":
                    q_nr, ok, n = self._nr_steps(q_nr, target, int(self.opts["nr_slice"]), deadline)
                    q_found = q_nr
                else:
                    q_sqp, ok, n = self._sqp(q_sqp, target, deadline)
                    q_found = q_sqp
                    if not ok:
                        q_sqp = chain.random(self.rng)  # converged elsewhere: restart
                iterations += n
                if ok and verify(chain, q_found, target, self.tolerance)[0]:
                    if speed:
                        return self._result(q_found, target, iterations)
                    score = self._score(q_found, seed)
                    if best is None or score > best[0]:
                        best = (score, q_found.copy())
                    # keep searching elsewhere for a better one
                    q_nr, q_sqp = chain.random(self.rng), chain.random(self.rng)
                if self.clock() >= deadline:
                    break
        if best is not None:
            return self._result(best[1], target, iterations)
        return self._result(q_nr, target, iterations, "timeout")
