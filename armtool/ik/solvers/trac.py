"""`trac`: TRAC-IK's design (Beeson & Ames, Humanoids 2015) in Python.

What TRAC-IK does (traclabs/trac_ik, `trac_ik_lib/src/trac_ik.cpp`, `kdl_tl.cpp`, `nlopt_ik.cpp`):
two solvers start from the seed on two threads and the first success wins.

(a) KDL-TL, KDL's Newton–Raphson with joint limits: per step Δq = J⁺Δ (KDL's truncated SVD
    pseudo-inverse, σ < 1e-5 dropped), then each joint that leaves its limits is wrapped by 2π
    back inside them when that fits (`try_jl_wrap`), else clamped; continuous joints are never
    limited. When a step leaves every joint where it was (|Δq| ≤ FLT_EPSILON: a fixed point
    against the limits), it jumps to a uniformly random configuration within the limits.
(b) NLOPT-IK, an SQP (NLopt's SLSQP) with joint bounds minimizing the squared twist error
    ‖Δ‖², started from the seed brought into the limits; bounds are the limits narrowed to
    seed ± 2π (seed ± 2π for continuous joints). An evaluation within the tolerance ends it;
    when SLSQP stops anywhere else it restarts from a random point within those bounds.

What is the same here: both solvers and their restarts, KDL's step and wrap-or-clamp, the
bounds, the objective, every answer normalized as TRAC-IK does (revolute joints moved by 2π
to the equivalent nearest the seed that is within the limits; to the middle of the limits for
the manipulability solve types), duplicates (within 1e-4 rad) dropped, and the solve types:

- `speed`: the first solution found;
- `distance`: search until the timeout, return the solution with the smallest Σ(q − seed)²;
- `manip1`: ... the largest penalty · Π σ_i(J) (= penalty · √det(JJᵀ) for n ≥ 6);
- `manip2`: ... the largest penalty · σ_min/σ_max;

with TRAC-IK's joint-limit penalty = max(0, 1 − exp(−Π_i (q_i − l_i)(u_i − q_i)/(u_i − l_i)²))
over the joints that have limits (it favours configurations away from the limits; without it the
raw manipulability can be larger at a solution that was not chosen).

What differs:
- Concurrency. Python threads share one interpreter lock, so the two solvers cannot run on two
  cores: they are interleaved in slices inside one budget, `nr_slice` Newton steps, then
  `sqp_slice` SQP evaluations (the Newton turns run from inside the SQP's objective, so SLSQP
  keeps its quasi-Newton state across turns). "Concurrent" in TRAC-IK's C++, interleaved here:
  the two split one timeout instead of each having all of it. Slices count iterations, not
  seconds, so how the two interleave does not depend on the machine's speed.
  The default split gives Newton about 85 % of the time (measured on Panda and UR5): a scipy
  SLSQP iteration costs ~30 µs and each run ~0.3 ms to start (NLopt: a few µs), so an SQP run
  from the seed needs 1–2 ms where Newton with restarts has usually finished. On Panda and UR5
  (500 targets, 5 ms, mid-range seed) an even split (`nr_slice=10, sqp_slice=6`) solved
  96–97 % with a median of ~1 ms; the defaults solve ~99 % with a median of ~0.6 ms.
- Stuck detection. Besides KDL-TL's "no joint moved", the Newton solver also restarts after
  `nr_patience` steps in which the error did not halve (oscillation between limits is the
  common way KDL wastes its budget; KDL-TL only notices exact fixed points).
- The SQP is scipy's SLSQP (`scipy.optimize.minimize`), with the analytic gradient −2·Jᵀ·Δ
  (exact for ‖Δ‖² with Δ = [p* − p; log(R* Rᵀ)], since θᵀ·J_log(θ) = θᵀ) where TRAC-IK uses a
  one-sided finite difference, and at most `sqp_max_iterations` per run (TRAC-IK: until the
  step is below FLT_EPSILON or the time is up).
- Repeatable answers. TRAC-IK draws restarts from rand() and races threads, so the same target
  can give a different answer each time. Here every solve draws its restarts from a stream
  derived from the solver's `seed` and the problem (target and seed bytes): solving the same
  problem twice gives the same answer unless the clock cuts the search at a different step
  (with `seed=None`, restarts come from one unseeded stream). Continuous joints restart within
  seed ± 2π (TRAC-IK's `runSolver`) in both solvers.

Success is our verdict: every component of [p* − p; log(R* Rᵀ)] within the tolerance, checked
by our own FK (`Solver.judge`), outside the solve.
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Callable, Iterator
from enum import Enum
from typing import Any, ClassVar

import numpy as np
import pinocchio as pin
from scipy.linalg import lapack

from armtool.errors import ArmtoolError
from armtool.ik.solver import Answer, Array, Solver
from armtool.model.chain import Chain

TWO_PI = 2.0 * math.pi
FLT_EPSILON = float(np.finfo(np.float32).eps)  # KDL-TL's "did not move" threshold
KDL_SVD_EPS = 1e-5  # ChainIkSolverVel_pinv: singular values below it are not inverted
SAME_SOLUTION = 1e-4  # TRAC-IK's myEqual: solutions closer than this (every joint) are one
PROGRESS = 0.5  # a Newton step makes progress when the error falls below this fraction of the try's best


class SolveType(str, Enum):
    SPEED = "speed"
    DISTANCE = "distance"
    MANIP1 = "manip1"
    MANIP2 = "manip2"


class _Stop(Exception):
    """The search is over: speed's first solution, or the time is up."""


class _Found(Exception):
    """The SQP reached a solution (solve types other than speed): restart it elsewhere."""


def squared_error(chain: Chain, target: Array, q: Array) -> tuple[float, Array, Array]:
    """‖Δ‖², its gradient −2·JᵀΔ, and Δ = [p* − p; log(R* Rᵀ)] (base frame) at q."""
    T, J = chain.fk_jacobian(q)
    e = np.empty(6)
    e[:3] = target[:3, 3] - T[:3, 3]
    e[3:] = pin.log3(target[:3, :3] @ T[:3, :3].T)
    return float(e @ e), -2.0 * (J.T @ e), e


def limit_penalty(chain: Chain, q: Array) -> float:
    """TRAC-IK's manipPenalty: 1 − exp(−Π (q−l)(u−q)/(u−l)²) over joints with limits, ≥ 0."""
    limited = ~chain.continuous
    lo, hi = chain.lower[limited], chain.upper[limited]
    x = q[limited]
    product = float(np.prod((x - lo) * (hi - x) / (hi - lo) ** 2))
    return max(0.0, -math.expm1(-product))  # = 1 − exp(−x), without rounding small x to 0


def manipulability(chain: Chain, q: Array, kind: SolveType) -> float:
    """TRAC-IK's manipValue1 (Π σ_i) or manipValue2 (σ_min/σ_max) of the 6×n Jacobian, without the penalty."""
    s = np.linalg.svd(chain.jacobian(q), compute_uv=False)
    if kind is SolveType.MANIP1:
        return float(np.prod(s))
    return float(s[-1] / s[0]) if s[0] > 0 else 0.0


class TracIK(Solver):
    name = "trac"
    summary = (
        "TRAC-IK's design: KDL Newton with random restarts and a bounded SLSQP, interleaved in one budget; solve types"
    )
    options: ClassVar[dict[str, Any]] = {
        "solve_type": "speed",  # speed | distance | manip1 | manip2
        "nr_slice": 50,  # Newton steps per turn (~1 ms)
        "sqp_slice": 3,  # SQP objective evaluations per turn (~0.1 ms, plus ~0.3 ms to start each SLSQP run)
        "nr_patience": 5,  # Newton steps without the error halving before a random restart
        "sqp_max_iterations": 60,  # SLSQP iterations per run before a random restart
    }

    def __init__(
        self, chain: Chain, timeout: float = 0.005, tolerance: float = 1e-5, seed: int | None = 0, **options: Any
    ) -> None:
        super().__init__(chain, timeout, tolerance, seed, **options)
        kind = self.opts["solve_type"]
        valid = ", ".join(t.value for t in SolveType)
        try:
            self.solve_type = SolveType(kind.value if isinstance(kind, SolveType) else kind)
        except (ValueError, TypeError):
            raise ArmtoolError(f"solver 'trac' has no solve_type {kind!r}", hint=f"solve_type: {valid}") from None
        for key in ("nr_slice", "sqp_slice", "nr_patience", "sqp_max_iterations"):
            value = self.opts[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value) or value < 1:
                raise ArmtoolError(
                    f"solver 'trac' option {key} must be an integer ≥ 1, got {value!r}",
                    hint=f"default: {self.options[key]}",
                )
        from scipy.optimize import Bounds, minimize  # here, not inside the first timed solve

        self._minimize = minimize
        self._bounds_type = Bounds
        self._seed = seed
        # Joints that TRAC-IK wraps by 2π (revolute with limits), and those it clamps (prismatic).
        self._wrap = (chain.revolute & ~chain.continuous).tolist()
        self._limited = ~chain.continuous
        self._lo = np.where(chain.continuous, -np.inf, chain.lower)
        self._hi = np.where(chain.continuous, np.inf, chain.upper)

    def call(self, prepared: tuple[Array, Array]) -> tuple[Array, bool, int, Array]:
        """(the chosen solution or the best q found, whether it is a solution, iterations, the seed)."""
        search = _Search(self, *prepared)
        try:
            search.run()
        except _Stop:
            pass
        return search.result()

    def answer(self, raw: tuple[Array, bool, int, Array]) -> Answer:
        """A failed search's best q normalized as its solutions are (by 2π nearest the seed)."""
        q, found, iterations, seed = raw
        if found:
            return Answer(q, True, iterations)
        return Answer(self.normalize(q, seed), False, iterations, "timeout")

    # ---- helpers shared by both solvers -------------------------------------------------------------
    def into_limits(self, q: Array) -> Array:
        """KDL-TL with try_jl_wrap: a revolute joint beyond a limit moves by 2π inside them if that fits,
        else to the limit; prismatic joints clamp; continuous joints stay as they are."""
        lo, hi = self._lo, self._hi  # ±inf for continuous joints
        if (q >= lo).all() and (q <= hi).all():
            return q
        q = q.copy()
        for i in np.flatnonzero((q < lo) | (q > hi)).tolist():
            v, low, high = float(q[i]), float(lo[i]), float(hi[i])
            if v < low:
                w = low + (v - low) % TWO_PI  # in [low, low + 2π)
                q[i] = w if self._wrap[i] and w <= high else low
            else:
                w = high - (high - v) % TWO_PI  # in (high − 2π, high]
                q[i] = w if self._wrap[i] and w >= low else high
        return q

    def normalize(self, q: Array, seed: Array) -> Array:
        """TRAC-IK's normalize_seed / normalize_limits: each revolute joint moved by a multiple of 2π to
        the value nearest its reference (the seed; for manip1/manip2 the middle of a limited joint's
        range) that is within the limits. The pose does not change."""
        chain = self.chain
        ref = seed
        if self.solve_type in (SolveType.MANIP1, SolveType.MANIP2):
            ref = np.where(chain.continuous, seed, chain.mid())
        shift = np.where(chain.revolute, TWO_PI * np.round((ref - q) / TWO_PI), 0.0)
        if not shift.any():
            return q
        cand = q + shift
        lo, hi = chain.lower, chain.upper
        cand = np.where(self._limited & (cand > hi), cand - TWO_PI * np.ceil((cand - hi) / TWO_PI), cand)
        cand = np.where(self._limited & (cand < lo), cand + TWO_PI * np.ceil((lo - cand) / TWO_PI), cand)
        inside = ~self._limited | ((cand >= lo) & (cand <= hi))
        return np.where(inside, cand, q)

    def score(self, q: Array, seed: Array) -> float:
        """Larger is better: −Σ(q − seed)² (distance, TRAC-IK's JointErr), or penalty · manipulability."""
        if self.solve_type in (SolveType.SPEED, SolveType.DISTANCE):
            d = q - seed
            return -float(d @ d)
        return limit_penalty(self.chain, q) * manipulability(self.chain, q, self.solve_type)

    def restart_range(self, lo: Array, hi: Array, seed: Array) -> tuple[Array, Array]:
        """Where random restarts are drawn: [lo, hi] for joints with limits, seed ± 2π for continuous
        joints (TRAC-IK's runSolver). Returns (low end, width)."""
        cont = self.chain.continuous
        low = np.where(cont, seed - TWO_PI, lo)
        return low, np.where(cont, seed + TWO_PI, hi) - low

    def problem_rng(self, target: Array, seed: Array) -> np.random.Generator:
        """The stream one solve draws its restarts from: a function of the solver's seed and the problem."""
        if self._seed is None:
            return self.rng
        key = zlib.crc32(np.ascontiguousarray(target).tobytes() + np.ascontiguousarray(seed).tobytes())
        return np.random.default_rng([self._seed, 0x7AC, key])


class _Search:
    """One solve: the budget, the solutions found so far, and the two interleaved solvers."""

    def __init__(self, solver: TracIK, target: Array, seed: Array) -> None:
        self.solver = solver
        self.chain = solver.chain
        self.target = target
        self.seed = seed
        self.clock: Callable[[], float] = solver.clock
        self.deadline = solver.clock() + solver.timeout
        self.tol = solver.tolerance
        self.speed = solver.solve_type is SolveType.SPEED
        self.solutions: list[Array] = []
        self.scores: list[float] = []
        self.iterations = 0
        self.best_err, self.best_q = math.inf, seed
        self.p_target = np.ascontiguousarray(target[:3, 3])
        self.R_target = np.ascontiguousarray(target[:3, :3])
        self._rng: np.random.Generator | None = None
        self.newton: Iterator[None] = self._newton()

    def random(self, n: int) -> Array:
        """n uniform numbers in [0, 1) from this problem's stream (made on the first restart: most solves need none)."""
        if self._rng is None:
            self._rng = self.solver.problem_rng(self.target, self.seed)
        return self._rng.random(n)

    # ---- bookkeeping ----------------------------------------------------------------------------------
    def found(self, q: Array) -> None:
        """Record a solution (normalized as TRAC-IK does); speed stops at the first."""
        q = self.solver.normalize(q.copy(), self.seed)
        if any(float(np.abs(q - s).max()) <= SAME_SOLUTION for s in self.solutions):
            return
        self.solutions.append(q)
        self.scores.append(self.solver.score(q, self.seed))
        if self.speed:
            raise _Stop

    def result(self) -> tuple[Array, bool, int, Array]:
        """The best-scored solution, or the best q found (TracIK.answer normalizes it)."""
        if self.solutions:
            return self.solutions[int(np.argmax(self.scores))], True, self.iterations, self.seed
        return self.best_q, False, self.iterations, self.seed

    def run(self) -> None:
        next(self.newton)  # a first Newton turn: most targets end here, before SLSQP's setup cost
        solver, chain, n = self.solver, self.chain, self.chain.n
        # NLOPT-IK's start: the seed brought into the limits (by 2π where that fits, else clamped; TRAC-IK
        # falls back to mid-range there), and its bounds: the limits narrowed to start ± 2π (start ± 2π
        # for continuous joints).
        x0 = solver.into_limits(self.seed)
        lo = np.where(
            chain.continuous, x0 - TWO_PI, np.where(chain.revolute, np.maximum(chain.lower, x0 - TWO_PI), chain.lower)
        )
        hi = np.where(
            chain.continuous, x0 + TWO_PI, np.where(chain.revolute, np.minimum(chain.upper, x0 + TWO_PI), chain.upper)
        )
        bounds = solver._bounds_type(lo, hi)
        options = {"maxiter": int(solver.opts["sqp_max_iterations"]), "ftol": 1e-20}
        sqp_slice = int(solver.opts["sqp_slice"])
        near = 6.0 * self.tol**2  # every |Δ_i| < tol implies ‖Δ‖² < 6·tol²
        evaluations = 0

        def objective(x: Array) -> tuple[float, Array]:
            nonlocal evaluations
            if self.clock() > self.deadline:
                raise _Stop
            err, grad, e = squared_error(chain, self.target, x)
            self.iterations += 1
            evaluations += 1
            if err < self.best_err:
                self.best_err, self.best_q = err, x.copy()
            if err < near and float(np.abs(e).max()) < self.tol:
                self.found(x)  # speed: raises _Stop
                raise _Found
            if evaluations % sqp_slice == 0:
                next(self.newton)  # the Newton solver's turn (raises _Stop when it ends the search)
            return err, grad

        while True:
            try:
                solver._minimize(objective, x0, jac=True, method="SLSQP", bounds=bounds, options=options)
            except _Found:
                pass
            x0 = lo + (hi - lo) * self.random(n)  # SLSQP stopped (elsewhere, or after a solution): restart

    # ---- (a) KDL-TL: Newton-Raphson, wrap-or-clamp at the limits, random restarts ---------------------
    def _newton(self) -> Iterator[None]:
        solver, chain, n = self.solver, self.chain, self.chain.n
        fk_jacobian = chain.fk_jacobian
        log3 = pin.log3
        dgesvd = lapack.dgesvd
        into_limits = solver.into_limits
        random = self.random
        clock, deadline, tol = self.clock, self.deadline, self.tol
        near = 6.0 * tol**2
        p_target, R_target = self.p_target, self.R_target
        nr_slice = int(solver.opts["nr_slice"])
        patience = int(solver.opts["nr_patience"])
        progress = PROGRESS
        low, width = solver.restart_range(chain.lower, chain.upper, self.seed)
        e = np.empty(6)
        q = self.seed.copy()  # KDL-TL starts from the seed as given
        try_best, stalled = math.inf, 0
        while True:
            for _ in range(nr_slice):
                if clock() > deadline:
                    raise _Stop
                T, J = fk_jacobian(q)
                np.subtract(p_target, T[:3, 3], out=e[:3])
                e[3:] = log3(R_target @ T[:3, :3].T)
                self.iterations += 1
                err = float(e @ e)
                if err < self.best_err:
                    self.best_err, self.best_q = err, q
                if err < near and float(np.abs(e).max()) < tol:
                    self.found(q)  # speed: raises _Stop
                    q, try_best, stalled = low + width * random(n), math.inf, 0  # search on elsewhere
                    continue
                if err < progress * try_best:
                    try_best, stalled = err, 0
                else:
                    stalled += 1
                U, s, Vt, info = dgesvd(J, compute_uv=1, full_matrices=0)
                if info != 0:
                    stalled = patience  # no step: treat as stuck
                    q_new = q
                else:
                    c = U.T @ e
                    if s[-1] >= KDL_SVD_EPS:
                        c /= s
                    else:  # KDL's truncation: directions with σ < 1e-5 get no motion
                        keep = s >= KDL_SVD_EPS
                        c = np.where(keep, c / np.where(keep, s, 1.0), 0.0)
                    q_step = q + Vt.T @ c
                    q_new = into_limits(q_step)
                    # KDL-TL's test: after wrap-or-clamp, no joint moved (a fixed point at the limits).
                    # An unclamped step this small means the error did not halve, which patience catches.
                    if q_new is not q_step and float(np.abs(q_new - q).max()) <= FLT_EPSILON:
                        stalled = patience
                if stalled >= patience:
                    q_new, try_best, stalled = low + width * random(n), math.inf, 0
                q = q_new
            yield
