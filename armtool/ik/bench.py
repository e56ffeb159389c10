"""The benchmark behind `armtool ik-bench`: TRAC-IK's protocol, every answer re-verified by FK.

Protocol (TRAC-IK's ik_tests, MoveIt's ik_benchmarking): N configurations uniform within the
limits → FK → targets; each solve starts from the nominal seed (mid-range), or a random one,
or one near the answer; a timeout per solve; success only if our own FK of the returned q
is within the tolerance and q is within the limits.

The timing boundary is the same for every solver, armtool's and the peers': only the solver's
own call (`Solver.call`, or `call_batch`) is timed. Putting the inputs in the solver's form
(`prepare`), reading its output (`answer`) and checking the answer by armtool's FK (`verify`) all
happen outside the timed region, for every row alike (TIMING).
"""

from __future__ import annotations

import re
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from armtool.ik.modes import SeedMode
from armtool.ik.peers import Captured, native_stderr_captured
from armtool.ik.solutions import distinct, missing, refine
from armtool.ik.solver import Answer, Array, Solver
from armtool.model.chain import Chain

# What the timings mean, for the table's footer and the JSON report.
TIMING = (
    "time = the solver's own solve call only (with the solver's own checks of its inputs), the same "
    "boundary for every row; converting the target into a solver's input form, reading its output into "
    "armtool's answer and checking every answer with armtool's forward kinematics (success = that check, "
    "never the solver's own flag) happen outside the timed region"
)


@dataclass(frozen=True)
class BenchConfig:
    samples: int = 1000
    rng_seed: int = 0
    seed_mode: SeedMode = SeedMode.MID
    timeout: float = 0.005
    tolerance: float = 1e-5
    repeat: int = 100  # targets solved a second time to check repeatability
    near_radius: float = 0.1  # rad (or m) of noise around the answer for seed_mode near
    position_only: bool = False  # MoveIt's position_only_ik: targets and the check are on the tip's position only


@dataclass
class Targets:
    q_true: Array  # (N, n)
    poses: Array  # (N, 4, 4)
    seeds: Array  # (N, n)


def run_header(chain: Chain, config: BenchConfig, how: str = "") -> str:
    """The line a run starts with: the chain, how it was chosen, and the protocol's settings."""
    text = (
        f"{chain.name}: {chain.base} → {chain.tip}, {chain.n} joints ({', '.join(chain.joint_names)})"
        + (f", {how}" if how else "")
        + f"; {config.samples} targets, seed {config.seed_mode.value}, "
        f"timeout {config.timeout * 1e3:g} ms, tolerance {config.tolerance:g}"
    )
    if config.position_only:
        text += (
            "; position only (position_only_ik in kinematics.yaml): targets and checks on the tip position, the solvers"
            " get the chain with a free virtual wrist at the tip"
        )
    return text


def make_targets(chain: Chain, config: BenchConfig) -> Targets:
    rng = np.random.default_rng(config.rng_seed)
    q_true = chain.random(rng, config.samples)
    if chain.free_orientation:  # position-only: the virtual wrist at zero, far from its gimbal lock
        q_true[:, chain.n - chain.free_orientation :] = 0.0
    poses = chain.fk_batch(q_true)
    if config.seed_mode is SeedMode.RANDOM:
        seeds = chain.random(rng, config.samples)
    elif config.seed_mode is SeedMode.NEAR:
        seeds = chain.clamp(q_true + rng.uniform(-config.near_radius, config.near_radius, q_true.shape))
    else:
        seeds = np.tile(chain.mid(), (config.samples, 1))
    return Targets(q_true, poses, seeds)


def _summary(values: Array) -> dict[str, float]:
    if values.size == 0:
        return {"median": float("nan"), "p95": float("nan"), "max": float("nan")}
    return {"median": float(np.median(values)), "p95": float(np.percentile(values, 95)), "max": float(values.max())}


@dataclass
class SolverReport:
    solver: str
    mode: str  # "single" (one timed call() per target) or "batch" (timed call_batch() over every target)
    samples: int
    success_rate: float
    wall_us: dict[str, float]
    cpu_us: dict[str, float]
    solves_per_s: float
    position_error_m: dict[str, float]
    orientation_error_rad: dict[str, float]
    seed_distance: dict[str, float]
    repeatability: float | None
    # Closed-form rows (answers with `solutions`): distinct solutions per target that pass armtool's
    # check (armtool.ik.solutions), mean over the targets; None for the other rows.
    distinct_solutions: float | None
    failed_condition_numbers: dict[str, float]
    failures: int
    claimed_but_wrong: int  # the solver said success, our FK disagreed
    failure_reasons: dict[
        str, int
    ]  # why the failures failed (the solver's reason, or why its claim was wrong), most common first
    stalled_failures: int | None = (
        None  # failures past the timeout with < timeout/2 of CPU: the machine was busy (None: batch)
    )
    # Closed-form rows beside other closed-form rows (compare_solutions): how many of the solutions the
    # others found (their union, distinct) this row lacks, in total and on how many targets.
    missing_solutions: int | None = None
    targets_missing_solutions: int | None = None
    method: str = ""  # how the solver solves this chain (Solver.method: a closed form's family)
    wall_times_us: list[float] = field(default_factory=list, repr=False)  # every solve, in target order
    solved: list[bool] = field(default_factory=list, repr=False)  # our FK verdict per target
    # Closed-form rows: per target, its distinct solutions that pass armtool's check, each refined onto
    # the exact solution it approximates (armtool.ik.solutions.refine; (k, n) arrays).
    verified: list[Array] = field(default_factory=list, repr=False)


@dataclass(frozen=True)
class NotApplicable:
    """A solver that cannot run on this chain (e.g. `analytic` on an arm without a closed form), and why."""

    solver: str
    reason: str
    mode: str = "single"


def _joint_distance(chain: Chain, a: Array, b: Array) -> Array:
    """Euclidean joint distance over the real joints (not a position-only chain's virtual wrist)."""
    m = chain.n - chain.free_orientation
    d: Array = a[..., :m] - b[..., :m]
    d = np.where(chain.continuous[:m], (d + np.pi) % (2 * np.pi) - np.pi, d)
    norms: Array = np.linalg.norm(d, axis=-1)  # numpy's stubs: Any when axis is given
    return norms


@contextmanager
def native_output(solver: Solver, phase: str) -> Iterator[None]:
    """Around a block of a solver's calls: for a solver that prints natively (Solver.prints_natively),
    what its native code writes on fd 2 is captured (armtool.ik.peers.native_stderr_captured) and kept
    in solver.native_stderr under `phase`; for the others, nothing happens. Entered once per block,
    outside the clock readings: moving fd 2 is never timed. If the block raises, what it caught is
    written back on stderr as it was: no summary will follow."""
    if not solver.prints_natively:
        yield
        return
    captured, finished = Captured(), False
    try:
        with native_stderr_captured() as captured:
            yield
        finished = True
    finally:
        if captured.text and finished:
            solver.native_stderr += ((phase, captured.text),)
        elif captured.text:
            sys.stderr.write(captured.text)


_PANIC = re.compile(r"^thread '.*' panicked at", re.MULTILINE)  # Rust's panic hook, first line of each panic


def native_stderr_note(solver: Solver) -> str:
    """One line on what a solver printed natively during its solves (solver.native_stderr): how many
    lines, the Rust panics among them by phase, and the first line; "" when it printed nothing."""
    text = "".join(t for _, t in solver.native_stderr)
    lines = text.splitlines()
    if not lines:
        return ""
    panics = {phase: 0 for phase in ("timed", "warm-up", "repeat")}
    for phase, t in solver.native_stderr:
        panics[phase] = panics.get(phase, 0) + len(_PANIC.findall(t))
    timed, untimed = panics["timed"], sum(panics.values()) - panics["timed"]
    parts = []
    if timed:
        parts.append(
            f"{timed} on timed targets, among its row's failures"
            if timed > 1
            else "1 on a timed target, among its row's failures"
        )
    if untimed:
        parts.append(f"{untimed} in untimed warm-up or repeat solves")
    total = timed + untimed
    panicked = (f"; {total} Rust panic{'s' if total != 1 else ''}: " + ", ".join(parts)) if parts else ""
    first = next((line.strip() for line in lines if line.strip()), "")
    if len(first) > 160:
        first = first[:157] + "..."
    return (
        f"{solver.name} printed {len(lines)} line{'s' if len(lines) != 1 else ''} on stderr during its solves"
        f" (not shown{panicked}); the first: {first}"
    )


WARM_UP_SOLVES = 8


def warm_up(chain: Chain, solver: Solver) -> None:
    """A few untimed solves before the timed ones: the first calls of a solver's code paths (its
    tables, LAPACK wrappers, restarts, a peer's native library) are not what a solve costs.

    Targets from a stream of their own (not the benchmark's), from the mid-range seed: not the
    mid-range pose itself, which a solver answers without a single step."""
    rng = np.random.default_rng(0x5EED)
    with native_output(solver, "warm-up"):
        for target in chain.fk_batch(chain.random(rng, WARM_UP_SOLVES)):
            solver.solve(target, chain.mid())
        solver.solve(chain.fk(chain.mid()), chain.mid())


@dataclass
class Timed:
    """A solver's answers to some targets, and the wall and process-CPU seconds of each solve call
    (or, for a batch, each answer's share of the one call)."""

    results: list[Answer]
    wall: Array
    cpu: Array
    batch: bool = False


def time_solves(solver: Solver, poses: Array, seeds: Array, progress: Callable[[int], None] | None = None) -> Timed:
    """One solver call per target, each timed on the wall and the process CPU clock; the inputs are
    prepared and the output read outside the timing (see TIMING)."""
    N = poses.shape[0]
    wall, cpu = np.zeros(N), np.zeros(N)
    results = []
    prepare, call, answer = solver.prepare, solver.call, solver.answer
    perf_counter, process_time = time.perf_counter, time.process_time
    with native_output(solver, "timed"):  # once around the block, not per call: never timed
        for i in range(N):
            prepared = prepare(poses[i], seeds[i])
            # The wall clock is read innermost: a process_time() read costs ~1 µs on the development VM
            # (a system call), which would be timed in every row, a quarter of EAIK's solve.
            c0 = process_time()
            w0 = perf_counter()
            raw = call(prepared)
            w1 = perf_counter()
            c1 = process_time()
            wall[i], cpu[i] = w1 - w0, c1 - c0
            results.append(answer(raw))
            if progress:
                progress(1)
    return Timed(results, wall, cpu)


def time_batch(solver: Solver, poses: Array, seeds: Array) -> Timed:
    """One call_batch() over every target; each answer is charged an equal share of it."""
    N = poses.shape[0]
    prepared = solver.prepare_batch(poses, seeds)
    with native_output(solver, "timed"):  # entered and left outside the clock readings
        c0 = time.process_time()
        w0 = time.perf_counter()
        raw = solver.call_batch(prepared)
        w1 = time.perf_counter()
        c1 = time.process_time()
    total_wall, total_cpu = w1 - w0, c1 - c0
    return Timed(solver.answer_batch(raw), np.full(N, total_wall / N), np.full(N, total_cpu / N), batch=True)


def join_timed(parts: Sequence[Timed]) -> Timed:
    """The timings of consecutive blocks of the same targets, as one run over all of them."""
    return Timed(
        [r for part in parts for r in part.results],
        np.concatenate([part.wall for part in parts]),
        np.concatenate([part.cpu for part in parts]),
        batch=all(part.batch for part in parts),
    )


def run_solver(
    chain: Chain,
    solver: Solver,
    targets: Targets,
    config: BenchConfig,
    *,
    batch: bool = False,
    progress: Callable[[int], None] | None = None,
) -> SolverReport:
    """Warm the solver up, time it on every target (one batch call, or one solve each) and report."""
    warm_up(chain, solver)
    if batch:
        timed = time_batch(solver, targets.poses, targets.seeds)
        if progress:
            progress(targets.poses.shape[0])
    else:
        timed = time_solves(solver, targets.poses, targets.seeds, progress)
    return solver_report(chain, solver, targets, config, timed)


def solver_report(chain: Chain, solver: Solver, targets: Targets, config: BenchConfig, timed: Timed) -> SolverReport:
    """Every figure of one run, each answer judged by our own FK; with config.repeat, the first
    targets are solved again (untimed) to check that the same target gives the same answer."""
    results, wall, cpu, batch = timed.results, timed.wall, timed.cpu, timed.batch
    N = targets.poses.shape[0]
    total_wall = float(wall.sum())
    tol, position_only = config.tolerance, config.position_only
    judged = solver.judge_batch(results, targets.poses, tolerance=tol, position_only=position_only)
    Q = np.array([r.q for r in judged])
    ok = np.array([r.success for r in judged], dtype=bool)
    pos = np.array([r.position_error_m for r in judged])
    rot = np.array([r.orientation_error_rad for r in judged])
    claimed = np.array([r.claimed for r in results])
    reasons: dict[str, int] = {}
    for r in judged:
        if not r.success:
            reasons[r.reason] = reasons.get(r.reason, 0) + 1
    repeat = None
    if config.repeat > 0 and not batch:
        m = min(config.repeat, N)
        prepare, call, answer = solver.prepare, solver.call, solver.answer
        with native_output(solver, "repeat"):
            again = [answer(call(prepare(targets.poses[i], targets.seeds[i]))) for i in range(m)]
        judged2 = solver.judge_batch(again, targets.poses[:m], tolerance=tol, position_only=position_only)
        Q2 = np.array([r.q for r in judged2])
        ok2 = np.array([r.success for r in judged2], dtype=bool)
        both = ok[:m] & ok2
        same = both & (_joint_distance(chain, Q[:m], Q2) < 1e-6)
        repeat = float(same.sum() / both.sum()) if both.any() else None  # nothing to compare
    verified = []
    if solver.returns_all_solutions or any(r.solutions for r in results):  # a closed-form row
        verified = [
            distinct(chain, refine(chain, np.array(r.solutions).reshape(-1, chain.n), pose))
            for r, pose in zip(judged, targets.poses)
        ]
    conds = []
    for i in np.flatnonzero(~ok)[:200]:
        s = np.linalg.svd(chain.jacobian(targets.q_true[i]), compute_uv=False)
        conds.append(float(s[0] / s[-1]) if s[-1] > 0 else float("inf"))
    return SolverReport(
        solver=solver.name,
        mode="batch" if batch else "single",
        samples=N,
        success_rate=float(ok.mean()),
        wall_us=_summary(wall * 1e6),
        cpu_us=_summary(cpu * 1e6),
        solves_per_s=float(N / total_wall) if total_wall > 0 else float("inf"),
        position_error_m=_summary(pos[ok]),
        orientation_error_rad=_summary(rot[ok]),
        seed_distance=_summary(_joint_distance(chain, Q[ok], targets.seeds[ok])),
        repeatability=repeat,
        distinct_solutions=float(np.mean([v.shape[0] for v in verified])) if verified else None,
        failed_condition_numbers=_summary(np.array(conds)),
        failures=int((~ok).sum()),
        claimed_but_wrong=int((claimed & ~ok).sum()),
        failure_reasons=dict(sorted(reasons.items(), key=lambda item: -item[1])),
        stalled_failures=None if batch else int(((~ok) & (wall >= config.timeout) & (cpu < config.timeout / 2)).sum()),
        method=solver.method,
        wall_times_us=list(wall * 1e6),
        solved=[bool(x) for x in ok],
        verified=verified,
    )


def compare_solutions(chain: Chain, reports: Sequence[SolverReport]) -> None:
    """Fill in each closed-form row's missing solutions: per target, the distinct verified solutions of
    the other closed-form solvers (their union; the same solver's other mode is not another solver)
    that this row does not have. Rows without another closed-form solver beside them keep None."""
    rows = [r for r in reports if r.distinct_solutions is not None]
    for row in rows:
        others = [o for o in rows if o.solver != row.solver]
        if not others:
            continue
        count = targets = 0
        for t in range(min(len(r.verified) for r in [row, *others])):
            union = distinct(chain, np.vstack([o.verified[t] for o in others]))
            lacking = missing(chain, row.verified[t], union)
            count += lacking
            targets += lacking > 0
        row.missing_solutions, row.targets_missing_solutions = count, targets


@dataclass(frozen=True)
class Entry:
    """One row of a benchmark: a solver solving one target at a time, or its one batch call over
    all of them; `limit` solves only the first targets (a very slow peer)."""

    solver: Solver
    batch: bool = False
    limit: int | None = None

    @property
    def label(self) -> str:
        return self.solver.name + (" (batch)" if self.batch else "")


BLOCK = 50  # targets a solver solves before the next one takes its turn


def time_interleaved(
    entries: Sequence[Entry],
    targets: Targets,
    block: int = BLOCK,
    rotate: int = 0,
    progress: Callable[[str, int], None] | None = None,
    batch_calls: int = 1,
) -> dict[str, Timed]:
    """Every entry timed on the same targets, taking turns: block by block, each one-at-a-time entry
    solves the block (the order rotated by one each block, starting `rotate` places on), and each
    batch entry makes its call over all targets mid-way, or `batch_calls` calls spread evenly
    over the blocks. A laptop's turbo or a VM's neighbours change the CPU's speed over seconds
    (the development VM: 2x, every 2.5-8 s); run whole one after the other, one solver would be
    timed fast and the next slow. A batch row's answers are its first call's; its time per
    target is the mean over its calls, so it samples the machine across the run as the
    one-at-a-time rows do."""
    labels = [e.label for e in entries]
    if len(set(labels)) < len(labels) or block < 1 or batch_calls < 1:
        raise ValueError(f"entries need distinct labels ({labels}), block and batch_calls >= 1")
    if any(e.limit is not None and (e.batch or e.limit < 1) for e in entries):
        raise ValueError("a limit is for one-at-a-time entries, and at least 1")
    N = targets.poses.shape[0]
    singles = [e for e in entries if not e.batch]
    parts: dict[str, list[Timed]] = {e.label: [] for e in singles}
    calls: dict[str, list[Timed]] = {e.label: [] for e in entries if e.batch}
    starts = range(0, N, block)
    batch_at = [int((i + 0.5) * len(starts) / batch_calls) for i in range(batch_calls)]
    for k, start in enumerate(starts):
        for _ in range(batch_at.count(k)):
            for e in entries:
                if e.batch:
                    calls[e.label].append(time_batch(e.solver, targets.poses, targets.seeds))
                    if progress and len(calls[e.label]) == 1:
                        progress(e.label, N)
        shift = (k + rotate) % len(singles) if singles else 0
        for e in singles[shift:] + singles[:shift]:
            stop = min(start + block, N if e.limit is None else min(e.limit, N))
            if start < stop:
                tick = (lambda n, label=e.label: progress(label, n)) if progress else None
                parts[e.label].append(time_solves(e.solver, targets.poses[start:stop], targets.seeds[start:stop], tick))
    timed = {label: join_timed(blocks) for label, blocks in parts.items() if blocks}
    for label, made in calls.items():
        wall = np.mean([c.wall for c in made], axis=0)
        cpu = np.mean([c.cpu for c in made], axis=0)
        timed[label] = Timed(made[0].results, wall, cpu, batch=True)
    return timed


def first(targets: Targets, count: int | None) -> Targets:
    """The first `count` targets (all of them for None)."""
    if count is None or count >= targets.poses.shape[0]:
        return targets
    return Targets(targets.q_true[:count], targets.poses[:count], targets.seeds[:count])


def run_bench(
    chain: Chain,
    entries: Sequence[Entry],
    targets: Targets,
    config: BenchConfig,
    *,
    block: int = BLOCK,
    progress: Callable[[str, int], None] | None = None,
) -> list[SolverReport]:
    """Warm every solver up, time them all on the same targets taking turns (time_interleaved),
    and report each, in the order of `entries`."""
    for e in entries:
        if not e.batch:
            warm_up(chain, e.solver)
    timed = time_interleaved(entries, targets, block, progress=progress)
    reports = [solver_report(chain, e.solver, first(targets, e.limit), config, timed[e.label]) for e in entries]
    compare_solutions(chain, reports)
    return reports
