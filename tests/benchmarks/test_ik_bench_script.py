"""benchmarks/ik_bench.py's rounds: the solvers take turns (armtool.ik.bench.time_interleaved), and
a machine probe is timed after every block."""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path
from typing import Any

import numpy as np

from armtool.ik import load_chain
from armtool.ik.bench import BenchConfig, Entry, make_targets
from armtool.ik.solver import IKResult, Solver
from tests.ik.robots import ARMS, erd

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "ik_bench.py"


def load_script() -> Any:
    spec = importlib.util.spec_from_file_location("ik_bench_script", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up by name
    spec.loader.exec_module(module)
    return module


class Seedy(Solver):
    """Answers with the seed at once."""

    summary = "test double"

    def solve(self, target: np.ndarray, seed: np.ndarray) -> IKResult:
        return IKResult(False, np.asarray(seed, dtype=float), 1.0, 1.0, 0)


def test_every_round_has_its_probe_and_each_solver_in_probe_units() -> None:
    script = load_script()
    chain = load_chain(erd(ARMS["ur5"][0]))
    targets = make_targets(chain, BenchConfig(samples=10))
    a, b = Seedy(chain), Seedy(chain)
    a.name, b.name = "a", "b"
    entries = [Entry(a), Entry(a, batch=True), Entry(b, limit=3)]
    machine = script.Machine()
    for r in range(2):
        args = argparse.Namespace(block=4, batch_calls=2)
        timed = script.interleaved_round(entries, targets, args, r, machine)
        assert {label: len(t.results) for label, t in timed.items()} == {"a": 10, "a (batch)": 10, "b": 3}
    assert len(machine.probes) == 2 and min(machine.probes) > 0
    assert set(machine.relative) == {"a", "b"} and all(len(v) == 2 for v in machine.relative.values())
    assert all(x > 0 for v in machine.relative.values() for x in v)
