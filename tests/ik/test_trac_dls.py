"""`trac` and `dls`: answers verified and within limits, solve types keep their promises,
DLS stays finite at a singularity, TRAC-IK's wrap-or-clamp and normalization, options checked."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.ik.registry import make_solver
from armtool.ik.solver import Solver, verify
from armtool.ik.solvers.dls import damped_step
from armtool.ik.solvers.trac import SolveType, TracIK, limit_penalty, manipulability, squared_error
from armtool.model.chain import Chain, load_chain
from tests.ik.robots import ARMS, erd

# Planar 3R in the xy plane: a pose (x, y, yaw) has two answers (elbow up/down) where both fit the
# limits. j1's range is wider than 2π, so TRAC-IK wraps it at its limits; j2 and j3 clamp.
PLANAR_3R = """<robot name="planar3r">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-3.5" upper="3.5" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.5 0 0"/><axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.4 0 0"/><axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="l3"/><child link="tool"/><origin xyz="0.3 0 0"/></joint>
</robot>
"""


@pytest.fixture(scope="module")
def planar(tmp_path_factory: pytest.TempPathFactory) -> Chain:
    path = Path(tmp_path_factory.mktemp("planar")) / "planar3r.urdf"
    path.write_text(PLANAR_3R)
    return load_chain(path)


@pytest.fixture(scope="module")
def panda() -> Chain:
    relative, base, tip = ARMS["panda"]
    return load_chain(erd(relative), base, tip)


def check_answers(chain: Chain, solver: Solver, targets: np.ndarray, seeds: np.ndarray) -> int:
    """Solve every target; each q within the limits and each success flag equal to our FK's verdict."""
    solved = 0
    for target, seed in zip(targets, seeds):
        result = solver.solve(target, seed)
        assert np.all(np.isfinite(result.q)) and chain.within_limits(result.q)
        assert result.success == verify(chain, result.q, target, 1e-5)[0]
        solved += result.success
    return solved


# ---- solved and verified -------------------------------------------------------------------------------
@pytest.mark.parametrize("chain_name", ["planar", "panda"])
def test_trac_solves_random_targets_from_mid_seed(chain_name: str, request: pytest.FixtureRequest) -> None:
    chain: Chain = request.getfixturevalue(chain_name)
    rng = np.random.default_rng(3)
    targets = chain.fk_batch(chain.random(rng, 20))
    solver = make_solver("trac", chain, timeout=0.05)
    assert check_answers(chain, solver, targets, np.tile(chain.mid(), (20, 1))) >= 19


@pytest.mark.parametrize("chain_name", ["planar", "panda"])
def test_dls_solves_targets_near_the_seed(chain_name: str, request: pytest.FixtureRequest) -> None:
    chain: Chain = request.getfixturevalue(chain_name)
    rng = np.random.default_rng(4)
    Q = chain.random(rng, 20)
    seeds = chain.clamp(Q + rng.uniform(-0.1, 0.1, Q.shape))  # no restarts: start where a Jacobian method gets there
    solver = make_solver("dls", chain, timeout=1.0)  # generous: correctness, not speed (CI may be loaded)
    assert check_answers(chain, solver, chain.fk_batch(Q), seeds) == 20


def test_dls_failures_are_in_limits_with_a_reason(panda: Chain) -> None:
    rng = np.random.default_rng(5)
    targets = panda.fk_batch(panda.random(rng, 15))
    solver = make_solver("dls", panda, timeout=0.003)
    results = [solver.solve(t, panda.mid()) for t in targets]
    for r in results:
        assert panda.within_limits(r.q)
        assert r.success or r.reason in ("timeout", "stalled at the joint limits")


# ---- solve types --------------------------------------------------------------------------------------
def test_distance_is_never_farther_than_speed(planar: Chain, panda: Chain) -> None:
    """Same solver seed: the search is the same up to speed's answer, which distance then may only improve."""
    for chain, count in ((planar, 8), (panda, 4)):
        rng = np.random.default_rng(6)
        seed = chain.mid()
        for q in chain.random(rng, count):
            target = chain.fk(q)
            speed = make_solver("trac", chain, timeout=0.02, solve_type="speed").solve(target, seed)
            distance = make_solver("trac", chain, timeout=0.02, solve_type="distance").solve(target, seed)
            assert speed.success and distance.success
            assert np.linalg.norm(distance.q - seed) <= np.linalg.norm(speed.q - seed) + 1e-9


def test_distance_finds_the_nearer_elbow(planar: Chain) -> None:
    """A planar 3R pose has two answers; seeded at one of them, distance returns that one."""
    q_true = np.array([0.4, 1.2, -0.7])
    target = planar.fk(q_true)
    result = make_solver("trac", planar, timeout=0.02, solve_type="distance").solve(target, q_true + 0.05)
    assert result.success and np.allclose(result.q, q_true, atol=1e-4)


@pytest.mark.parametrize("kind", [SolveType.MANIP1, SolveType.MANIP2])
def test_manip_solve_types_do_not_lose_to_speed(planar: Chain, panda: Chain, kind: SolveType) -> None:
    """TRAC-IK maximizes penalty · manipulability (its joint-limit penalty times Π σ or σ_min/σ_max)."""
    for chain, count in ((planar, 5), (panda, 3)):
        rng = np.random.default_rng(7)
        for q in chain.random(rng, count):
            target = chain.fk(q)
            speed = make_solver("trac", chain, timeout=0.2).solve(target, chain.mid())
            best = make_solver("trac", chain, timeout=0.2, solve_type=kind).solve(target, chain.mid())
            assert speed.success and best.success

            def score(x: np.ndarray) -> float:
                return limit_penalty(chain, x) * manipulability(chain, x, kind)

            assert score(best.q) >= score(speed.q) - 1e-12


def test_manipulability_definitions(panda: Chain) -> None:
    q = panda.random(np.random.default_rng(8))
    J = panda.jacobian(q)
    s = np.linalg.svd(J, compute_uv=False)
    assert manipulability(panda, q, SolveType.MANIP1) == pytest.approx(math.sqrt(np.linalg.det(J @ J.T)))
    assert manipulability(panda, q, SolveType.MANIP2) == pytest.approx(s[-1] / s[0])
    assert limit_penalty(panda, panda.mid()) > limit_penalty(panda, panda.clamp(panda.mid() + 1.0)) > 0.0
    assert limit_penalty(panda, panda.lower.copy()) == 0.0


# ---- determinism --------------------------------------------------------------------------------------
def test_trac_gives_the_same_answer_twice(panda: Chain) -> None:
    """Restarts come from a stream derived from the solver's seed and the problem, not from a shared one."""
    rng = np.random.default_rng(9)
    targets = panda.fk_batch(panda.random(rng, 6))
    solver = make_solver("trac", panda, timeout=0.05, seed=11)
    first = [solver.solve(t, panda.mid()) for t in targets]
    again = [solver.solve(t, panda.mid()) for t in reversed(targets)][::-1]
    other = [make_solver("trac", panda, timeout=0.05, seed=11).solve(t, panda.mid()) for t in targets]
    for a, b, c in zip(first, again, other):
        assert a.success and np.array_equal(a.q, b.q) and np.array_equal(a.q, c.q)


# ---- pieces -------------------------------------------------------------------------------------------
def test_sqp_gradient_matches_finite_differences(panda: Chain) -> None:
    rng = np.random.default_rng(10)
    target = panda.fk(panda.random(rng))
    for q in panda.random(rng, 3):
        _, grad, _ = squared_error(panda, target, q)
        h = 1e-6
        fd = np.array(
            [
                (squared_error(panda, target, q + h * d)[0] - squared_error(panda, target, q - h * d)[0]) / (2 * h)
                for d in np.eye(panda.n)
            ]
        )
        assert np.allclose(grad, fd, atol=1e-6 * max(1.0, float(np.abs(fd).max())))


def test_wrap_or_clamp_at_the_limits(planar: Chain) -> None:
    solver = make_solver("trac", planar)
    assert isinstance(solver, TracIK)
    out = solver.into_limits(np.array([3.7, 2.6, -2.7]))
    # j1 (range 7 rad > 2π) wraps to the same angle inside its limits; j2, j3 (range 5 rad) clamp.
    assert out == pytest.approx([3.7 - 2 * math.pi, 2.5, -2.5])
    inside = np.array([0.1, -0.2, 0.3])
    assert solver.into_limits(inside) is inside


def test_answers_are_normalized_toward_the_seed(planar: Chain) -> None:
    solver = make_solver("trac", planar)
    assert isinstance(solver, TracIK)
    # j1 = -2.9 and j1 = -2.9 + 2π = 3.38 are the same pose and both within [-3.5, 3.5]: the seed decides.
    q = np.array([-2.9, 0.5, 0.5])
    assert solver.normalize(q, np.array([3.0, 0.0, 0.0])) == pytest.approx([-2.9 + 2 * math.pi, 0.5, 0.5])
    assert solver.normalize(q, np.array([-3.0, 0.0, 0.0])) == pytest.approx(q)


def test_dls_step_stays_bounded_at_a_singularity(planar: Chain) -> None:
    stretched = np.zeros(3)  # arm straight: no joint moves the tip along the arm
    J = planar.jacobian(stretched)
    e = np.array([-0.05, 0.0, 0.0, 0.0, 0.0, 0.0])  # pull the tip inward, along the lost direction
    dq, lam2 = damped_step(J, e, lambda_max=0.05, singular_region=0.05, max_step=0.5)
    assert np.all(np.isfinite(dq)) and np.abs(dq).max() <= 0.5
    assert lam2 == pytest.approx(0.05**2)  # σ_min = 0: full damping
    bent = np.array([0.3, 1.0, -0.8])
    dq_far, lam2_far = damped_step(planar.jacobian(bent), e, lambda_max=0.05, singular_region=0.05, max_step=10.0)
    assert lam2_far == 0.0  # far from singularities: the undamped pseudo-inverse step
    assert dq_far == pytest.approx(np.linalg.pinv(planar.jacobian(bent)) @ e)


def test_dls_from_a_singular_seed_converges_without_nan(planar: Chain) -> None:
    target = planar.fk(np.array([0.1, -0.3, 0.2]))  # just inside the stretched pose
    result = make_solver("dls", planar, timeout=0.05).solve(target, np.zeros(3))
    assert np.all(np.isfinite(result.q)) and planar.within_limits(result.q)
    assert result.success


# ---- options ------------------------------------------------------------------------------------------
def test_options_are_checked(planar: Chain) -> None:
    with pytest.raises(ArmtoolError, match="no solve_type 'fastest'") as info:
        make_solver("trac", planar, solve_type="fastest")
    assert info.value.hint is not None and "speed, distance, manip1, manip2" in info.value.hint
    with pytest.raises(ArmtoolError, match="no option"):
        make_solver("trac", planar, solvetype="speed")
    with pytest.raises(ArmtoolError, match="nr_slice must be an integer"):
        make_solver("trac", planar, nr_slice=0)
    with pytest.raises(ArmtoolError, match="no option"):
        make_solver("dls", planar, damping=1.0)
    with pytest.raises(ArmtoolError, match="max_step must be > 0"):
        make_solver("dls", planar, max_step=0.0)
    with pytest.raises(ArmtoolError, match="lambda_max must be a number"):
        make_solver("dls", planar, lambda_max="big")
    solver = make_solver("trac", planar, solve_type=SolveType.DISTANCE)
    assert isinstance(solver, TracIK) and solver.solve_type is SolveType.DISTANCE
