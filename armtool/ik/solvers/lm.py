"""`lm`: Levenberg–Marquardt with joint limits, error-scaled damping and restarts from a table of poses.

Damping follows Sugihara (2011): λ = k·E + λ̄ with E = ‖e‖² the squared pose error, so steps
approach Gauss–Newton near a solution and shrink where the error is large. Every step is taken,
also one that raises the error (λ grows with it, as in rtb's ik_LM): a monotone search (reject,
raise λ, retry) crawls through the curved valleys around near-singular poses, which is where the
slowest 1 % of targets lie, and this one crosses them. Limits are enforced by projection, with
joints held at a limit taken out of the step; continuous joints move freely and wrap into
[-π, π) in the answer. The error e = [p_target − p; log(R_target Rᵀ)] is the one `verify()` checks,
in the base frame; an answer is accepted once its position and rotation norms are each within
0.99·tolerance (so is every component, which is what the protocol asks).

Where tries start: a table of random configurations and their tip poses, grouped in 1024 cells
around 1024 of them (the centres), built once per solver on first need. The first try starts
from the caller's seed, or from a table pose near the target (the nearest of the cell whose centre
is nearest the target) when it is nearer the target than the seed's pose and the seed's pose is
farther than FAR; the seed is then the second try. A try whose best error has not fallen by 30 %
in STALL iterations ends, and the solver restarts until the time budget is spent: from the 16
table poses nearest the target in the 4 nearest cells (skipping the first try's), then uniform
random ones.

The iterations, the table look-ups and the tries run compiled (`lm_kernel`, Numba); Python only
orders the restarts and watches the clock between groups of tries.
"""

from __future__ import annotations

import logging
import math
import os
from typing import TYPE_CHECKING, Any, ClassVar, NoReturn

import numpy as np

from armtool.errors import ArmtoolError
from armtool.ik.solver import Answer, Array, Solver
from armtool.ik.solvers import lm_kernel as kernel

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from armtool.model.chain import Chain

log = logging.getLogger(__name__)


class LevenbergMarquardt(Solver):
    name = "lm"
    summary = (
        "Levenberg–Marquardt with joint limits, error-scaled damping and restarts from a pose table (armtool's best)"
    )
    options: ClassVar[dict[str, Any]] = {
        "error_damping": 0.03,
        "damping_bias": 1e-6,
        "max_iterations_per_try": 25,
    }
    TAIL_TIMEOUTS = 4.0  # a batch's unsolved targets share its budget, up to this many timeouts each
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
    FIRST_TABLE = 1024  # cells of the table: their centres are searched by brute force
    RESTARTS_PER_CALL = 4  # tries per compiled call between looks at the clock (≤ ~0.1 ms)
    # Feature distance² (|Δp|² + 0.2²·‖ΔR‖²_F) from the seed's pose above which the table is asked
    # for a nearer start: below it (a path's next point, a near seed) the seed is used as it is.
    FAR = 1e-3

    def __init__(
        self,
        chain: Chain,
        timeout: float = 0.005,
        tolerance: float = 1e-5,
        seed: int | None = 0,
        *,
        lazy_table: bool = False,
        **options: Any,
    ) -> None:
        """lazy_table: build the table on first need rather than now (`traj`'s path steps start near
        their seed and rarely need it; SciPy is imported only to build it). Otherwise it is built
        here, so that no solve's budget pays for it."""
        super().__init__(chain, timeout, tolerance, seed, **options)
        n = chain.n
        self._n = n
        self._geometry = chain_geometry(chain)
        self._settings = np.array(
            [
                self.FIRST_STALL,
                self.STALL,
                self.PROGRESS,
                int(self.opts["max_iterations_per_try"]),
                float(self.opts["error_damping"]),
                float(self.opts["damping_bias"]),
                self.tolerance,
                self.FAR,
            ],
            dtype=float,
        )
        self._table: tuple[Array, Array, NDArray[np.int64], Array] | None = None
        self._NO_TABLE = (np.zeros((0, 16)), np.zeros((0, 16)), np.zeros(1, dtype=np.int64), np.zeros((0, n)))
        self._load_kernel()
        if not lazy_table:
            self.table()

    def _load_kernel(self) -> None:
        """Call each compiled entry point once on the mid-range pose (a one-pose table), so that loading
        (or, on the very first run, compiling) their machine code happens here, not inside a solve."""
        if compiled_on_disk() is False:
            log.warning("compiling lm's kernel with Numba (once: ~10-30 s; later runs load it from its cache)")
        n, mid = self._n, self.chain.mid()
        target = np.ascontiguousarray(self.chain.fk(mid))
        scores, bounds, table_q = np.zeros((1, 16)), np.array([0, 1], dtype=np.int64), mid[None].copy()
        out = np.empty(kernel.OUT_HEAD + 2 * n)
        kernel.first_tries(self._geometry, self._settings, scores, scores, bounds, table_q, target, mid, out)
        kernel.restart_rows(scores, scores, bounds, target, 1, 1, -1)
        kernel.run_tries(self._geometry, self._settings, target, table_q, self.STALL, out)

    # ---- the table ------------------------------------------------------------------------------
    def table(self) -> tuple[Array, Array, NDArray[np.int64], Array]:
        """(centre scores (FIRST_TABLE, 16), every pose's scores (TABLE_SIZE, 16) in cell order, cell
        bounds (FIRST_TABLE + 1,), configurations in cell order), built on first need.

        TABLE_SIZE random configurations (self.rng: independent of any target stream); a row's
        score f·F_i − |F_i|²/2 is largest for the table pose nearest the target (|f − F_i|² = |f|² −
        2·score_i), f·F_i being one product with the target's 4×4 entries in row order: positions
        weigh 1, rotation entries 0.2² (features scale them by 0.2), entry [3, 3] = 1 carries
        −|F_i|²/2. The first FIRST_TABLE poses are the cells' centres: every pose joins the cell
        of the centre nearest it, and a first try searches the cell of the centre nearest the
        target (~32 poses): never farther than the nearest centre, and mostly much nearer."""
        if self._table is None:
            from scipy.spatial import cKDTree  # here: a solve that never needs the table never imports SciPy

            Q = self.chain.random(self.rng, self.TABLE_SIZE)
            T = self.chain.fk_batch(Q)
            F = _pose_features(T)
            G = np.zeros((len(Q), 4, 4))
            G[:, :3, :3] = 0.04 * T[:, :3, :3]
            G[:, :3, 3] = T[:, :3, 3]
            G[:, 3, 3] = -0.5 * np.einsum("ij,ij->i", F, F)
            scores = G.reshape(len(Q), 16)
            m = self.FIRST_TABLE
            _, cell = cKDTree(F[:m]).query(F)  # exact: ~0.1 s, where a brute-force assignment took ~0.5 s
            order = np.argsort(cell, kind="stable")
            bounds = np.searchsorted(cell[order], np.arange(m + 1)).astype(np.int64)
            self._table = (
                np.ascontiguousarray(scores[:m]),
                np.ascontiguousarray(scores[order]),
                bounds,
                np.ascontiguousarray(Q[order]),
            )
        return self._table

    # ---- one target -----------------------------------------------------------------------------
    def prepare(self, target: Array, seed: Array) -> tuple[Array, Array]:
        """The target and seed as contiguous float arrays (a conversion only: `call` checks them)."""
        return np.ascontiguousarray(target, dtype=float), np.ascontiguousarray(seed, dtype=float)

    def call(self, prepared: tuple[Array, Array]) -> Array:
        """The solve: its inputs checked (the compiled loop reads them without bounds checks, and
        would clamp a NaN to a limit without a word), the first tries, then restarts until solved or
        out of time. Returns the kernel's `out` vector: [SOLVED or 0, iterations, best ‖e‖², q (the
        answer, continuous joints wrapped), best q]; `answer` reads it."""
        target, seed = prepared
        if target.shape != (4, 4) or seed.shape != (self._n,):
            self._refuse(target.shape, seed.shape)
        deadline = self.clock() + self.timeout
        out = np.empty(kernel.OUT_HEAD + 2 * self._n)
        tried = kernel.first_tries(self._geometry, self._settings, *self._table_or_none(), target, seed, out)
        if tried == kernel.NOT_FINITE:
            self._refuse()
        if self._table is None and (tried == kernel.NEED_TABLE or out[0] != kernel.SOLVED):
            deadline += self._build_table()  # lazy_table: the table's first build is no solve's budget
        if tried == kernel.NEED_TABLE:
            tried = kernel.first_tries(self._geometry, self._settings, *self.table(), target, seed, out)
        self._restarts(target, out, tried, deadline)
        return out

    def answer(self, raw: Array) -> Answer:
        n, head = self._n, kernel.OUT_HEAD
        if raw[0] == kernel.SOLVED:
            return Answer(raw[head : head + n].copy(), True, int(raw[1]))
        return Answer(raw[head : head + n].copy(), False, int(raw[1]), "timeout")

    def _refuse(
        self, target_shape: tuple[int, ...] | None = None, seed_shape: tuple[int, ...] | None = None
    ) -> NoReturn:
        """Raise the error for inputs the compiled loop must not read: wrong shapes, or not finite."""
        if target_shape is not None and seed_shape is not None:
            raise ArmtoolError(f"expected a 4x4 target and {self._n} seed values, got {target_shape} and {seed_shape}")
        raise ArmtoolError("target and seed must be finite numbers (NaN or inf given)")

    def _build_table(self) -> float:
        """Build the table now (lazy_table); the seconds it took."""
        start = self.clock()
        self.table()
        return self.clock() - start

    def _table_or_none(self) -> tuple[Array, Array, NDArray[np.int64], Array]:
        """The table, or an empty one while it is not built (first_tries then says if it needs it)."""
        if self._table is None:
            return self._NO_TABLE
        return self._table

    def _restarts(self, target: Array, out: Array, tried: int, deadline: float) -> None:
        """Go on from the first tries' result in `out` until solved or past the deadline: the table's
        poses nearest the target, then uniform random ones, RESTARTS_PER_CALL tries at a time. Leaves
        the result in `out`: the status, every try's iterations, and the answer (or the best q found)."""
        n, head = self._n, kernel.OUT_HEAD
        if out[0] == kernel.SOLVED:
            return
        iterations = int(out[1])
        best_err, best_q = float(out[2]), out[head + n :].copy()
        scores, cell_scores, bounds, table_q = self.table()
        rows = kernel.restart_rows(scores, cell_scores, bounds, target, self.RESTART_CELLS, self.TABLE_SEEDS, tried)
        starts = table_q[rows]
        taken = 0
        stall = self.STALL
        while self.clock() < deadline:
            if taken < len(starts):
                group = starts[taken : taken + self.RESTARTS_PER_CALL]
            else:
                group = self.rng.uniform(self.chain.lower, self.chain.upper, (self.RESTARTS_PER_CALL, n))
            taken += len(group)
            kernel.run_tries(self._geometry, self._settings, target, group, stall, out)
            iterations += int(out[1])
            if out[0] == kernel.SOLVED:
                out[1] = iterations
                return
            if out[2] < best_err:
                best_err, best_q = float(out[2]), out[head + n :].copy()
        out[1] = iterations
        out[head : head + n] = best_q

    # ---- many targets ---------------------------------------------------------------------------
    def prepare_batch(self, targets: Array, seeds: Array) -> tuple[Array, Array]:
        targets, seeds = self._batch_arrays(targets, seeds)
        return np.ascontiguousarray(targets), np.ascontiguousarray(seeds)

    def call_batch(self, prepared: tuple[Array, Array]) -> Array:
        """Every target's first tries, then the unsolved few restart one by one,
        sharing what is left of the call's budget (`timeout` per target), up to TAIL_TIMEOUTS
        timeouts each: one unreachable target must not hold up the whole batch. Returns one `out`
        row per target (see `call`); `answer_batch` reads them."""
        targets, seeds = prepared
        N, n, head = targets.shape[0], self._n, kernel.OUT_HEAD
        if targets.shape[1:] != (4, 4) or seeds.shape != (N, n):
            self._refuse(targets.shape[1:], seeds.shape[1:])
        scores, cell_scores, bounds, table_q = self.table()  # before the clock: lazy_table builds it here
        deadline = self.clock() + self.timeout * N
        outs = np.empty((N, head + 2 * n))
        first_tries, geometry, settings = kernel.first_tries, self._geometry, self._settings
        tried = [
            first_tries(geometry, settings, scores, cell_scores, bounds, table_q, t, s, out)
            for t, s, out in zip(targets, seeds, outs)
        ]
        if kernel.NOT_FINITE in tried:
            self._refuse()
        unsolved = np.flatnonzero(outs[:, 0] != kernel.SOLVED).tolist()
        for j, i in enumerate(unsolved):
            left = (deadline - self.clock()) / (len(unsolved) - j)
            budget = min(self.TAIL_TIMEOUTS * self.timeout, max(left, 0.0))
            self._restarts(targets[i], outs[i], int(tried[i]), self.clock() + budget)
        return outs

    def answer_batch(self, raw: Array) -> list[Answer]:
        n, head = self._n, kernel.OUT_HEAD
        Q = raw[:, head : head + n].copy()
        return [
            Answer(q, True, i) if solved else Answer(q, False, i, "timeout")
            for q, solved, i in zip(Q, (raw[:, 0] == kernel.SOLVED).tolist(), raw[:, 1].astype(int).tolist())
        ]


def compiled_on_disk() -> bool | None:
    """Whether Numba's cache holds lm's machine code (None: this Numba does not say)."""
    try:
        index: str = getattr(kernel.run_tries, "_cache")._cache_file._index_path  # noqa: B009 (private to Numba)
    except AttributeError:
        return None
    return os.path.exists(index)


def chain_geometry(chain: Chain) -> Array:
    """The chain as lm_kernel reads it: (n + 1, 19) rows of origin rotation (9), translation (3),
    axis (3), prismatic flag, lower and upper limit (±inf for continuous joints), continuous flag;
    the tip offset last."""
    rows = np.zeros((chain.n + 1, 19))
    for i, joint in enumerate(chain.joints):
        rows[i, :9] = joint.origin[:3, :3].reshape(9)
        rows[i, 9:12] = joint.origin[:3, 3]
        rows[i, 12:15] = joint.axis
        rows[i, 15] = 1.0 if joint.kind == "prismatic" else 0.0
        rows[i, 16] = -math.inf if joint.kind == "continuous" else joint.lower
        rows[i, 17] = math.inf if joint.kind == "continuous" else joint.upper
        rows[i, 18] = 1.0 if joint.kind == "continuous" else 0.0
    rows[chain.n, :9] = chain.tip_offset[:3, :3].reshape(9)
    rows[chain.n, 9:12] = chain.tip_offset[:3, 3]
    return rows


def _pose_features(T: Array) -> Array:
    """(N, 12) vectors whose distances compare poses: position in m, rotation matrix entries × 0.2 m."""
    return np.concatenate([T[:, :3, 3], 0.2 * T[:, :3, :3].reshape(-1, 9)], axis=1)
