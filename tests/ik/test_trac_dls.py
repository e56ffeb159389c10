"""`trac` and `dls`: answers verified and within limits, solve types behave, options checked."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.ik import load_chain, make_solver
from armtool.ik.solver import verify
from tests.ik.robots import ARMS, PLANAR_2R, erd


@pytest.fixture
def planar(tmp_path: Path):  # type: ignore[no-untyped-def]
    path = tmp_path / "planar.urdf"
    path.write_text(PLANAR_2R)
    return load_chain(path)


@pytest.mark.parametrize("name", ["trac", "dls"])
def test_reachable_targets_are_solved_and_verified(name: str) -> None:
    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver(name, chain, timeout=0.05)
    rng = np.random.default_rng(5)
    Q = chain.random(rng, 10)
    # near the seed: every method gets there
    results = [solver.solve(chain.fk(q), np.clip(q + 0.05, chain.lower, chain.upper)) for q in Q]
    assert sum(r.success for r in results) >= 9
    for r, q in zip(results, Q):
        assert chain.within_limits(r.q)
        assert r.success == verify(chain, r.q, chain.fk(q), 1e-5)[0]


def test_trac_solve_types(planar) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(1)
    seed = planar.mid()
    for q in planar.random(rng, 5):
        target = planar.fk(q)
        speed = make_solver("trac", planar, timeout=0.02, solve_type="speed").solve(target, seed)
        distance = make_solver("trac", planar, timeout=0.02, solve_type="distance").solve(target, seed)
        assert speed.success and distance.success
        # a planar 2R has two answers (elbow up/down): distance returns the nearer one
        assert np.linalg.norm(distance.q - seed) <= np.linalg.norm(speed.q - seed) + 1e-9


def test_dls_near_singularity_stays_finite(planar) -> None:  # type: ignore[no-untyped-def]
    stretched = np.array([0.3, 0.0])  # elbow straight: the Jacobian loses rank
    target = planar.fk(stretched)
    result = make_solver("dls", planar, timeout=0.01).solve(target, np.array([0.2, 0.01]))
    assert np.all(np.isfinite(result.q)) and result.position_error_m < 1e-3


def test_options_are_checked(planar) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ArmtoolError, match="solve_type"):
        make_solver("trac", planar, solve_type="fastest")
    with pytest.raises(ArmtoolError, match="no option"):
        make_solver("dls", planar, damping=1.0)
