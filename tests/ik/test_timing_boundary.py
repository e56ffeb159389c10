"""One timing boundary for every solver: what `ik-bench` times is the solver's own call, nothing of armtool's.

A profiler watches the timed region of the benchmark's own timing code (`time_solves`,
`time_batch`: between the two clock readings that bound a solve) and records every function that
runs inside it. armtool's answer check (`verify`, `judge`) must never be among them, for any solver,
armtool's own or a peer; nor the building of armtool's answer from a solver's output (`Answer`,
`answer`, wrapping continuous joints), which every peer's adapter does outside the timing; and a
peer's timed region holds nothing but the peer's library (no conversion of the target by armtool
or Pinocchio, which only that row would pay).
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from types import FrameType
from typing import Any

import numpy as np
import pytest

from armtool.ik import bench
from armtool.ik import solver as solver_module
from armtool.ik.bench import BenchConfig, make_targets, time_batch, time_solves
from armtool.ik.modes import SeedMode
from armtool.ik.peers import PEERS, make_peer
from armtool.ik.registry import SOLVERS, make_solver
from armtool.ik.solver import Answer, IKResult, Solver
from armtool.ik.solvers import lm_kernel
from armtool.model.chain import chain_from_xml
from armtool.model.load import load_robot_xml
from tests.ik.robots import ARMS, erd

# armtool's check of an answer: never inside the timing.
CHECKS = {
    solver_module.verify.__code__,
    solver_module.verify_batch.__code__,
    solver_module.pose_error_batch.__code__,
    solver_module.rotation_error.__code__,
    Solver.judge.__code__,
    Solver.judge_batch.__code__,
    Solver.solve.__code__,
    Solver.solve_batch.__code__,
}
# armtool's building of an answer from a solver's own output: never inside the timing either.
BUILDS = {Answer.__init__.__code__: "Answer(...)", IKResult.__init__.__code__: "IKResult(...)"}
BUILD_NAMES = {"answer", "answer_batch", "_wrap"}  # armtool's result-reading methods, by name
ARMTOOL = solver_module.__file__.rsplit("/ik/", 1)[0]


def armtool_code(watch: Watch) -> list[Any]:
    return [c for c in watch.python if c.co_filename.startswith(ARMTOOL)]


def builds(watch: Watch) -> list[str]:
    """armtool's answer building seen inside the timed regions."""
    found = {BUILDS[c] for c in watch.python if c in BUILDS}
    found |= {
        f"{c.co_name} ({c.co_filename.rsplit('/', 1)[-1]})" for c in armtool_code(watch) if c.co_name in BUILD_NAMES
    }
    return sorted(found)


class Watch:
    """Records the functions called inside the benchmark's timed regions."""

    def __init__(self) -> None:
        self.inside = False
        self.python: list[Any] = []  # code objects of Python functions entered
        self.native: list[Any] = []  # C functions called (builtins, extension modules)

    def profile(self, frame: FrameType, event: str, arg: Any) -> None:
        if not self.inside:
            return
        if event == "call":
            self.python.append(frame.f_code)
        elif event == "c_call":
            self.native.append(arg)


@contextmanager
def watching(monkeypatch: pytest.MonkeyPatch) -> Iterator[Watch]:
    """Every perf_counter() read by the benchmark's timing functions opens or closes a timed region."""
    watch = Watch()
    real = time.perf_counter
    timers = {time_solves.__code__, time_batch.__code__}

    def clock() -> float:
        caller = sys._getframe(1).f_code
        if caller in timers:
            watch.inside = not watch.inside
        return real()

    monkeypatch.setattr(bench.time, "perf_counter", clock)
    sys.setprofile(watch.profile)
    try:
        yield watch
    finally:
        sys.setprofile(None)
        watch.inside = False


def targets_for(chain: Any, count: int = 4) -> Any:
    return make_targets(chain, BenchConfig(samples=count, rng_seed=3))


def arm(name: str) -> tuple[Any, Any]:
    relative, base, tip = ARMS[name]
    root = load_robot_xml(erd(relative))
    return root, chain_from_xml(root, base, tip)


def timed_functions(monkeypatch: pytest.MonkeyPatch, s: Solver, batch: bool) -> Watch:
    targets = targets_for(s.chain)
    s.solve(targets.poses[0], targets.seeds[0])  # loaded and warm: the first call's imports are not the point
    with watching(monkeypatch) as watch:
        if batch:
            time_batch(s, targets.poses, targets.seeds)
        else:
            time_solves(s, targets.poses, targets.seeds)
    assert not watch.inside  # every region that opened closed
    return watch


@pytest.mark.parametrize("name", sorted(SOLVERS))
def test_armtools_solvers_are_timed_without_the_answer_check(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    _, chain = arm("ur5")
    s = make_solver(name, chain, timeout=0.002)
    for batch in (False, True) if s.has_batch() else (False,):
        watch = timed_functions(monkeypatch, s, batch)
        assert watch.python, "nothing was timed"
        checked = [c.co_name for c in watch.python if c in CHECKS]
        assert not checked, f"{name} runs armtool's answer check inside its timed call: {checked}"
        built = builds(watch)
        assert not built, f"{name} builds armtool's answer inside its timed call (the peers do not): {built}"


@pytest.mark.parametrize("arm_name", ["ur5", "kinova"])  # Kinova: continuous joints, which lm wraps
def test_lm_builds_no_answer_inside_its_timed_call(arm_name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    # Targets that need restarts too (from a random seed), whose answer lm's restarts assemble.
    _, chain = arm(arm_name)
    s = make_solver("lm", chain, timeout=0.002)
    targets = make_targets(chain, BenchConfig(samples=12, rng_seed=5, seed_mode=SeedMode.RANDOM))
    s.solve(targets.poses[0], targets.seeds[0])
    for batch in (False, True):
        with watching(monkeypatch) as watch:
            (time_batch if batch else time_solves)(s, targets.poses, targets.seeds)
        assert watch.python and not builds(watch), builds(watch)


@pytest.mark.parametrize("name", sorted(PEERS))
def test_peers_are_timed_on_their_own_call_only(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip(PEERS[name][1])
    root, chain = arm("ur5")
    s = make_peer(name, chain, root, timeout=0.002, tolerance=1e-5)
    assert isinstance(s, Solver)
    for batch in (False, True) if s.has_batch() else (False,):  # eaik: IK_batched too
        watch = timed_functions(monkeypatch, s, batch)
        ours = {c.co_name for c in armtool_code(watch)}
        # The adapter's call() is the only armtool code inside the timing: no check, no conversion; a
        # peer looped until its timeout (pykdl, as TRAC-IK's benchmark runs KDL) reads the clock.
        entry = "call_batch" if batch else "call"
        assert ours - {"clock"} == {entry}, f"{name}: armtool code inside the timed {entry}: {sorted(ours)}"
        assert not builds(watch), f"{name}: armtool builds its answer inside the timed call: {builds(watch)}"
        pinocchio = [f for f in watch.native if (getattr(f, "__module__", None) or "").startswith("pinocchio")]
        assert not pinocchio, f"{name}: Pinocchio converts its inputs inside the timing: {pinocchio}"


class Slow(Solver):
    """Preparing the inputs and reading the output take 20 ms each; the call itself nothing."""

    name = "slow-edges"
    summary = "test double"

    def prepare(self, target: Any, seed: Any) -> Any:
        time.sleep(0.02)
        return target, seed

    def call(self, prepared: Any) -> Answer:
        return Answer(np.asarray(prepared[1], dtype=float), True)

    def answer(self, raw: Any) -> Answer:
        time.sleep(0.02)
        return super().answer(raw)


def test_preparing_and_reading_are_outside_the_timing() -> None:
    _, chain = arm("ur5")
    s = Slow(chain)
    targets = targets_for(chain, 3)
    timed = time_solves(s, targets.poses, targets.seeds)
    assert timed.wall.max() < 0.005 and timed.cpu.max() < 0.005
    batch = time_batch(s, targets.poses, targets.seeds)
    assert batch.wall.max() < 0.005


def test_the_cpu_clock_is_read_outside_the_wall_timing(monkeypatch: pytest.MonkeyPatch) -> None:
    # process_time() is a system call (~1 µs on the development VM, a quarter of EAIK's solve): read
    # inside the wall-clock window, it would be timed in every row. Here each read takes 10 ms.
    _, chain = arm("ur5")
    s = Slow(chain)
    s.prepare = lambda target, seed: (target, seed)  # type: ignore[method-assign]
    s.answer = lambda raw: raw  # type: ignore[method-assign]
    real = time.process_time

    def slow_cpu_clock() -> float:
        time.sleep(0.01)
        return real()

    monkeypatch.setattr(bench.time, "process_time", slow_cpu_clock)
    targets = targets_for(chain, 3)
    assert time_solves(s, targets.poses, targets.seeds).wall.max() < 0.005
    assert time_batch(s, targets.poses, targets.seeds).wall.max() < 0.005


def test_every_answer_is_checked_outside_the_timing_lm_included() -> None:
    # The report's verdict is armtool's FK check of every answer: a solver (lm too) whose answers
    # were wrong would be counted as failing, whatever it claimed.
    _, chain = arm("ur5")
    config = BenchConfig(samples=6, repeat=0)
    targets = make_targets(chain, config)
    lm = make_solver("lm", chain)

    def claims_the_seed(prepared: Any) -> np.ndarray:  # lm's raw output: solved, 1 iteration, q = the seed
        n = chain.n
        out = np.zeros(lm_kernel.OUT_HEAD + 2 * n)
        out[0], out[1] = lm_kernel.SOLVED, 1
        out[lm_kernel.OUT_HEAD : lm_kernel.OUT_HEAD + n] = prepared[1]
        return out

    lm.call: Callable[[Any], Any] = claims_the_seed  # type: ignore[method-assign]
    report = bench.solver_report(chain, lm, targets, config, time_solves(lm, targets.poses, targets.seeds))
    assert report.success_rate == 0.0 and report.claimed_but_wrong == 6
