"""`lm`: Levenberg–Marquardt with joint limits, error-scaled damping and random restarts.

Damping follows Sugihara (2011): λ = k·E + λ̄ with E = ‖e‖² the squared pose error, so steps
approach Gauss–Newton near a solution and shrink where the error is large. Every step is taken,
also one that raises the error (λ grows with it, as in rtb's ik_LM): a monotone search (reject,
raise λ, retry) crawls through the curved valleys around near-singular poses, which is where the
slowest 1 % of targets lie, and this one crosses them. Limits are enforced by projection, with
joints held at a limit taken out of the step; continuous joints move freely and wrap into
[-π, π) in the answer. A try whose best error has not halved in STALL iterations ends, and the
solver restarts until the time budget is spent: first from the configurations of a table of
random poses (built once per solver) nearest to the target, then uniform random ones.

The scalar loop works in the tip frame (Pinocchio's body Jacobian and log6 twist: one call
each), ~10 µs per iteration in all; an answer is accepted once every component of the
base-frame twist error is within 0.99·tolerance.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from armtool.ik.solver import Array, IKResult, Solver, pose_error, pose_error_batch, verify_batch


class LevenbergMarquardt(Solver):
    name = "lm"
    summary = "Levenberg–Marquardt with joint limits, error-scaled damping and random restarts (armtool's best)"
    options: ClassVar[dict[str, Any]] = {
        "error_damping": 0.1,
        "damping_bias": 1e-6,
        "max_iterations_per_try": 25,
    }
    SCALAR_TAIL = 16
    STALL = 5  # iterations without the try's best error falling by PROGRESS end a try
    PROGRESS = 0.5
    TABLE_SIZE = 4096
    TABLE_SEEDS = 8
    BATCH_TABLE_SIZE = 1024  # restarts of many targets at once search a smaller table
    _table: tuple[Array, Array, Array] | None = None  # per instance, built on first restart

    def __init__(self, chain: Any, timeout: float = 0.005, tolerance: float = 1e-5, seed: int | None = 0, **options: Any) -> None:
        super().__init__(chain, timeout, tolerance, seed, **options)
        import pinocchio as pin
        from scipy.linalg import blas, lapack

        self._lapack_dposv = lapack.dposv
        self._blas_dsyrk = blas.dsyrk
        # Per-solve constants, computed once: every microsecond counts at ~10 µs per iteration.
        self._pin_calls = (pin.computeJointJacobians, pin.updateFramePlacement, pin.getFrameJacobian, pin.log6, pin.LOCAL)
        cont = chain.continuous
        self._k = float(self.opts["error_damping"])
        self._bias = float(self.opts["damping_bias"])
        self._per_try = int(self.opts["max_iterations_per_try"])
        self._lower = np.where(cont, -np.inf, chain.lower)
        self._upper = np.where(cont, np.inf, chain.upper)
        self._lower_l, self._upper_l = self._lower.tolist(), self._upper.tolist()
        self._limits_l = (chain.lower.tolist(), chain.upper.tolist(), cont.tolist())
        self._wrap_any = bool(cont.any())
        self._eye = np.asfortranarray(np.eye(chain.n))
        self._restart_seeds(np.eye(4))  # build the pose table now, not inside a timed solve

    def _dposv(self, A: Array, g: Array) -> Array:
        """Solve the damped normal equations (symmetric positive definite) with LAPACK's Cholesky
        directly: a quarter of np.linalg.solve's cost at this size."""
        _, x, info = self._lapack_dposv(A, g)
        return x if info == 0 else np.linalg.solve(A, g)

    def _batch_restart_seeds(self, targets: Array, count: Array) -> Array:
        """For each target, its count-th nearest table configuration (random once those run out)."""
        assert self._table is not None
        Qt, F, F2 = (a[: self.BATCH_TABLE_SIZE] for a in self._table)
        f = _pose_features(targets)
        d = F2[None, :] - 2.0 * (f @ F.T)  # squared distance up to |f|², which does not change the order
        order = np.argpartition(d, self.TABLE_SEEDS, axis=1)[:, : self.TABLE_SEEDS]
        order = np.take_along_axis(order, np.argsort(np.take_along_axis(d, order, axis=1), axis=1), axis=1)
        out = self.rng.uniform(self.chain.lower, self.chain.upper, size=(len(targets), self.chain.n))
        use = count < self.TABLE_SEEDS
        out[use] = Qt[order[use, count[use]]]
        return out

    def _restart_seeds(self, target: Array) -> list[Array]:
        """Configurations whose tip pose is nearest the target (position, plus 0.2 m per unit of rotation)."""
        if self._table is None:
            Q = self.chain.random(self.rng, self.TABLE_SIZE)  # self.rng is independent of any target stream
            T, _ = self.chain.fk_jacobian_batch(Q, jacobian=False)
            F = _pose_features(T)
            self._table = (Q, F, np.einsum("ij,ij->i", F, F))
        Q, F, F2 = self._table
        d = F2 - 2.0 * (F @ _pose_features(target[None])[0])
        nearest = np.argpartition(d, self.TABLE_SEEDS)[: self.TABLE_SEEDS]
        return list(Q[nearest[np.argsort(d[nearest])]])

    def solve(self, target: Array, seed: Array) -> IKResult:
        chain = self.chain
        deadline = self.clock() + self.timeout
        pin, model, data, frame = chain._model()
        joint_jacobians, place, frame_jacobian, log6, local = self._pin_calls
        target = np.asarray(target, dtype=float)
        goal_pose = pin.SE3(target)
        k, bias, per_try = self._k, self._bias, self._per_try
        lower, upper = self._lower, self._upper  # ±inf for continuous joints: they wrap, once, at the end
        lower_l, upper_l = self._lower_l, self._upper_l
        eye = self._eye
        # Close enough to check: every component within 0.99·tolerance is possible once ‖e‖² < 6·(0.99·tol)².
        near = 6.0 * (0.99 * self.tolerance) ** 2
        dposv, dsyrk = self._lapack_dposv, self._blas_dsyrk
        maximum, minimum = np.maximum, np.minimum
        q = np.minimum(np.maximum(np.asarray(seed, dtype=float), lower), upper)
        iterations = 0
        best_q, best_err = q, math.inf
        restarts: list[Array] | None = None
        while True:
            # Local frame: J is the tip's body Jacobian and e = log6(T⁻¹·target) the body twist to the
            # target, both rotated by Rᵀ from the base frame, so JᵀJ and Jᵀe (and the step) are the same.
            joint_jacobians(model, data, q)  # forward kinematics and every joint's Jacobian
            e = log6(place(model, data, frame).actInv(goal_pose)).vector
            J = frame_jacobian(model, data, frame, local)
            err = float(e.dot(e))
            try_q, try_err, since = q, err, 0
            ql = q.tolist()
            touching = any(map(float.__le__, ql, lower_l)) or any(map(float.__ge__, ql, upper_l))  # a joint at a limit
            for _ in range(per_try):
                if err < near:
                    done = self._converged(q, target, goal_pose, iterations)
                    if done is not None:
                        return done
                iterations += 1
                # A = JᵀJ + λI in one BLAS call (upper triangle, which is all dposv reads); J.T is Fortran-ordered.
                A = dsyrk(1.0, J.T, beta=k * err + bias, c=eye)
                g = J.T.dot(e)
                _, dq, info = dposv(A, g)
                if info:
                    dq = np.linalg.lstsq(A + np.triu(A, 1).T, g, rcond=None)[0]
                if touching:
                    blocked = ((q <= lower) & (dq < 0)) | ((q >= upper) & (dq > 0))
                    if blocked.any():
                        # Joints held at a limit leave the step; the others re-plan without them.
                        A[blocked, :] = 0.0
                        A[:, blocked] = 0.0
                        A[blocked, blocked] = 1.0
                        g[blocked] = 0.0
                        _, dq, info = dposv(A, g)
                        if info:
                            dq = np.linalg.lstsq(A + np.triu(A, 1).T, g, rcond=None)[0]
                q_raw = q + dq
                q = minimum(maximum(q_raw, lower), upper)
                ql = q.tolist()
                touching = ql != q_raw.tolist() or (
                    touching and (any(map(float.__le__, ql, lower_l)) or any(map(float.__ge__, ql, upper_l)))
                )
                # Every step is taken, also one that raises the error (λ then grows with it): a
                # monotone search stalls in the curved valleys near singular poses, this one crosses them.
                joint_jacobians(model, data, q)
                e = log6(place(model, data, frame).actInv(goal_pose)).vector
                J = frame_jacobian(model, data, frame, local)
                err = float(e.dot(e))
                if err < try_err * self.PROGRESS:
                    since = 0
                else:
                    since += 1
                    if since >= self.STALL:
                        break  # no progress: a local minimum, or pinned at a limit
                if err < try_err:
                    try_q, try_err = q, err
            if try_err < best_err:
                best_q, best_err = try_q, try_err
            if err < near:
                done = self._converged(q, target, goal_pose, iterations)
                if done is not None:
                    return done
            if self.clock() > deadline:
                return self._result(self._wrap(best_q), target, iterations, "timeout")
            if restarts is None:
                restarts = self._restart_seeds(target)
            q = restarts.pop(0) if restarts else self.rng.uniform(chain.lower, chain.upper)

    def _wrap(self, q: Array) -> Array:
        """Continuous joints into [-π, π)."""
        if self._wrap_any:
            q = np.where(self.chain.continuous, (q + math.pi) % (2 * math.pi) - math.pi, q)
        return q

    def _converged(self, q: Array, target: Array, goal_pose: Any, iterations: int) -> IKResult | None:
        """The answer if q passes verify() (Pinocchio's FK at q, as verify uses, in plain floats: the
        base-frame twist error [p_target − p; R·log3(Rᵀ R_target)] per component within 0.99·tolerance,
        a margin for other FK implementations, and the limits); None to keep iterating."""
        pin, model, data, frame = self.chain._model()
        q = self._wrap(q)
        pin.forwardKinematics(model, data, q)  # data may hold a rejected step's pose
        M = pin.updateFramePlacement(model, data, frame)
        ep = (target[:3, 3] - M.translation).tolist()
        er = M.rotation.dot(pin.log3(M.actInv(goal_pose).rotation)).tolist()
        ql = q.tolist()
        tol = 0.99 * self.tolerance
        ok = (
            max(map(abs, ep + er)) <= tol
            and all(map(math.isfinite, ql))
            and all(lo - 1e-9 <= x <= hi + 1e-9 or c for x, lo, hi, c in zip(ql, self._limits_l[0], self._limits_l[1], self._limits_l[2]))
        )
        if not ok:
            return None
        pos = math.sqrt(ep[0] * ep[0] + ep[1] * ep[1] + ep[2] * ep[2])
        rot = math.sqrt(er[0] * er[0] + er[1] * er[1] + er[2] * er[2])
        return IKResult(True, q, pos, rot, iterations)

    def solve_batch(self, targets: Array, seeds: Array) -> list[IKResult]:
        """All targets at once: the same algorithm with numpy over every unsolved target per step.

        Each target keeps its own damping, stall counter and restarts; the whole call stops when
        every target is solved or after `timeout` seconds per target. BLAS runs single-threaded
        here: its matrices are tiny, and OpenBLAS threads only add overhead (10x on a busy machine).
        """
        from threadpoolctl import threadpool_limits

        with threadpool_limits(limits=1, user_api="blas"):
            return self._solve_batch(targets, seeds)

    def _solve_batch(self, targets: Array, seeds: Array) -> list[IKResult]:
        targets = np.asarray(targets, dtype=float)
        seeds = np.asarray(seeds, dtype=float)
        chain = self.chain
        N, n = seeds.shape
        if targets.shape != (N, 4, 4) or n != chain.n:
            return super().solve_batch(targets, seeds)
        deadline = self.clock() + self.timeout * N
        k = float(self.opts["error_damping"])
        bias = float(self.opts["damping_bias"])
        per_try = int(self.opts["max_iterations_per_try"])
        goal = (self.tolerance * 0.5) ** 2
        lower, upper, cont = chain.lower, chain.upper, chain.continuous
        eye = np.eye(n)

        def project(Q: Array) -> Array:
            wrapped = (Q + math.pi) % (2 * math.pi) - math.pi
            return np.where(cont, wrapped, np.clip(Q, lower, upper))

        Q = project(seeds.copy())
        iterations = np.zeros(N, dtype=int)
        solved = np.zeros(N, dtype=bool)
        idx = np.arange(N)  # unsolved targets
        T, J = chain.fk_jacobian_batch(Q)
        E = pose_error_batch(T, targets)
        err = np.einsum("ij,ij->i", E, E)
        mu = np.ones(N)
        rejected = np.zeros(N, dtype=int)
        tries = np.zeros(N, dtype=int)
        restarts = np.zeros(N, dtype=int)  # per target: which table seed comes next
        while idx.size and self.clock() < deadline:
            done = err < goal
            solved[idx[done]] = True
            keep = ~done
            idx, J, E, err, mu, rejected, tries = idx[keep], J[keep], E[keep], err[keep], mu[keep], rejected[keep], tries[keep]
            if idx.size <= self.SCALAR_TAIL:
                break  # a few stubborn targets: numpy's per-call overhead makes the scalar loop faster
            iterations[idx] += 1
            tries += 1
            A = J.transpose(0, 2, 1) @ J + ((mu * (k * err + bias))[:, None, None] * eye)
            g = np.einsum("mji,mj->mi", J, E)
            q = Q[idx]
            dq = np.linalg.solve(A, g[..., None])[..., 0]
            blocked = ((q <= lower) & (dq < 0)) | ((q >= upper) & (dq > 0))
            rows = blocked.any(axis=1)
            if rows.any():  # joints held at a limit leave the step, as in solve()
                free = ~blocked[rows]
                A_b = A[rows] * (free[:, :, None] & free[:, None, :]) + blocked[rows][:, :, None] * eye
                dq[rows] = np.linalg.solve(A_b, (g[rows] * free)[..., None])[..., 0]
            Q_new = project(q + dq)
            T_new, J_new = chain.fk_jacobian_batch(Q_new)
            E_new = pose_error_batch(T_new, targets[idx])
            err_new = np.einsum("ij,ij->i", E_new, E_new)
            better = err_new < err
            progress = better & (err_new < 0.5 * err)
            Q[idx[better]] = Q_new[better]
            J[better], E[better], err[better] = J_new[better], E_new[better], err_new[better]
            mu = np.where(better, 1.0, mu * 10.0)
            rejected = np.where(progress, 0, rejected + 1)
            restart = ((rejected >= 4) | (tries >= per_try)) & (err >= goal)
            if restart.any():
                r = idx[restart]
                Q[r] = self._batch_restart_seeds(targets[r], restarts[r])
                restarts[r] += 1
                T_r, J_r = chain.fk_jacobian_batch(Q[r])
                J[restart], E[restart] = J_r, pose_error_batch(T_r, targets[r])
                err[restart] = np.einsum("ij,ij->i", E[restart], E[restart])
                mu[restart], rejected[restart], tries[restart] = 1.0, 0, 0
        for i in idx:
            tail = self.solve(targets[i], Q[i])
            Q[i] = tail.q
            iterations[i] += tail.iterations
        ok, pos, rot = verify_batch(chain, Q, targets, self.tolerance)
        return [
            IKResult(bool(ok[i]), Q[i].copy(), float(pos[i]), float(rot[i]), int(iterations[i]), "" if ok[i] else "timeout")
            for i in range(N)
        ]


def _pose_features(T: Array) -> Array:
    """(N, 12) vectors whose distances compare poses: position in m, rotation matrix entries × 0.2 m."""
    return np.concatenate([T[:, :3, 3], 0.2 * T[:, :3, :3].reshape(-1, 9)], axis=1)
