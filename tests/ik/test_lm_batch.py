"""`lm` batch mode: the configuration-last kinematics, and the batch against one solve at a time."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from armtool.ik import load_chain, make_solver
from armtool.ik.solver import verify
from tests.ik.robots import ARMS, erd


def test_soa_kinematics_match_the_batch_layout() -> None:
    for arm in ("panda", "kinova"):
        relative, base, tip = ARMS[arm]
        chain = load_chain(erd(relative), base, tip)
        Q = chain.random(np.random.default_rng(1), 7)
        T, J = chain.fk_jacobian_batch(Q)
        R, p, Jt = chain.fk_jacobian_soa(Q)
        assert Jt is not None and J is not None
        assert np.allclose(R.transpose(2, 0, 1), T[:, :3, :3], atol=1e-12)
        assert np.allclose(p.T, T[:, :3, 3], atol=1e-12)
        assert np.allclose(Jt.transpose(2, 0, 1), J, atol=1e-12)
        for q, t, j in zip(Q, T, J):
            t_pin, j_pin = chain.fk_jacobian(q)
            assert np.allclose(t, t_pin, atol=1e-12) and np.allclose(j, j_pin, atol=1e-12)


def test_unreachable_targets_do_not_hold_up_the_batch() -> None:
    chain = load_chain(erd(ARMS["ur5"][0]))
    timeout, n = 0.002, 60
    solver = make_solver("lm", chain, timeout=timeout)
    targets = chain.fk_batch(chain.random(np.random.default_rng(2), n))
    far = [3, 17, 41]
    targets[far, :3, 3] = [5.0, 0.0, 0.0]  # out of reach
    seeds = np.tile(chain.mid(), (n, 1))
    start = time.perf_counter()
    results = solver.solve_batch(targets, seeds)
    elapsed = time.perf_counter() - start
    assert elapsed < n * timeout + 0.25  # the whole call's budget, and the tail's share of it
    for i, (r, t) in enumerate(zip(results, targets)):
        assert r.success == verify(chain, r.q, t, 1e-5)[0]
        if i in far:
            assert not r.success and r.reason == "timeout"
    assert sum(r.success for r in results) >= n - len(far) - 1


def test_far_seeds_start_from_the_nearest_table_pose() -> None:
    # As in solve(): targets that are table poses, from the mid-range seed, are answered by their
    # table configuration without an iteration; a target at its seed's own pose keeps the seed.
    relative, base, tip = ARMS["kinova"]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver("lm", chain, timeout=0.05)
    table = solver.table()[3][:40]  # type: ignore[attr-defined]
    near = chain.random(np.random.default_rng(3), 30)
    targets = np.concatenate([chain.fk_batch(table), chain.fk_batch(near)])
    seeds = np.concatenate([np.tile(chain.mid(), (40, 1)), near])
    results = solver.solve_batch(targets, seeds)
    assert all(r.success and r.iterations == 0 for r in results)
    assert np.allclose([r.q for r in results[:40]], wrap(chain, table))
    assert np.allclose([r.q for r in results[40:]], wrap(chain, near))


def wrap(chain: Any, Q: np.ndarray) -> np.ndarray:
    """Continuous joints into [-π, π), as lm returns them."""
    return np.where(chain.continuous, (Q + np.pi) % (2 * np.pi) - np.pi, Q)


def test_batch_answers_equal_single_solves() -> None:
    # The batch runs every target's first tries in one compiled call, then restarts the unsolved
    # ones one by one: each answer and its iteration count are those of solve() on the same target
    # (restarts from the table too; random restarts, rarely reached, draw from the solver's stream).
    chain = load_chain(erd(ARMS["ur5"][0]))
    rng = np.random.default_rng(4)
    targets = chain.fk_batch(chain.random(rng, 50))
    seeds = np.tile(chain.mid(), (50, 1))
    batch = make_solver("lm", chain, timeout=0.05).solve_batch(targets, seeds)
    single = make_solver("lm", chain, timeout=0.05)
    for b, t, s in zip(batch, targets, seeds):
        one = single.solve(t, s)
        assert b.success and one.success
        assert b.iterations == one.iterations and np.array_equal(b.q, one.q)
