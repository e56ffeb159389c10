"""`lm` batch mode: the configuration-last kinematics it runs on, and the budget of its scalar tail."""

from __future__ import annotations

import time

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
