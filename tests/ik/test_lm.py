"""armtool's `lm` solver: every answer verified, limits respected, batch equals single in quality."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.ik import load_chain, make_solver
from armtool.ik.solver import verify
from tests.ik.robots import ARMS, erd


@pytest.mark.parametrize("arm", ["panda", "ur5"])
def test_solves_random_targets_from_mid_seed(arm: str) -> None:
    relative, base, tip = ARMS[arm]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver("lm", chain, timeout=0.05)
    rng = np.random.default_rng(1)
    targets = chain.fk_batch(chain.random(rng, 40))
    results = [solver.solve(t, chain.mid()) for t in targets]
    assert sum(r.success for r in results) >= 39
    for r, t in zip(results, targets):
        assert chain.within_limits(r.q)
        if r.success:
            ok, pos, rot = verify(chain, r.q, t, 1e-5)
            assert ok and pos == pytest.approx(r.position_error_m) and rot == pytest.approx(r.orientation_error_rad)


def test_batch_solves_and_verifies() -> None:
    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver("lm", chain, timeout=0.05)
    rng = np.random.default_rng(2)
    targets = chain.fk_batch(chain.random(rng, 100))
    results = solver.solve_batch(targets, np.tile(chain.mid(), (100, 1)))
    assert len(results) == 100 and sum(r.success for r in results) >= 99
    for r, t in zip(results, targets):
        assert r.success == verify(chain, r.q, t, 1e-5)[0]


def test_unreachable_target_fails_with_reason() -> None:
    chain = load_chain(erd(ARMS["ur5"][0]))
    target = np.eye(4)
    target[:3, 3] = [5.0, 0, 0]
    result = make_solver("lm", chain, timeout=0.002).solve(target, chain.mid())
    assert not result.success and result.reason == "timeout"


def test_bad_options_and_names() -> None:
    chain = load_chain(erd(ARMS["ur5"][0]))
    with pytest.raises(ArmtoolError, match="no option"):
        make_solver("lm", chain, dampin=1)
    with pytest.raises(ArmtoolError, match="unknown solver 'lmm'.*did you mean 'lm'"):
        make_solver("lmm", chain)
    with pytest.raises(ArmtoolError, match="timeout must be > 0"):
        make_solver("lm", chain, timeout=0)
