"""The closed-form peers `eaik` and `ik-geo`: every solution, in armtool's frames and joint order, placed
within the limits; a row with the reason on an arm they cannot take. Skipped without the peer (pip
install 'armtool[peers]')."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik.bench import BenchConfig, Entry, make_targets, run_bench
from armtool.ik.peers import PEERS, make_peer
from armtool.ik.solver import Solver
from armtool.model.chain import Chain, chain_from_xml
from armtool.model.load import load_robot_xml
from tests.ik.robots import ARMS, GENERAL_6R, PLANAR_2R, erd

CLOSED_FORM = ("eaik", "ik-geo")


def arm(name: str) -> tuple[Chain, etree._Element]:
    relative, base, tip = ARMS[name]
    root = load_robot_xml(erd(relative))
    return chain_from_xml(root, base, tip), root


def built(name: str, chain: Chain, root: etree._Element) -> Solver:
    pytest.importorskip(PEERS[name][1])
    solver = make_peer(name, chain, root, timeout=0.005, tolerance=1e-5)
    assert isinstance(solver, Solver), solver
    return solver


def refused(name: str, chain: Chain, root: etree._Element) -> str:
    pytest.importorskip(PEERS[name][1])
    with pytest.raises(ArmtoolError) as err:
        make_peer(name, chain, root, timeout=0.005, tolerance=1e-5)
    return err.value.what


@pytest.mark.parametrize("robot", ["ur5", "kinova"])
@pytest.mark.parametrize("name", CLOSED_FORM)
def test_every_solution_reaches_the_target_within_the_limits(name: str, robot: str) -> None:
    chain, root = arm(robot)
    solver = built(name, chain, root)
    rng = np.random.default_rng(7)
    for q in chain.random(rng, 10):
        target = chain.fk(q)
        result = solver.solve(target, chain.mid())
        assert result.success, result.reason
        assert 2 <= len(result.solutions) <= 8
        for s in result.solutions:  # armtool's FK, armtool's joint order, within the limits
            np.testing.assert_allclose(chain.fk(s), target, atol=1e-9)
            assert chain.within_limits(s)
        distances = [np.linalg.norm(s - chain.mid()) for s in result.solutions]
        assert distances == sorted(distances)  # nearest the seed first; q is the first
        turns = [(np.asarray(s) - q + np.pi) % (2 * np.pi) - np.pi for s in result.solutions]
        assert min(np.abs(t).max() for t in turns) < 1e-6  # the one it came from (modulo 2π: UR5's ±2π limits)


@pytest.mark.parametrize("robot", ["ur5", "kinova"])
def test_eaik_and_ik_geo_find_the_same_solution_sets(robot: str) -> None:
    chain, root = arm(robot)
    rows = [Entry(built(name, chain, root)) for name in CLOSED_FORM]
    config = BenchConfig(samples=30, repeat=0)
    reports = run_bench(chain, rows, make_targets(chain, config), config)
    for r in reports:
        assert r.success_rate == 1.0 and r.missing_solutions == 0 and r.distinct_solutions is not None
        assert r.distinct_solutions >= 4
    assert reports[0].distinct_solutions == reports[1].distinct_solutions


def test_eaik_batch_gives_the_single_answers() -> None:
    chain, root = arm("ur5")
    solver = built("eaik", chain, root)
    assert solver.has_batch()
    targets = make_targets(chain, BenchConfig(samples=8, rng_seed=2))
    batch = solver.solve_batch(targets.poses, targets.seeds)
    for pose, seed, b in zip(targets.poses, targets.seeds, batch):
        one = solver.solve(pose, seed)
        assert b.success and one.success
        np.testing.assert_allclose(b.q, one.q, atol=1e-12)
        assert len(b.solutions) == len(one.solutions)


@pytest.mark.parametrize("name", CLOSED_FORM)
def test_the_row_names_the_decomposition(name: str) -> None:
    chain, root = arm("ur5")
    method = built(name, chain, root).method
    assert method == ("6R-THREE_INNER_PARALLEL" if name == "eaik" else "three_parallel_two_intersecting (closed form)")


# ---- arms they cannot take: a row that says why ------------------------------------------------------------------


@pytest.mark.parametrize("name", CLOSED_FORM)
def test_a_7_joint_arm_needs_a_locked_joint(name: str) -> None:
    chain, root = arm("xarm7")
    why = refused(name, chain, root)
    assert "cannot take 7 joints" in why and "lock one joint of a 7-DOF arm (--lock JOINT=VALUE" in why


def test_eaik_has_no_decomposition_for_a_general_6r_arm() -> None:
    root = etree.fromstring(GENERAL_6R)
    why = refused("eaik", chain_from_xml(root), root)
    assert why.startswith("EAIK knows no subproblem decomposition for this arm (EAIK: 6R-Unknown Kinematic Class)")


def test_ik_geo_takes_a_general_6r_arm_by_its_2d_search() -> None:
    root = etree.fromstring(GENERAL_6R)
    solver = built("ik-geo", chain_from_xml(root), root)
    assert solver.method == "gen_six_dof (2-D search)"


def test_ik_geo_takes_six_joints_only() -> None:
    root = etree.fromstring(PLANAR_2R)
    assert (
        refused("ik-geo", chain_from_xml(root), root)
        == "IK-Geo cannot take 2 joints: its Python package solves 6R chains only"
    )


@pytest.mark.parametrize("name", CLOSED_FORM)
def test_a_prismatic_joint_is_refused(name: str) -> None:
    text = PLANAR_2R.replace('name="j2" type="revolute"', 'name="j2" type="prismatic"')
    root = etree.fromstring(text)
    assert refused(name, chain_from_xml(root), root).endswith("revolute joints only; j2 is prismatic")


# ---- IK-Geo: which decomposition, and its failures as answers -----------------------------------------------------


def test_ik_geo_decomposition_of_real_arms() -> None:
    from armtool.ik.peers.ik_geo_peer import decompose

    ur5, _ = arm("ur5")
    family, method, _, _, P = decompose(ur5)
    assert (family, method) == ("three_parallel_two_intersecting", "closed form")
    np.testing.assert_allclose(P[5], 0.0, atol=1e-12)  # axes 4 and 5 meet: their points are one
    kinova, _ = arm("kinova")
    family, _, _, _, P = decompose(kinova)
    assert family == "spherical_two_intersecting"
    np.testing.assert_allclose(P[[1, 4, 5]], 0.0, atol=1e-12)  # shoulder axes meet, the wrist's three meet
    general = chain_from_xml(etree.fromstring(GENERAL_6R))
    assert decompose(general)[:2] == ("gen_six_dof", "2-D search")


def test_ik_geo_two_parallel_axes_take_the_1d_search() -> None:
    from armtool.ik.peers.ik_geo_peer import decompose

    # GENERAL_6R with joint 3's frame turned like joint 2's: axes 1 and 2 (0-based) parallel.
    text = GENERAL_6R.replace('rpy="0.2 -0.4 0.1"', 'rpy="0 0 0.1"')
    assert decompose(chain_from_xml(etree.fromstring(text)))[:2] == ("two_parallel", "1-D search")


def test_ik_geo_panic_is_an_answer_with_its_reason() -> None:
    chain, root = arm("ur5")
    solver: Any = built("ik-geo", chain, root)

    class Panic(BaseException):  # what pyo3 raises for a Rust panic derives from BaseException
        pass

    def panics(*args: Any) -> Any:
        raise Panic("called `Option::unwrap()` on a `None` value")

    solver._ik = panics
    result = solver.solve(chain.fk(chain.mid() + 0.3), chain.mid())
    assert not result.success
    assert result.reason == "ik-geo failed inside its solver (Panic: called `Option::unwrap()` on a `None` value)"


def test_ik_geo_least_squares_only_answers_say_so() -> None:
    chain, root = arm("ur5")
    solver: Any = built("ik-geo", chain, root)
    solver._ik = lambda R, t: [([0.1] * 6, True)]  # what its searches return: approximations
    result = solver.solve(chain.fk(chain.mid() + 0.3), chain.mid())
    assert not result.success and "least-squares (approximate) solutions only" in result.reason


@pytest.mark.parametrize("name", CLOSED_FORM)
def test_the_timed_call_hands_the_prepared_input_over_unchanged(name: str) -> None:
    # The conversion into the peer's tool frame (T·C⁻¹) is prepare's, untimed: call() passes on the
    # very objects prepare made (a conversion inside it would be timed in this row and no other).
    chain, root = arm("ur5")
    solver: Any = built(name, chain, root)
    seen: list[Any] = []
    solver._ik = lambda *args: seen.extend(args) or []
    prepared = solver.prepare(chain.fk(chain.mid() + 0.2), chain.mid())
    solver.call(prepared)
    assert len(seen) == len(prepared) - 1 and all(a is b for a, b in zip(seen, prepared))
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = (
        (np.array(seen[0]).T, seen[1]) if name == "ik-geo" else (seen[0][:3, :3], seen[0][:3, 3])
    )
    # ... and what it hands over is the target in the peer's frame: the peer's FK there is the target's.
    np.testing.assert_allclose(pose @ solver._tool, chain.fk(chain.mid() + 0.2), atol=1e-12)
