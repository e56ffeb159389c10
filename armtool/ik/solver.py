"""What every IK solver offers: `solve(target, seed) -> IKResult`, `solve_batch(targets, seeds)`.

Targets are 4x4 homogeneous poses of the chain's tip in its base frame; seeds are joint vectors.

A solve has three steps, so that a benchmark times every solver the same way (TRAC-IK's paper and
roboticstoolbox time the solve call only):
- `prepare(target, seed)`: the inputs in the form the solver's own call takes (a peer's quaternion,
  a contiguous array). Not timed.
- `call(prepared)`: the solver's own work, and nothing else. This is what `ik-bench` times. It
  returns the solver's raw output (armtool's own solvers: a tuple or a buffer, never an `Answer`).
- `answer(raw)`: that output as an `Answer` (q, the solver's own claim, iterations). Not timed.
Then `judge` checks the answer with armtool's own forward kinematics (`verify`), the same for every
solver and outside the timing: a solver's claim is never trusted.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from armtool.errors import ArmtoolError
from armtool.model.chain import Chain

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Answer:
    """What a solver's own call returned, before armtool checks it."""

    q: Array
    claimed: bool  # the solver's own verdict: it says q reaches the target
    iterations: int = 0
    reason: str = ""  # why the solver gave up, in its own terms (empty when it claims success)
    # Every solution found (closed-form solvers return all of them, in their order of preference,
    # nearest the seed first; q is the first). The answer is judged on these: see Solver.judge.
    solutions: tuple[Array, ...] = ()


@dataclass(frozen=True)
class IKResult:
    success: bool
    q: Array
    position_error_m: float
    orientation_error_rad: float
    iterations: int
    reason: str = ""
    # A closed-form solver's solutions that pass armtool's check (q is the first of them); empty for others.
    solutions: tuple[Array, ...] = field(default=())


def rotation_error(R: Array, R_target: Array) -> Array:
    """Rotation vector (base frame) that turns R into R_target: log(R_target Rᵀ)."""
    M = R_target @ R.T
    cos = max(-1.0, min(1.0, (M[0, 0] + M[1, 1] + M[2, 2] - 1.0) / 2.0))
    v = np.array([M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]])
    angle = math.acos(cos)
    if angle < 1e-6:
        return 0.5 * v
    if math.pi - angle > 1e-6:
        return v * (angle / (2.0 * math.sin(angle)))
    # angle ≈ π: axis from the diagonal of (M + I)/2 = a aᵀ
    diag = np.clip((np.diag(M) + 1.0) / 2.0, 0.0, None)
    k = int(np.argmax(diag))
    axis: Array = (M[:, k] + np.eye(3)[:, k]) / 2.0 / math.sqrt(diag[k])
    axis /= np.linalg.norm(axis)
    if np.dot(axis, v) < 0:
        axis = -axis
    return axis * angle


def rotation_error_batch(R: Array, R_target: Array) -> Array:
    """rotation_error for (N,3,3) stacks: (N,3) rotation vectors log(R_target Rᵀ)."""
    M = R_target @ R.transpose(0, 2, 1)
    v = 0.5 * np.stack([M[:, 2, 1] - M[:, 1, 2], M[:, 0, 2] - M[:, 2, 0], M[:, 1, 0] - M[:, 0, 1]], axis=1)
    cos = np.clip((M[:, 0, 0] + M[:, 1, 1] + M[:, 2, 2] - 1.0) / 2.0, -1.0, 1.0)
    sin = np.linalg.norm(v, axis=1)
    angle = np.arctan2(sin, cos)
    scale = np.where(sin > 1e-9, angle / np.maximum(sin, 1e-300), 1.0)
    out = v * scale[:, None]
    near_pi = (sin <= 1e-9) & (cos < 0)
    for i in np.flatnonzero(near_pi):
        out[i] = rotation_error(R[i], R_target[i])
    return out


def pose_error_batch(T: Array, targets: Array) -> Array:
    """(N,6) pose errors [dp; dw] for (N,4,4) poses and targets."""
    return np.concatenate(
        [targets[:, :3, 3] - T[:, :3, 3], rotation_error_batch(T[:, :3, :3], targets[:, :3, :3])], axis=1
    )


def pose_error(T: Array, target: Array) -> Array:
    """6-vector [dp; dw] in the base frame from pose T to the target (dw = log(R_target Rᵀ))."""
    import pinocchio as pin

    e = np.empty(6)
    e[:3] = target[:3, 3] - T[:3, 3]
    e[3:] = pin.log3(target[:3, :3] @ T[:3, :3].T)
    return e


def verify_batch(
    chain: Chain, Q: Array, targets: Array, tolerance: float, *, position_only: bool = False
) -> tuple[NDArray[np.bool_], Array, Array]:
    """verify() for many answers at once, with numpy FK: (success mask, position errors, orientation errors).

    position_only (MoveIt's position_only_ik): success needs the position within the tolerance only."""
    T, _ = chain.fk_jacobian_batch(Q, jacobian=False)
    e = pose_error_batch(T, targets)
    pos, rot = np.linalg.norm(e[:, :3], axis=1), np.linalg.norm(e[:, 3:], axis=1)
    within = np.all((Q >= chain.lower - 1e-9) & (Q <= chain.upper + 1e-9) | chain.continuous, axis=1)
    checked = e[:, :3] if position_only else e
    ok = np.all(np.isfinite(Q), axis=1) & (np.abs(checked).max(axis=1) <= tolerance) & within
    return ok, pos, rot


def verify(chain: Chain, q: Array, target: Array, tolerance: float) -> tuple[bool, float, float]:
    """Recompute FK: (success, position error m, orientation error rad). Never trust a solver's flag.

    Success is the reference protocol's (TRAC-IK, KDL's Equal): every component of the twist
    error [dp; dw] within `tolerance`, and q within the joint limits. The errors returned are norms.
    """
    T = chain.fk(q)
    e = np.concatenate([target[:3, 3] - T[:3, 3], rotation_error(T[:3, :3], target[:3, :3])])
    pos, rot = float(np.linalg.norm(e[:3])), float(np.linalg.norm(e[3:]))
    finite = bool(np.all(np.isfinite(q)))
    return finite and float(np.abs(e).max()) <= tolerance and chain.within_limits(q), pos, rot


class Solver:
    """Base class: options, and the prepare → call → answer → judge steps of a solve.

    Subclasses implement `call` (and `prepare` / `answer` when their own call takes or returns
    something other than float arrays and a tuple (q, claimed, iterations, reason)); `call_batch`
    when they solve many targets at once in their own way."""

    name: ClassVar[str]
    summary: ClassVar[str]
    options: ClassVar[dict[str, Any]] = {}
    # False for solvers whose method needs the real chain (closed forms): they cannot take a
    # position-only chain (Chain.with_free_orientation) and are reported as not applicable.
    position_only_capable: ClassVar[bool] = True
    # Closed-form solvers return every solution (Answer.solutions): ik-bench counts and compares them.
    # (A solver whose answers carry solutions is treated so too.)
    returns_all_solutions: ClassVar[bool] = False
    # How this solver solves this chain, for the benchmark's row (a closed form's family); "" if nothing to say.
    method: str = ""
    # True for a solver whose native code writes on file descriptor 2 itself, past sys.stderr (IK-Geo:
    # Rust's message for every panic): the benchmark points fd 2 at a file around each block of its
    # calls, outside the timing (armtool.ik.bench.native_output), and keeps what it caught here.
    prints_natively: ClassVar[bool] = False
    # What it wrote there, block by block: (phase, text), phase "warm-up", "timed" or "repeat".
    native_stderr: tuple[tuple[str, str], ...] = ()

    def __init__(
        self, chain: Chain, timeout: float = 0.005, tolerance: float = 1e-5, seed: int | None = 0, **options: Any
    ) -> None:
        if not (math.isfinite(timeout) and timeout > 0):  # inf would never end a solve
            raise ArmtoolError(f"timeout must be > 0 seconds and finite, got {timeout}", hint="e.g. 0.005 (5 ms)")
        if not (math.isfinite(tolerance) and tolerance > 0):
            raise ArmtoolError(f"tolerance must be a finite number > 0 (m and rad), got {tolerance}", hint="e.g. 1e-5")
        unknown = set(options) - set(self.options)
        if unknown:
            known = ", ".join(f"{k} (default {v!r})" for k, v in self.options.items()) or "none"
            raise ArmtoolError(
                f"solver '{self.name}' has no option(s) {', '.join(sorted(unknown))}", hint=f"options: {known}"
            )
        self.chain = chain
        self.timeout = float(timeout)
        self.tolerance = float(tolerance)
        # A stream of its own: benchmarks draw their targets from default_rng(seed), and restarts
        # drawn from the same stream would start exactly at the answers.
        self.rng = np.random.default_rng(None if seed is None else [seed, 0x1C])
        self.opts = {**self.options, **options}
        chain.fk(chain.mid())  # builds the Pinocchio model now, not inside the first timed solve

    # ---- one target -------------------------------------------------------------------------------
    def prepare(self, target: Array, seed: Array) -> Any:
        """The inputs as the solver's own call takes them (untimed)."""
        return np.asarray(target, dtype=float), np.asarray(seed, dtype=float)

    def call(self, prepared: Any) -> Any:
        """The solver's own work on one prepared target: what a benchmark times."""
        raise NotImplementedError

    def answer(self, raw: Any) -> Answer:
        """call()'s output as an Answer (untimed): by default call() returns (q, claimed, iterations,
        reason). An Answer is passed on as it is (a solver whose call builds it: armtool's own do not,
        since that would be timed in their row and in no other)."""
        if isinstance(raw, Answer):
            return raw
        q, claimed, iterations, reason = raw
        return Answer(q, claimed, iterations, reason)

    def solve(self, target: Array, seed: Array) -> IKResult:
        """Solve one target and judge the answer by armtool's FK."""
        return self.judge(self.answer(self.call(self.prepare(target, seed))), target)

    def judge(self, answer: Answer, target: Array) -> IKResult:
        """The answer checked by our own FK (`verify`): success is its verdict, not the solver's.

        A closed-form answer (one with `solutions`) succeeds when any of its solutions passes the
        check: q is then the first that passes, in the solver's order, and the result's `solutions`
        are those that pass."""
        q = np.asarray(answer.q, dtype=float).reshape(self.chain.n)
        ok, pos, rot = verify(self.chain, q, target, self.tolerance)
        if not answer.solutions:
            return IKResult(ok, q, pos, rot, answer.iterations, "" if ok else self.failure_reason(answer))
        passed: list[Array] = []
        for s in answer.solutions:
            s = np.asarray(s, dtype=float).reshape(self.chain.n)
            good, p, r = verify(self.chain, s, target, self.tolerance)
            if good:
                if not passed:
                    q, pos, rot = s, p, r
                passed.append(s)
        ok = bool(passed)
        reason = "" if ok else self.failure_reason(answer)
        return IKResult(ok, q, pos, rot, answer.iterations, reason, tuple(passed))

    def failure_reason(self, answer: Answer) -> str:
        """Why an answer that armtool's check rejected failed: the solver's reason, or why its claim was wrong."""
        return self.rejected_claim(answer) if answer.claimed else (answer.reason or "did not converge")

    def rejected_claim(self, answer: Answer) -> str:
        """Why an answer the solver accepted fails armtool's check (a solver whose own test differs says how)."""
        return f"{self.name} accepted an answer that armtool's FK check rejects"

    # ---- many targets -----------------------------------------------------------------------------
    def prepare_batch(self, targets: Array, seeds: Array) -> Any:
        """The inputs of call_batch (untimed): by default each target prepared as for call()."""
        targets, seeds = self._batch_arrays(targets, seeds)
        return [self.prepare(t, s) for t, s in zip(targets, seeds)]

    def call_batch(self, prepared: Any) -> Any:
        """The solver's own work on every prepared target (timed as one call); by default one call() each."""
        return [self.call(p) for p in prepared]

    def answer_batch(self, raw: Any) -> list[Answer]:
        return [self.answer(r) for r in raw]

    @classmethod
    def has_batch(cls) -> bool:
        """Whether the solver solves many targets in a way of its own (not one call() after another)."""
        return cls.call_batch is not Solver.call_batch

    def solve_batch(self, targets: Array, seeds: Array) -> list[IKResult]:
        """Solve every target and judge the answers by armtool's FK (prepare_batch checks the shapes)."""
        answers = self.answer_batch(self.call_batch(self.prepare_batch(targets, seeds)))
        return self.judge_batch(answers, targets)

    def judge_batch(
        self, answers: list[Answer], targets: Array, *, tolerance: float | None = None, position_only: bool = False
    ) -> list[IKResult]:
        """judge() for many answers at once (verify_batch); by default at the solver's own tolerance,
        and on the whole pose (position_only: on the position, see verify_batch). Closed-form answers
        as in judge(): every solution is checked, the first that passes is the result."""
        if not answers:
            return []
        n = self.chain.n
        # Each answer's q, then its solutions, checked in one batch; owner[k]: the answer of row k.
        rows = [
            [np.asarray(a.q, dtype=float).reshape(n), *(np.asarray(s, dtype=float).reshape(n) for s in a.solutions)]
            for a in answers
        ]
        owner = np.repeat(np.arange(len(rows)), [len(r) for r in rows])
        Q = np.array([q for r in rows for q in r])
        targets = np.asarray(targets, dtype=float)
        ok, pos, rot = verify_batch(
            self.chain,
            Q,
            targets[owner],
            self.tolerance if tolerance is None else tolerance,
            position_only=position_only,
        )
        results = []
        start = 0
        for a, r in zip(answers, rows):
            pick, passed = start, ()
            if a.solutions:
                good = [start + 1 + k for k in range(len(a.solutions)) if ok[start + 1 + k]]
                passed = tuple(Q[k] for k in good)
                pick = good[0] if good else start
                success = bool(good)
            else:
                success = bool(ok[start])
            reason = "" if success else self.failure_reason(a)
            results.append(IKResult(success, Q[pick], float(pos[pick]), float(rot[pick]), a.iterations, reason, passed))
            start += len(r)
        return results

    def _batch_arrays(self, targets: Array, seeds: Array) -> tuple[Array, Array]:
        targets = np.asarray(targets, dtype=float)
        seeds = np.asarray(seeds, dtype=float)
        if targets.ndim != 3 or targets.shape[1:] != (4, 4) or seeds.shape != (targets.shape[0], self.chain.n):
            raise ArmtoolError(
                f"expected (N,4,4) targets and (N,{self.chain.n}) seeds, got {targets.shape} and {seeds.shape}"
            )
        return targets, seeds

    @staticmethod
    def clock() -> float:
        return time.perf_counter()
