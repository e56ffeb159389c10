"""`lm`: Levenberg–Marquardt with joint limits, error-scaled damping and random restarts.

Damping follows Sugihara (2011): λ = k·E + λ̄ with E = ‖e‖² the squared pose error, so steps
approach Gauss–Newton near a solution and shrink where the error is large. Every step is taken,
also one that raises the error (λ grows with it, as in rtb's ik_LM): a monotone search (reject,
raise λ, retry) crawls through the curved valleys around near-singular poses, which is where the
slowest 1 % of targets lie, and this one crosses them. Limits are enforced by projection, with
joints held at a limit taken out of the step; continuous joints move freely and wrap into
[-π, π) in the answer.

Where tries start: a table of random configurations and their tip poses, grouped in 1024 cells
around 1024 of them (the centres), is built once per solver. The first try starts from the
caller's seed, or from a table pose near the target (the nearest of the cell whose centre is
nearest the target: two matrix-vector products) when it is nearer the target than the seed's
pose; the seed is then the second try. A try whose best error has not fallen by 30 % in STALL
iterations ends, and the solver restarts until the time budget is spent: from the 16 table poses
nearest the target in the 4 nearest cells (skipping the first try's), then uniform random ones.

The scalar loop works in the tip frame (Pinocchio's body Jacobian and log6 twist), about a dozen
Python-level calls per iteration; joint limits are checked on plain lists, and clamped with numpy
only when a step crossed one. An answer is accepted once its position and orientation error norms, read off the
loop's own twist, are each within 0.99·tolerance (so is every component of the twist error,
which is what the protocol asks).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from armtool.ik.solver import Array, IKResult, Solver, rotation_error, verify_batch

if TYPE_CHECKING:
    from numpy.typing import NDArray


_THREADPOOLS: Any = None  # see LevenbergMarquardt._threadpools


class LevenbergMarquardt(Solver):
    name = "lm"
    summary = "Levenberg–Marquardt with joint limits, error-scaled damping and random restarts (armtool's best)"
    options: ClassVar[dict[str, Any]] = {
        "error_damping": 0.03,
        "damping_bias": 1e-6,
        "max_iterations_per_try": 25,
    }
    SCALAR_TAIL = 16
    TAIL_TIMEOUTS = 4.0
    # Iterations without the try's best error falling by PROGRESS end a try. Shorter tries restart
    # sooner from a better pose: 8/5 -> 4/3 cut the mean iterations 9.4 -> 8.1 (UR5), 10.2 -> 8.7
    # (xArm6), 8.0 -> 7.0 (Panda) on 1000 targets each; over 5000 more per arm (5 ms), 11 failures
    # in 20,000 (Panda, UR5, xArm6, Kinova) against 16.
    STALL = 3
    FIRST_STALL = 4  # from the caller's seed (or the first table pose)
    PROGRESS = 0.7
    TABLE_SIZE = 32768  # vs 4096: p99 iterations 59 -> 41 (Panda), 61 -> 54 (UR5)
    TABLE_SEEDS = 16
    RESTART_CELLS = 4  # cells searched for the restarts' TABLE_SEEDS poses
    BATCH_TABLE_SIZE = 1024  # restarts of many targets at once search a smaller table, by brute force
    BATCH_TABLE_SEEDS = 8
    START_CHUNK = 128  # targets per chunk of _start_from_table
    FAR = 1e-3  # ‖e‖² from the seed above which the nearest table pose may be nearer
    _table: tuple[Array, Array, Array] | None = None  # configurations, pose features, their squared norms
    FIRST_TABLE = 1024  # cells of the table for first tries: their centres are searched by brute force
    _scores: Array  # (FIRST_TABLE, 16): see _build_table

    def __init__(
        self, chain: Any, timeout: float = 0.005, tolerance: float = 1e-5, seed: int | None = 0, **options: Any
    ) -> None:
        super().__init__(chain, timeout, tolerance, seed, **options)
        import pinocchio as pin
        from scipy.linalg import blas, lapack

        self._lapack_dposv = lapack.dposv
        self._blas_dsyrk = blas.dsyrk
        # Per-solve constants, computed once: every microsecond counts at ~10 µs per iteration.
        frame_jacobian = pin.getFrameJacobian
        if chain.n == 1:  # eigenpy hands a 6x1 matrix back as a flat (6,) array; the steps need (6, 1)

            def frame_jacobian(*args: Any) -> Any:
                return pin.getFrameJacobian(*args).reshape(6, 1)

        self._pin_calls = (pin.computeJointJacobians, pin.updateFramePlacement, frame_jacobian, pin.log6, pin.LOCAL)
        cont = chain.continuous
        self._k = float(self.opts["error_damping"])
        self._bias = float(self.opts["damping_bias"])
        self._per_try = int(self.opts["max_iterations_per_try"])
        self._lower = np.where(cont, -np.inf, chain.lower)
        self._upper = np.where(cont, np.inf, chain.upper)
        self._lower_list = self._lower.tolist()
        self._upper_list = self._upper.tolist()
        self._lower_tol = np.where(cont, -np.inf, chain.lower - 1e-9).tolist()
        self._upper_tol = np.where(cont, np.inf, chain.upper + 1e-9).tolist()
        self._cont_idx = np.flatnonzero(cont).tolist()
        self._wrap_any = bool(cont.any())
        self._eye = np.asfortranarray(np.eye(chain.n))
        self._build_table()  # now, not inside a timed solve
        self._threadpools()  # and scan the BLAS libraries now, not inside a timed solve_batch

    def _batch_nearest(self, targets: Array) -> NDArray[np.intp]:
        """(m, BATCH_TABLE_SEEDS) indices of the first BATCH_TABLE_SIZE table configurations nearest
        each target, nearest first."""
        assert self._table is not None
        F2 = self._table[2][: self.BATCH_TABLE_SIZE]
        # Squared distance up to |f|², which does not change the order; −2F is scaled by a power of
        # two (exact), so f·(−2F) is bit for bit −2·(f·F) in one pass over the (m, 1024) product fewer.
        d = F2 + _pose_features(targets) @ self._batch_minus_2F.T
        order = np.argpartition(d, self.BATCH_TABLE_SEEDS, axis=1)[:, : self.BATCH_TABLE_SEEDS]
        return np.take_along_axis(order, np.argsort(np.take_along_axis(d, order, axis=1), axis=1), axis=1)

    def _build_table(self) -> None:
        """TABLE_SIZE random configurations and their tip poses (self.rng: independent of any target
        stream), and the matrices that score the first FIRST_TABLE of them (the cells' centres)
        and each cell's poses against a target, for first tries and restarts."""
        from scipy.spatial import cKDTree

        Q = self.chain.random(self.rng, self.TABLE_SIZE)
        T, _ = self.chain.fk_jacobian_batch(Q, jacobian=False)
        F = _pose_features(T)
        F2 = np.einsum("ij,ij->i", F, F)
        self._table = (Q, F, F2)
        # score_i = f·F_i − |F_i|²/2 is largest for the table pose nearest the target (|f − F_i|² =
        # |f|² − 2·score_i), and f·F_i is one product with the target's 4×4 entries in row order:
        # positions weigh 1, rotation entries 0.2² (features scale them by 0.2), entry [3, 3] = 1
        # carries −|F_i|²/2. One matrix-vector product per lookup, no work on the target.
        G = np.zeros((len(Q), 4, 4))
        G[:, :3, :3] = 0.04 * T[:, :3, :3]
        G[:, :3, 3] = T[:, :3, 3]
        G[:, 3, 3] = -0.5 * F2
        scores = G.reshape(len(Q), 16)
        m = self.FIRST_TABLE
        self._scores = np.asfortranarray(scores[:m])  # column-major: its product takes ~10 % less time
        # The first FIRST_TABLE poses are cells' centres: every table pose joins the cell of the
        # centre nearest it (a centre is in its own cell), and a first try searches the cell of the
        # centre nearest the target (~32 poses, one more small product): never farther than the
        # nearest centre, and mostly much nearer.
        _, cell = cKDTree(F[:m]).query(F)  # exact: ~0.1 s, where a brute-force assignment took ~0.5 s
        order = np.argsort(cell, kind="stable")
        self._cell_order = order
        self._cell_scores = np.ascontiguousarray(scores[order])
        bounds = np.searchsorted(cell[order], np.arange(m + 1))
        self._cell_bounds = bounds.tolist()
        # The same cells padded to one width for the batch (a padding row scores −inf: its entry
        # [3, 3] meets the target's 1).
        width = int(np.diff(bounds).max())
        slot = np.arange(len(Q)) - bounds[cell[order]]
        self._cell_padded = np.full((m, width), -1, dtype=np.intp)
        self._cell_padded[cell[order], slot] = order
        self._cell_padded_scores = np.zeros((m, width, 16))
        self._cell_padded_scores[:, :, 15] = -np.inf
        self._cell_padded_scores[cell[order], slot] = self._cell_scores
        # For _batch_nearest: −2 × the pose features of the first BATCH_TABLE_SIZE table poses.
        self._batch_minus_2F: Array = -2.0 * F[: self.BATCH_TABLE_SIZE]

    def _nearest(self, target: Array) -> tuple[Array, float]:
        """A table configuration whose pose is near the target, and the squared feature distance of
        its pose to the target's: the nearest pose in the cell of the centre nearest the target
        (one 1024×16 product over the centres, one ~30×16 product over the cell's poses).

        The cell search starts, on a random target, median 5 -> 4 iterations (UR5, xArm6: 6 -> 5)
        and mean 10-20 % fewer than the nearest centre alone did. Not the k-d tree: its query
        starts nearer still but costs ~60 µs of wall time per call (scipy's per-call overhead,
        whatever the table's size), more than the iterations it saves."""
        t = target.reshape(16)
        c = int(self._scores.dot(t).argmax())
        a, b = self._cell_bounds[c], self._cell_bounds[c + 1]
        scores = self._cell_scores[a:b].dot(t)
        j = int(scores.argmax())
        p = target[:3, 3]
        i = self._cell_order[a + j]
        return self._table[0][i], float(p.dot(p)) + 0.12 - 2.0 * float(scores[j])  # type: ignore[index]

    def _restart_seeds(self, target: Array) -> list[Array]:
        """The TABLE_SEEDS table configurations whose tip poses are nearest the target (position, plus
        0.2 m per unit of rotation matrix entry), nearest first, from the cells of the RESTART_CELLS
        centres nearest the target (~130 poses): one 1024×16 and one ~130×16 product.

        Restarts are where the hard targets are: a brute-force search over 4096 poses cost a third
        of the query's time but left 1 in 1000 xArm6 targets unsolved in 50 ms. The cells find the
        exact nearest pose for 84-89 % of targets and 16 poses within 1.07× (median, at most 1.32×)
        of the 16 nearest (Panda, UR5, xArm6; 300 targets each). One call costs what scipy's
        approximate k-d query did (~45 µs, timed alone); within solves, alternating with the k-d
        query on the same 1000 targets per arm (UR5, xArm6, Panda, xArm7, Kinova, SO-101): the
        same success and iterations, mean solve 1-5 % and p95 up to 15 % less time."""
        t = target.reshape(16)
        centres = np.argpartition(self._scores.dot(t), -self.RESTART_CELLS)[-self.RESTART_CELLS :]
        bounds = self._cell_bounds
        members = np.concatenate([np.arange(bounds[c], bounds[c + 1]) for c in centres.tolist()])
        scores = self._cell_scores[members].dot(t)
        k = min(self.TABLE_SEEDS, len(members))
        best = np.argpartition(scores, -k)[-k:]
        best = best[np.argsort(-scores[best])]
        assert self._table is not None
        return list(self._table[0][self._cell_order[members[best]]])

    def solve(self, target: Array, seed: Array) -> IKResult:
        return self._solve(target, seed, self.timeout)

    def _solve(self, target: Array, seed: Array, timeout: float, from_seed: bool = True) -> IKResult:
        """solve() with its own budget; from_seed=False skips the try from the seed (the batch's tail:
        its seeds are where a batch try just stalled) and starts from the nearest table pose.

        The first try starts from the seed or, when the table pose _nearest() finds is nearer the
        target than the seed's pose, from that table pose, and then the seed is the second try
        (from the mid-range seed, a random target's median iterations fall from 7-9 to 4-5); the
        restarts from the table then skip that pose.
        """
        clock = self.clock
        deadline = clock() + timeout
        pin, model, data, frame = self.chain._model()
        joint_jacobians, place, frame_jacobian, log6, local = self._pin_calls
        target = np.asarray(target, dtype=float)
        goal = pin.SE3(target)
        k, bias, per_try = self._k, self._bias, self._per_try
        lower, upper = self._lower, self._upper  # ±inf for continuous joints: they wrap, once, at the end
        eye = self._eye
        # Close enough to check: both norms within 0.99·tolerance is possible once ‖e‖² < 2·(0.99·tol)².
        near = 2.0 * (0.99 * self.tolerance) ** 2
        dposv, dsyrk = self._lapack_dposv, self._blas_dsyrk
        maximum, minimum = np.maximum, np.minimum
        lower_list, upper_list, le = self._lower_list, self._upper_list, float.__le__
        progress = self.PROGRESS
        q = minimum(maximum(np.asarray(seed, dtype=float), lower), upper)
        starts: list[Array] = []  # where the next tries start; _restart_seeds fills it when empty
        table_tries = False  # whether the table's restart seeds have been queued
        tried: list[float] = []  # the table pose of the first try, as a list: its restarts skip it
        patience = self.FIRST_STALL
        fresh = False  # whether D, e and err below are already those of q
        if from_seed:
            joint_jacobians(model, data, q)
            D = place(model, data, frame).actInv(goal)
            e = log6(D).vector
            err = float(e.dot(e))
            fresh = True
            if err > self.FAR:
                # The nearer pose first, by the table's feature distance: |Δp|² + 0.2²·‖R − R_target‖²
                # with ‖R − R_target‖² = 4(1 − cos θ), θ = ‖log3‖ = the norm of e's rotation part.
                q_table, d2_table = self._nearest(target)
                t, w = D.translation, e[3:]
                if d2_table < float(t.dot(t)) + 0.16 * (1.0 - math.cos(math.sqrt(float(w.dot(w))))):
                    starts, q, fresh, tried = [q], q_table, False, q_table.tolist()
        else:
            starts, table_tries = self._restart_seeds(target), True
            q = starts.pop(0)
            patience = self.STALL
        iterations = steps = since = 0
        best_q, best_err = q, math.inf
        try_q, try_err = q, math.inf
        ql = q.tolist()
        while True:
            if fresh:
                fresh = False
            else:
                # Local frame: J is the tip's body Jacobian and e = log6(T⁻¹·target) the body twist to
                # the target, both rotated by Rᵀ from the base frame, so JᵀJ and Jᵀe (and the step) are the same.
                joint_jacobians(model, data, q)  # forward kinematics and every joint's Jacobian
                D = place(model, data, frame).actInv(goal)
                e = log6(D).vector
                err = float(e.dot(e))
            if err < near:
                done = self._converged(q, D, e, iterations)
                if done is not None:
                    return done
            # A try ends when its best error has not fallen by PROGRESS in `patience` steps, or
            # after max_iterations_per_try steps. Every step is taken, also one that raises the
            # error (λ then grows with it): a monotone search stalls in the curved valleys near
            # singular poses, this one crosses them.
            if err < try_err * progress:
                since = 0
            else:
                since += 1
            if err < try_err:
                try_q, try_err = q, err
            if since >= patience or steps >= per_try:
                if try_err < best_err:
                    best_q, best_err = try_q, try_err
                if clock() > deadline:
                    return self._result(self._wrap(best_q), target, iterations, "timeout")
                if not starts and not table_tries:
                    starts, table_tries = [s for s in self._restart_seeds(target) if s.tolist() != tried], True
                q = starts.pop(0) if starts else self.rng.uniform(self.chain.lower, self.chain.upper)
                ql = q.tolist()
                patience, steps, since, try_err = self.STALL, 0, 0, math.inf
                continue
            iterations += 1
            steps += 1
            Jt = frame_jacobian(model, data, frame, local).T  # Fortran-ordered, as dsyrk wants
            # A = JᵀJ + λI in one BLAS call (upper triangle, which is all dposv reads).
            damping = k * err + bias
            A = dsyrk(1.0, Jt, damping, eye)  # positional: f2py parses keywords in ~1.7k more instructions
            g = Jt.dot(e)
            _, dq, info = dposv(A, g)
            if info:
                dq = np.linalg.lstsq(A + np.triu(A, 1).T, g, rcond=None)[0]
            q_next = q + dq
            ql_next = q_next.tolist()
            # Within the limits (the common case) takes two comparisons of plain lists; a clamp
            # with numpy costs two calls and a list more.
            if not (all(map(le, lower_list, ql_next)) and all(map(le, ql_next, upper_list))):  # crossed a limit
                q_raw, ql_raw = q_next, ql_next
                q_next = minimum(maximum(q_raw, lower), upper)
                ql_next = q_next.tolist()
                # Joints held at a limit (the step pushes them further out) leave the step, and
                # the others re-plan without them; the rest of the step is clamped.
                blocked = [
                    i for i, (before, after, raw) in enumerate(zip(ql, ql_next, ql_raw)) if before == after != raw
                ]
                if blocked:
                    # Their Jacobian columns zeroed: A's rows and columns for them hold λ on the
                    # diagonal only and g's entries are 0, so their step is 0 (J is this step's own).
                    for i in blocked:
                        Jt[i] = 0.0
                    A = dsyrk(1.0, Jt, damping, eye)
                    g = Jt.dot(e)
                    _, dq, info = dposv(A, g)
                    if info:
                        dq = np.linalg.lstsq(A + np.triu(A, 1).T, g, rcond=None)[0]
                    q_next = minimum(maximum(q + dq, lower), upper)
                    ql_next = q_next.tolist()
            q, ql = q_next, ql_next

    def _wrap(self, q: Array) -> Array:
        """Continuous joints into [-π, π)."""
        if self._wrap_any:
            q = np.where(self.chain.continuous, (q + math.pi) % (2 * math.pi) - math.pi, q)
        return q

    def _converged(self, q: Array, D: Any, e: Array, iterations: int) -> IKResult | None:
        """The answer if q passes verify() with a margin, else None to keep iterating.

        D = T(q)⁻¹·target and e = log6(D): ‖D.translation‖ = ‖p_target − p‖ and ‖e[3:]‖ = ‖log3(Rᵀ
        R_target)‖ are the norms of verify()'s position and rotation errors; each must be within
        0.99·tolerance (a margin for other FK implementations), and q within the limits.
        """
        t = D.translation
        w = e[3:]
        pos2, rot2 = float(t.dot(t)), float(w.dot(w))
        tol2 = (0.99 * self.tolerance) ** 2
        if not (pos2 <= tol2 and rot2 <= tol2):
            return None
        q = self._wrap(q)
        ql = q.tolist()
        ok = (
            all(map(math.isfinite, ql))
            and all(map(float.__le__, self._lower_tol, ql))  # within_limits(), on lists
            and all(map(float.__le__, ql, self._upper_tol))
        )
        return IKResult(True, q, math.sqrt(pos2), math.sqrt(rot2), iterations) if ok else None

    def solve_batch(self, targets: Array, seeds: Array) -> list[IKResult]:
        """All targets at once: the same algorithm with numpy over every unsolved target per step.

        Each target keeps its own stall counter and restarts; when SCALAR_TAIL or fewer remain,
        solve() finishes them one by one (they share what is left of the budget, up to
        TAIL_TIMEOUTS timeouts each). The whole call stops when every target is solved or after
        `timeout` seconds per target. BLAS runs single-threaded here: its matrices are tiny, and
        OpenBLAS threads only add overhead (10x on a busy machine).
        """
        with self._threadpools().limit(limits=1, user_api="blas"):
            return self._solve_batch(targets, seeds)

    @staticmethod
    def _threadpools() -> Any:
        """threadpoolctl's view of the loaded BLAS libraries, scanned once per process: a scan on every
        call (threadpool_limits) cost 3-25 ms with the peers' libraries loaded, 25 % of a 1000-target batch."""
        global _THREADPOOLS
        if _THREADPOOLS is None:
            from threadpoolctl import ThreadpoolController

            _THREADPOOLS = ThreadpoolController()
        return _THREADPOOLS

    def _start_from_table(self, targets: Array, Q: Array) -> NDArray[np.intp]:
        """Replace, in place, the rows of Q whose table pose from the cell search of _nearest is nearer
        their target than their own pose; 1 for those rows whose start is their cell's centre
        (the first table pose their restarts would take), else 0.

        The targets go through in chunks of START_CHUNK: for 1000 at once the centres' scores
        (8 MB) and the gathered cells' rows (14 MB) were allocated, page-faulted and evicted on
        every call; a chunk's fit in the cache (the same products, row by row)."""
        assert self._table is not None
        N = targets.shape[0]
        flat = targets.reshape(N, 16)
        centre = np.empty(N, dtype=np.intp)
        best = np.empty(N, dtype=np.intp)
        top = np.empty(N)  # each target's best cell score
        for a in range(0, N, self.START_CHUNK):
            f = flat[a : a + self.START_CHUNK]
            c = (f @ self._scores.T).argmax(axis=1)  # (chunk, FIRST_TABLE) scores, as in _nearest
            scores = np.einsum("nkj,nj->nk", self._cell_padded_scores[c], f)
            j = scores.argmax(axis=1)
            centre[a : a + len(f)] = c
            best[a : a + len(f)] = self._cell_padded[c, j]
            top[a : a + len(f)] = scores[np.arange(len(f)), j]
        p = targets[:, :3, 3]
        d2_table = np.einsum("ij,ij->i", p, p) + 0.12 - 2.0 * top
        T, _ = self.chain.fk_jacobian_batch(Q, jacobian=False)
        diff = targets[:, :3, :] - T[:, :3, :]
        d2_seed = np.einsum("ij,ij->i", diff[:, :, 3], diff[:, :, 3]) + 0.04 * np.einsum(
            "ijk,ijk->i", diff[:, :, :3], diff[:, :, :3]
        )
        use = d2_table < d2_seed
        Q[use] = np.minimum(np.maximum(self._table[0][best[use]], self._lower), self._upper)
        return np.asarray(use & (best == centre), dtype=np.intp)

    def _solve_batch(self, targets: Array, seeds: Array) -> list[IKResult]:
        targets = np.asarray(targets, dtype=float)
        seeds = np.asarray(seeds, dtype=float)
        chain = self.chain
        N, n = seeds.shape
        if targets.shape != (N, 4, 4) or n != chain.n:
            return super().solve_batch(targets, seeds)
        deadline = self.clock() + self.timeout * N
        k, bias, per_try, progress = self._k, self._bias, self._per_try, self.PROGRESS
        near = 2.0 * (0.99 * self.tolerance) ** 2
        accept = (0.99 * self.tolerance) ** 2
        lower, upper = self._lower, self._upper
        Q = np.minimum(np.maximum(seeds, lower), upper)  # answers, written back as targets finish
        iterations = np.zeros(N, dtype=int)
        restarts = np.zeros(N, dtype=int)  # per target: which table seed comes next
        nearest = np.zeros((N, self.BATCH_TABLE_SEEDS), dtype=int)
        assert self._table is not None
        # The active (unsolved) targets, configuration index last ("SoA"): every numpy call works
        # on contiguous rows of length m, and the whole step is one FK + one batched solve.
        idx = np.arange(N)
        Qa = Q.copy()
        # First tries from the nearest of FIRST_TABLE table poses where it is nearer the target than
        # the seed's pose, as in solve(); their restarts then skip that pose (the nearest of the
        # same rows). The seed's pose distance is the same feature distance as the table's.
        skip = self._start_from_table(targets, Qa)
        # Everything kept per active target is in four arrays, so that dropping the finished ones
        # is four fancy indexings (with this step's Jt, e, err: seven), not ten: idx, Qa, the
        # targets' rotations and positions (12, m), and the stall state (4, m): the try's best
        # error, steps since it last fell by PROGRESS, steps in the try, and the try's patience
        # (FIRST_STALL, then STALL).
        goal = np.ascontiguousarray(np.concatenate([targets[:, :3, :3].reshape(N, 9), targets[:, :3, 3]], axis=1).T)
        state = np.array([[np.inf], [0.0], [0.0], [float(self.FIRST_STALL)]]).repeat(N, axis=1)
        fresh = np.array([[np.inf], [0.0], [0.0], [float(self.STALL)]])  # a restarted try's state
        try_err, since, tries, patience = state
        step, tail = 0, False  # every active target takes one iteration per step: its count is the step's
        while self.clock() < deadline:
            R, p, Jt = chain.fk_jacobian_soa(Qa)
            assert Jt is not None
            e = _pose_error_soa(R, p, goal[:9].reshape(3, 3, -1), goal[9:])
            err = np.einsum("im,im->m", e, e)
            close = (err < near).nonzero()[0]
            if close.size:
                ec = e[:, close]
                done = close[
                    (np.einsum("im,im->m", ec[:3], ec[:3]) <= accept)
                    & (np.einsum("im,im->m", ec[3:], ec[3:]) <= accept)
                ]
                if done.size:
                    finished = idx[done]
                    Q[finished] = Qa[done]
                    iterations[finished] = step
                    keep = np.ones(idx.size, dtype=bool)
                    keep[done] = False
                    idx, Qa, Jt, e, err = idx[keep], Qa[keep], Jt[..., keep], e[:, keep], err[keep]
                    goal, state = goal[:, keep], state[:, keep]
                    try_err, since, tries, patience = state
            if idx.size <= self.SCALAR_TAIL:
                tail = True
                break  # a few stubborn targets: numpy's per-call overhead makes the scalar loop faster
            step += 1
            # Stall bookkeeping as in solve(): a try ends when its best error has not fallen by
            # PROGRESS in its patience's steps, or after max_iterations_per_try steps.
            since += 1
            since[err < progress * try_err] = 0
            np.minimum(try_err, err, out=try_err)
            tries += 1
            # Every step is taken (non-monotone, as in solve()).
            # JᵀJ with the configuration index last, as its inputs: einsum then runs unbuffered
            # (half the time of "->mjk" at m = 20 and 1000, the same numbers); + λI on the diagonal only.
            A_soa = np.einsum("rjm,rkm->jkm", Jt, Jt)
            A_soa.reshape(n * n, -1)[:: n + 1] += k * err + bias
            A = A_soa.transpose(2, 0, 1)
            g = np.einsum("rjm,rm->mj", Jt, e)
            dq = np.linalg.solve(A, g[..., None])[..., 0]
            blocked = ((Qa <= lower) & (dq < 0)) | ((Qa >= upper) & (dq > 0))
            rows = blocked.any(axis=1).nonzero()[0]
            if rows.size:  # joints held at a limit leave the step, as in solve()
                b = blocked[rows]
                free = ~b
                A_b = A[rows] * (free[:, :, None] & free[:, None, :]) + b[:, :, None] * self._eye
                dq[rows] = np.linalg.solve(A_b, (g[rows] * free)[..., None])[..., 0]
            Qa += dq
            np.maximum(Qa, lower, out=Qa)
            np.minimum(Qa, upper, out=Qa)
            restart = ((since >= patience) | (tries >= per_try)).nonzero()[0]
            if restart.size:
                r = idx[restart]
                first = r[restarts[r] == 0]
                if first.size:  # nearest table poses, computed once per target on its first restart
                    nearest[first] = self._batch_nearest(targets[first])
                count = restarts[r] + skip[r]
                use = count < self.BATCH_TABLE_SEEDS
                seeds_r = self._table[0][nearest[r, np.minimum(count, self.BATCH_TABLE_SEEDS - 1)]]
                if not use.all():  # table seeds used up: uniform random ones
                    seeds_r[~use] = self.rng.uniform(chain.lower, chain.upper, size=(int((~use).sum()), n))
                Qa[restart] = np.minimum(np.maximum(seeds_r, lower), upper)
                restarts[r] += 1
                state[:, restart] = fresh
        Q[idx] = Qa
        iterations[idx] = step
        if tail:
            # The hardest few share what is left of the call's budget, up to TAIL_TIMEOUTS
            # timeouts each: one unreachable target must not hold up the whole batch.
            for j, i in enumerate(idx):
                left = (deadline - self.clock()) / (idx.size - j)
                res = self._solve(
                    targets[i], Q[i], min(self.TAIL_TIMEOUTS * self.timeout, max(left, 0.0)), from_seed=False
                )
                Q[i] = res.q
                iterations[i] += res.iterations
        Q = self._wrap(Q)
        ok, pos, rot = verify_batch(chain, Q, targets, self.tolerance)
        # Plain Python values per row: indexing numpy arrays 1000 times costs more than the solve's last steps.
        return [
            IKResult(o, q, p, r, i, "" if o else "timeout")
            for o, q, p, r, i in zip(ok.tolist(), Q, pos.tolist(), rot.tolist(), iterations.tolist())
        ]


def _pose_error_soa(R: Array, p: Array, Rt: Array, pt: Array) -> Array:
    """pose_error_batch with the configuration index last: (6, m) [p_target − p; log(R_target Rᵀ)]
    for R (3,3,m), p (3,m) and targets Rt (3,3,m), pt (3,m); the same formula as verify_batch's."""
    M = np.einsum("ikm,jkm->ijm", Rt, R)
    e = np.empty((6, R.shape[2]))
    np.subtract(pt, p, out=e[:3])
    v = e[3:]
    np.subtract(M[2, 1], M[1, 2], out=v[0])
    np.subtract(M[0, 2], M[2, 0], out=v[1])
    np.subtract(M[1, 0], M[0, 1], out=v[2])
    v *= 0.5
    cos = np.minimum(np.maximum((M[0, 0] + M[1, 1] + M[2, 2] - 1.0) * 0.5, -1.0), 1.0)  # np.clip's wrapper: 2x the time
    sin = np.sqrt(np.einsum("im,im->m", v, v))
    angle = np.arctan2(sin, cos)
    v *= np.where(sin > 1e-9, angle / np.maximum(sin, 1e-300), 1.0)
    for i in ((sin <= 1e-9) & (cos < 0)).nonzero()[0]:  # a half turn: the axis from the diagonal
        v[:, i] = rotation_error(R[:, :, i], Rt[:, :, i])
    return e


def _pose_features(T: Array) -> Array:
    """(N, 12) vectors whose distances compare poses: position in m, rotation matrix entries × 0.2 m."""
    return np.concatenate([T[:, :3, 3], 0.2 * T[:, :3, :3].reshape(-1, 9)], axis=1)
