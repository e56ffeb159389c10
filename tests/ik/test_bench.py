"""The benchmark harness: targets by the protocol, verdicts from our own FK, never the solver's flag."""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
import pytest

from armtool.ik import load_chain
from armtool.ik.bench import BenchConfig, SeedMode, make_targets, run_solver
from armtool.ik.solver import Answer, Solver
from tests.ik.robots import ARMS, erd


class Liar(Solver):
    """Claims success with the seed: the harness must not believe it."""

    name = "liar"
    summary = "test double"

    def call(self, prepared):  # type: ignore[no-untyped-def]
        return Answer(prepared[1], True, 1)


def test_targets_follow_the_protocol() -> None:
    chain = load_chain(erd(ARMS["ur5"][0]))
    config = BenchConfig(samples=50, rng_seed=4)
    t = make_targets(chain, config)
    assert np.allclose(t.seeds, chain.mid()) and t.poses.shape == (50, 4, 4)
    assert np.all((t.q_true >= chain.lower) & (t.q_true <= chain.upper))
    assert np.allclose(t.poses, chain.fk_batch(t.q_true))
    again = make_targets(chain, config)
    assert np.array_equal(t.q_true, again.q_true)
    near = make_targets(chain, BenchConfig(samples=50, rng_seed=4, seed_mode=SeedMode.NEAR))
    assert np.abs(near.seeds - near.q_true).max() <= 0.1 + 1e-12


def test_solver_flags_are_never_trusted() -> None:
    chain = load_chain(erd(ARMS["ur5"][0]))
    config = BenchConfig(samples=20, repeat=5)
    report = run_solver(chain, Liar(chain), make_targets(chain, config), config)
    assert report.success_rate == 0.0 and report.claimed_but_wrong == 20 and report.failures == 20


def test_lm_report_fields() -> None:
    from armtool.ik import make_solver

    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip)
    config = BenchConfig(samples=30, repeat=10, timeout=0.02)
    targets = make_targets(chain, config)
    single = run_solver(chain, make_solver("lm", chain, timeout=0.02), targets, config)
    batch = run_solver(chain, make_solver("lm", chain, timeout=0.02), targets, config, batch=True)
    for r in (single, batch):
        assert r.success_rate >= 29 / 30 and r.claimed_but_wrong == 0
        assert r.position_error_m["max"] <= 1e-5 and r.orientation_error_rad["max"] <= 1e-5
        assert r.wall_us["median"] > 0 and r.solves_per_s > 0
    assert single.repeatability is not None and 0.0 <= single.repeatability <= 1.0
    assert batch.mode == "batch" and batch.repeatability is None


def test_solver_randomness_is_independent_of_the_target_stream() -> None:
    """Targets come from default_rng(seed); restarts drawn from the same stream would start at the answers."""
    from armtool.ik import make_solver

    chain = load_chain(erd(ARMS["ur5"][0]))
    targets = make_targets(chain, BenchConfig(samples=50, rng_seed=0))
    solver = make_solver("lm", chain, seed=0)
    table = solver.table()[3]  # type: ignore[attr-defined]
    nearest = np.abs(table[:, None, :] - targets.q_true[None, :, :]).sum(axis=2).min()
    assert nearest > 1e-3
    assert not np.allclose(
        solver.rng.uniform(chain.lower, chain.upper), np.random.default_rng(0).uniform(chain.lower, chain.upper)
    )


class Recorder(Liar):
    """Records every target it is asked to solve."""

    name = "recorder"

    def __init__(self, chain, **kw):  # type: ignore[no-untyped-def]
        super().__init__(chain, **kw)
        self.targets: list[np.ndarray] = []

    def call(self, prepared):  # type: ignore[no-untyped-def]
        self.targets.append(np.array(prepared[0]))
        return super().call(prepared)


def test_warm_up_solves_real_targets_before_the_timed_ones() -> None:
    # Warming up on the mid-range pose alone runs no step of an iterative solver (its seed is the
    # answer): the first timed solves then paid for the solver's first calls.
    from armtool.ik.bench import WARM_UP_SOLVES

    chain = load_chain(erd(ARMS["ur5"][0]))
    config = BenchConfig(samples=5, repeat=0)
    targets = make_targets(chain, config)
    solver = Recorder(chain)
    run_solver(chain, solver, targets, config)
    warm, timed = solver.targets[:-5], solver.targets[-5:]
    assert np.allclose(timed, targets.poses)
    mid = chain.fk(chain.mid())
    away = [t for t in warm if not np.allclose(t, mid)]
    assert len(away) == WARM_UP_SOLVES
    assert not any(np.allclose(a, p) for a in away for p in targets.poses)  # a stream of their own


def test_blocks_joined_report_like_one_run() -> None:
    # The benchmark script times solvers block by block, taking turns; the joined blocks must give
    # the same verdicts and the same number of timings as one run over every target.
    from armtool.ik import make_solver
    from armtool.ik.bench import join_timed, solver_report, time_solves

    chain = load_chain(erd(ARMS["ur5"][0]))
    config = BenchConfig(samples=12, repeat=0, timeout=0.02)
    targets = make_targets(chain, config)
    solver = make_solver("lm", chain, timeout=0.02)
    whole = solver_report(chain, solver, targets, config, time_solves(solver, targets.poses, targets.seeds))
    blocks = [time_solves(solver, targets.poses[a : a + 5], targets.seeds[a : a + 5]) for a in (0, 5, 10)]
    joined = join_timed(blocks)
    assert len(joined.results) == 12 and joined.wall.shape == (12,) and not joined.batch
    report = solver_report(chain, solver, targets, config, joined)
    assert report.solved == whole.solved and report.samples == 12
    assert report.solves_per_s == 12 / joined.wall.sum()
    liar = solver_report(
        chain, Liar(chain), targets, config, join_timed([time_solves(Liar(chain), targets.poses, targets.seeds)])
    )
    assert liar.claimed_but_wrong == 12


def test_run_bench_takes_turns_block_by_block() -> None:
    # Solvers run whole one after the other would be timed at different CPU speeds: they take
    # turns on blocks of targets (the order rotated), the batch call runs once, mid-way.
    from armtool.ik.bench import Entry, run_bench

    chain = load_chain(erd(ARMS["ur5"][0]))
    config = BenchConfig(samples=10, repeat=0)
    targets = make_targets(chain, config)
    calls: list[tuple[str, int]] = []

    class Logged(Liar):
        def call(self, prepared):  # type: ignore[no-untyped-def]
            hit = np.flatnonzero((targets.poses == prepared[0]).all(axis=(1, 2)))
            calls.append((self.name, int(hit[0]) if hit.size else -1))  # -1: a warm-up target
            return super().call(prepared)

        def call_batch(self, prepared):  # type: ignore[no-untyped-def]
            calls.append((self.name + " (batch)", len(prepared)))
            return [Liar.call(self, p) for p in prepared]

    a, b, c = Logged(chain), Logged(chain), Logged(chain)
    a.name, b.name, c.name = "a", "b", "c"
    entries = [Entry(a), Entry(a, batch=True), Entry(b), Entry(c, limit=3)]
    reports = run_bench(chain, entries, targets, config, block=4)
    assert [(r.solver, r.mode, r.samples) for r in reports] == [
        ("a", "single", 10),
        ("a", "batch", 10),
        ("b", "single", 10),
        ("c", "single", 3),
    ]
    timed = [(name, i) for name, i in calls if i >= 0 and "batch" not in name]
    for name, count in (("a", 10), ("b", 10), ("c", 3)):
        assert [i for n, i in timed if n == name] == list(range(count))
    runs = [name for k, (name, _) in enumerate(timed) if k == 0 or timed[k - 1][0] != name]
    assert runs == ["a", "b", "c", "b", "a", "b"]  # blocks of 4: a b c | b (c done) a | (c) a b
    batch_at = calls.index(("a (batch)", 10))
    assert 0 < batch_at < len(calls) - 1


def test_batch_calls_are_spread_over_the_blocks() -> None:
    from armtool.ik.bench import Entry, time_interleaved

    chain = load_chain(erd(ARMS["ur5"][0]))
    targets = make_targets(chain, BenchConfig(samples=12, repeat=0))
    order: list[str] = []

    class Logged(Liar):
        def call(self, prepared):  # type: ignore[no-untyped-def]
            order.append("single")
            return super().call(prepared)

        def call_batch(self, prepared):  # type: ignore[no-untyped-def]
            order.append("batch")
            return [Liar.call(self, p) for p in prepared]

    solver = Logged(chain)
    timed = time_interleaved([Entry(solver), Entry(solver, batch=True)], targets, block=3, batch_calls=2)
    # Four blocks of three: the calls come before blocks 1 and 3, not both at the start.
    assert order == ["single"] * 3 + ["batch"] + ["single"] * 6 + ["batch"] + ["single"] * 3
    batch = timed["liar (batch)"]
    assert batch.batch and len(batch.results) == 12 and batch.wall.shape == (12,)


def test_interleaving_refuses_entries_it_would_mix_up() -> None:
    # Two entries with one label would solve every block into the same list (2N answers for N).
    import pytest

    from armtool.ik.bench import Entry, time_interleaved

    chain = load_chain(erd(ARMS["ur5"][0]))
    targets = make_targets(chain, BenchConfig(samples=4, repeat=0))
    a, b = Liar(chain), Liar(chain)
    for entries in ([Entry(a), Entry(b)], [Entry(a, limit=0)], [Entry(a, batch=True, limit=2)]):
        with pytest.raises(ValueError):
            time_interleaved(entries, targets)
    with pytest.raises(ValueError):
        time_interleaved([Entry(a)], targets, batch_calls=0)


def test_solve_batch_reads_its_inputs_once(monkeypatch: pytest.MonkeyPatch) -> None:
    # solve_batch's inputs are converted and their shapes checked once, by prepare_batch.
    from armtool.ik import make_solver

    chain = load_chain(erd(ARMS["ur5"][0]))
    targets = make_targets(chain, BenchConfig(samples=4))
    for solver in (Liar(chain), make_solver("lm", chain)):
        seen: list[int] = []
        real = solver._batch_arrays

        def counted(t: np.ndarray, s: np.ndarray, real: Any = real) -> Any:
            seen.append(len(t))
            return real(t, s)

        monkeypatch.setattr(solver, "_batch_arrays", counted)
        assert len(solver.solve_batch(targets.poses, targets.seeds)) == 4
        assert seen == [4], solver.name


def test_the_report_checks_every_answer_once(monkeypatch: pytest.MonkeyPatch) -> None:
    # Every timed answer and every repeated one is checked by armtool's FK once (verify_batch), and
    # the report's verdicts and failure reasons are judge_batch's.
    from armtool.ik import bench, make_solver
    from armtool.ik import solver as solver_module
    from armtool.ik.bench import solver_report, time_solves

    chain = load_chain(erd(ARMS["ur5"][0]))
    config = BenchConfig(samples=8, repeat=3, timeout=0.02)
    targets = make_targets(chain, config)
    rows: list[int] = []
    real_batch, real_one = solver_module.verify_batch, solver_module.verify

    def verify_batch(chain: Any, Q: np.ndarray, *args: Any, **kwargs: Any) -> Any:
        rows.append(len(Q))
        return real_batch(chain, Q, *args, **kwargs)

    def verify(*args: Any, **kwargs: Any) -> Any:
        rows.append(1)
        return real_one(*args, **kwargs)

    monkeypatch.setattr(solver_module, "verify_batch", verify_batch)
    monkeypatch.setattr(solver_module, "verify", verify)
    monkeypatch.setattr(bench, "verify_batch", verify_batch, raising=False)
    for solver in (make_solver("lm", chain, timeout=0.02), Liar(chain)):
        timed = time_solves(solver, targets.poses, targets.seeds)
        rows.clear()
        report = solver_report(chain, solver, targets, config, timed)
        assert sum(rows) == 8 + 3, solver.name
        judged = solver.judge_batch(timed.results, targets.poses)
        assert report.solved == [r.success for r in judged]
        reasons: dict[str, int] = {}
        for r in judged:
            if not r.success:
                reasons[r.reason] = reasons.get(r.reason, 0) + 1
        assert report.failure_reasons == reasons


# ---- closed-form rows: distinct solutions, and the ones a row misses ----------------------------------------------


class HandMade(Solver):
    """Closed form by hand on COAXIAL_2R (the pose depends on q1 + q2 only): for q1 in `starts`,
    (q1, s − q1) with s = the target's q1 + q2; plus `extra` solutions as given (wrong or repeats)."""

    summary = "test double"
    returns_all_solutions = True

    def __init__(self, chain: Any, name: str, starts: list[float], extra: tuple[tuple[float, float], ...] = ()) -> None:
        super().__init__(chain)
        self.name, self.starts, self.extra = name, starts, extra

    def call(self, prepared: Any) -> Any:
        target, seed = prepared
        s = float(np.arctan2(target[1, 0], target[0, 0]))
        qs = [np.array([a, s - a]) for a in self.starts] + [np.array(e) for e in self.extra]
        return Answer(qs[0], True, 0, "", tuple(qs)) if qs else Answer(seed, False, 0, "nothing")


def coaxial_reports(*solvers: HandMade, samples: int = 6) -> dict[str, Any]:
    from armtool.ik.bench import Entry, run_bench

    chain = solvers[0].chain
    config = BenchConfig(samples=samples, repeat=0)
    reports = run_bench(chain, [Entry(s) for s in solvers], make_targets(chain, config), config)
    return {r.solver: r for r in reports}


def test_closed_form_rows_count_distinct_verified_solutions_and_the_ones_they_miss() -> None:
    from lxml import etree

    from armtool.model.chain import chain_from_xml
    from tests.ik.robots import COAXIAL_2R

    chain = chain_from_xml(etree.fromstring(COAXIAL_2R))
    tau = 2 * np.pi
    full = HandMade(chain, "full", [0.1, 0.2, 0.3, 0.1 + tau])  # the last repeats the first, a turn on
    short = HandMade(chain, "short", [0.2, 0.1], extra=((5.0, 5.0),))  # lacks 0.3; (5, 5) is wrong
    none = HandMade(chain, "none", [])
    rows = coaxial_reports(full, short, none)
    assert rows["full"].success_rate == rows["short"].success_rate == 1.0 and rows["none"].success_rate == 0.0
    assert rows["full"].distinct_solutions == 3.0 and rows["short"].distinct_solutions == 2.0
    assert rows["none"].distinct_solutions == 0.0
    assert (rows["full"].missing_solutions, rows["full"].targets_missing_solutions) == (0, 0)
    assert (rows["short"].missing_solutions, rows["short"].targets_missing_solutions) == (6, 6)
    assert (rows["none"].missing_solutions, rows["none"].targets_missing_solutions) == (18, 6)
    # A row's solutions keep the solver's order (the first that passes is its answer's q).
    assert np.allclose(rows["short"].verified[0][0][0], 0.2)


def test_missing_solutions_need_another_closed_form_solver() -> None:
    from lxml import etree

    from armtool.ik.bench import Entry, compare_solutions, run_bench
    from armtool.model.chain import chain_from_xml
    from tests.ik.robots import COAXIAL_2R

    chain = chain_from_xml(etree.fromstring(COAXIAL_2R))
    alone = HandMade(chain, "alone", [0.1, 0.2])
    config = BenchConfig(samples=3, repeat=0)
    targets = make_targets(chain, config)
    reports = run_bench(chain, [Entry(alone), Entry(Liar(chain))], targets, config)
    assert reports[0].missing_solutions is None and reports[0].distinct_solutions == 2.0
    assert reports[1].distinct_solutions is None and reports[1].missing_solutions is None  # not a closed form
    # The same solver's other mode is not another solver.
    twin = [reports[0], run_solver(chain, alone, targets, config)]
    compare_solutions(chain, twin)
    assert twin[0].missing_solutions is None


class Offset(Solver):
    """One solution: the target's configuration, plus `offset` (passes a 1e-5 check, off by > 1e-6 rad)."""

    summary = "test double"
    returns_all_solutions = True

    def __init__(self, chain: Any, name: str, offset: tuple[float, float], truth: Any) -> None:
        super().__init__(chain)
        self.name, self.offset, self.truth = name, np.array(offset), truth

    def call(self, prepared: Any) -> Any:
        target, _ = prepared
        q = self.truth[int(np.argmin([np.abs(self.chain.fk(t) - target).max() for t in self.truth]))] + self.offset
        return Answer(q, True, 0, "", (q,))


def test_two_approximations_of_one_solution_are_not_missing_from_each_other() -> None:
    from lxml import etree

    from armtool.ik.bench import Entry, run_bench
    from armtool.model.chain import chain_from_xml
    from tests.ik.robots import PLANAR_2R

    chain = chain_from_xml(etree.fromstring(PLANAR_2R))
    config = BenchConfig(samples=5, repeat=0)
    targets = make_targets(chain, config)
    exact = Offset(chain, "exact", (0.0, 0.0), targets.q_true)
    near = Offset(chain, "near", (4e-6, -3e-6), targets.q_true)  # a nearest-model solver's answers
    reports = run_bench(chain, [Entry(exact), Entry(near)], targets, config)
    assert [r.success_rate for r in reports] == [1.0, 1.0]
    assert [r.missing_solutions for r in reports] == [0, 0] and [r.distinct_solutions for r in reports] == [1.0, 1.0]


# ---------------------------------------------------------------- native stderr

PANIC = b"thread '<unnamed>' panicked at src/fake.rs:154:54:\ncalled `Option::unwrap()` on a `None` value\n"


class Panicky(Solver):
    """Stands in for IK-Geo's Rust: panics on every third call, its panic hook writing on fd 2
    itself (os.write, past sys.stderr), and the adapter turns the panic into a failed answer."""

    name = "panicky"
    summary = "test double"
    prints_natively = True

    def __init__(self, chain: Any) -> None:
        Solver.__init__(self, chain)
        self.calls = 0

    def call(self, prepared):  # type: ignore[no-untyped-def]
        self.calls += 1
        if self.calls % 3 == 0:
            os.write(2, PANIC)
            return Answer(prepared[1], False, 0, "panicky failed inside its solver (PanicException)")
        return Answer(prepared[1], False, 0, "no solution")


def _planar() -> Any:
    from lxml import etree

    from armtool.model.chain import chain_from_xml
    from tests.ik.robots import PLANAR_2R

    return chain_from_xml(etree.fromstring(PLANAR_2R))


def test_native_stderr_is_held_back_and_summed_up_once(capfd: pytest.CaptureFixture[str]) -> None:
    """The panic text a solver's native code writes on fd 2 during the benchmark does not reach
    stderr; the note counts its lines and panics, by phase, and quotes the first line."""
    from armtool.ik.bench import Entry, native_stderr_note, run_bench

    chain = _planar()
    config = BenchConfig(samples=12, repeat=6)
    solver = Panicky(chain)
    reports = run_bench(chain, [Entry(solver)], make_targets(chain, config), config, block=5)
    err = capfd.readouterr().err
    assert "panicked" not in err and "unwrap" not in err, err
    # 9 warm-up solves (calls 1-9), 12 timed (10-21), 6 repeat (22-27): panics at every third call
    assert solver.calls == 9 + 12 + 6
    assert [phase for phase, _ in solver.native_stderr] == ["warm-up", "timed", "timed", "timed", "repeat"]
    assert reports[0].failure_reasons["panicky failed inside its solver (PanicException)"] == 4
    note = native_stderr_note(solver)
    assert note == (
        "panicky printed 18 lines on stderr during its solves (not shown; 9 Rust panics: 4 on timed targets,"
        " among its row's failures, 5 in untimed warm-up or repeat solves);"
        " the first: thread '<unnamed>' panicked at src/fake.rs:154:54:"
    )


def test_a_quiet_native_solver_has_no_note() -> None:
    from armtool.ik.bench import native_stderr_note

    chain = _planar()
    assert native_stderr_note(Panicky(chain)) == ""


def test_fd_2_moves_once_per_block_outside_the_clock_readings(monkeypatch: pytest.MonkeyPatch) -> None:
    """The capture is entered around each block of calls (the warm-up, each block of timed solves,
    the repeat, the batch call), never per call, and fd 2 moves only outside the clock readings
    that bound each timed call; a solver that does not print natively is never captured."""
    import time

    from armtool.ik import bench
    from armtool.ik.bench import Entry, run_bench

    events: list[str] = []
    real = bench.native_stderr_captured

    @contextmanager
    def logged() -> Iterator[Any]:
        events.append("[")
        with real() as captured:
            yield captured
        events.append("]")

    clock = time.perf_counter

    def perf_counter() -> float:
        events.append("t")
        return clock()

    class Logged(Panicky):
        def call(self, prepared):  # type: ignore[no-untyped-def]
            events.append("c")
            return super().call(prepared)

    class Quiet(Liar):
        def call(self, prepared):  # type: ignore[no-untyped-def]
            events.append("q")
            return super().call(prepared)

    monkeypatch.setattr(bench, "native_stderr_captured", logged)
    monkeypatch.setattr(time, "perf_counter", perf_counter)
    chain = _planar()
    config = BenchConfig(samples=12, repeat=6)
    targets = make_targets(chain, config)
    run_bench(chain, [Entry(Logged(chain)), Entry(Quiet(chain))], targets, config, block=5)
    text = "".join(events)
    blocks = [b.split("]")[0] for b in text.split("[")[1:]]
    assert text.count("[") == text.count("]") == 5
    assert blocks == ["c" * 9, "tct" * 5, "tct" * 5, "tct" * 2, "c" * 6]  # warm-up, 3 timed blocks, repeat
    assert all("q" not in b for b in blocks) and text.count("q") == 9 + 12 + 6

    events.clear()
    bench.time_batch(Logged(chain), targets.poses, targets.seeds)
    assert "".join(events) == "[t" + "c" * 12 + "t]"
