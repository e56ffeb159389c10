"""benchmarks/ik_bench.py's rounds: every solver solves every target once per round, taking turns."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from typing import Any

import numpy as np

from armtool.ik import load_chain
from armtool.ik.bench import BenchConfig, make_targets
from armtool.ik.solver import IKResult
from tests.ik.robots import ARMS, erd

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "ik_bench.py"


def load_script() -> Any:
    spec = importlib.util.spec_from_file_location("ik_bench_script", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up by name
    spec.loader.exec_module(module)
    return module


class Log:
    def __init__(self) -> None:
        self.calls: list[tuple[str, int]] = []


class Solver:
    def __init__(self, name: str, log: Log, poses: np.ndarray) -> None:
        self.name, self.log, self.poses = name, log, poses

    def index(self, target: np.ndarray) -> int:
        return int(np.flatnonzero((self.poses == target).all(axis=(1, 2)))[0])

    def solve(self, target: np.ndarray, seed: np.ndarray) -> IKResult:
        self.log.calls.append((self.name, self.index(target)))
        return IKResult(False, np.asarray(seed, dtype=float), 1.0, 1.0, 0)

    def solve_batch(self, targets: np.ndarray, seeds: np.ndarray) -> list[IKResult]:
        self.log.calls.append((self.name + " (batch)", len(targets)))
        return [IKResult(False, np.asarray(s, dtype=float), 1.0, 1.0, 0) for s in seeds]


def test_solvers_take_turns_block_by_block() -> None:
    script = load_script()
    chain = load_chain(erd(ARMS["ur5"][0]))
    targets = make_targets(chain, BenchConfig(samples=10))
    log = Log()
    a, b, c = (Solver(name, log, targets.poses) for name in "abc")
    runs = [script.Run("a", a), script.Run("a (batch)", a, batch=True), script.Run("b", b), script.Run("c", c, limit=3)]
    machine = script.Machine()
    timed = script.interleaved_round(runs, targets, 4, 0, machine)
    assert len(machine.probes) == 1 and machine.probes[0] > 0
    assert set(machine.relative) == {"a", "b", "c"}  # per single-solve run, in probe units
    for label, count in (("a", 10), ("b", 10), ("c", 3), ("a (batch)", 10)):
        assert len(timed[label].results) == count
    singles = [(name, i) for name, i in log.calls if "batch" not in name]
    for name, count in (("a", 10), ("b", 10), ("c", 3)):
        assert [i for n, i in singles if n == name] == list(range(count))  # every target once, in order
    # Block by block, the order rotated: block 0 a, b, c (4 + 4 + 3 solves); block 1 b, (c is
    # done), a; block 2 (c), a, b.
    order = [name for k, (name, _) in enumerate(singles) if k == 0 or singles[k - 1][0] != name]
    assert order == ["a", "b", "c", "b", "a", "b"]
    assert log.calls.index(("a (batch)", 10)) > 0  # the batch call runs mid-round, not first
