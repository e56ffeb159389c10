"""The KDL ports `kdl-nr-jl` and `kdl-lma`: KDL's steps, our verdict, limits, determinism, the clock."""

from __future__ import annotations

import glob
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from lxml import etree

from armtool.ik.registry import make_solver
from armtool.ik.solver import Array, pose_error, verify
from armtool.model.chain import Chain, chain_from_xml, load_chain

# Planar 3R in the xy plane; joint 1 only reaches [-0.5, 0.5] rad.
PLANAR_3R = """<robot name="planar3r">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-0.5" upper="0.5" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="1.0 0 0"/><axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.8 0 0"/><axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="l3"/><child link="tool"/><origin xyz="0.5 0 0"/></joint>
</robot>"""

# LMA's own test is on the weighted error (rotation × 0.01): to meet an unweighted tolerance of
# 1e-5 its eps must be 100× smaller. With KDL's default eps (= tolerance) rotation errors up to
# 1e-3 rad pass KDL's test and fail ours.
LMA_STRICT = {"eps": 1e-7}


def planar() -> Chain:
    return chain_from_xml(etree.fromstring(PLANAR_3R), "base", "tool")


def panda() -> Chain:
    hits = glob.glob(f"{sys.prefix}/**/example-robot-data/robots/panda_description/urdf/panda.urdf", recursive=True)
    if not hits:
        pytest.skip("example-robot-data (Panda) not installed")
    return load_chain(Path(hits[0]), "panda_link0", "panda_hand")


def near_targets(chain: Chain, count: int, radius: float, rng_seed: int) -> tuple[Array, Array]:
    """Configurations within `radius` of mid-range (and within limits), and their poses."""
    rng = np.random.default_rng(rng_seed)
    Q = chain.clamp(chain.mid() + rng.uniform(-radius, radius, (count, chain.n)))
    return Q, chain.fk_batch(Q)


@pytest.mark.parametrize("make_chain", [planar, panda])
@pytest.mark.parametrize(("name", "options"), [("kdl-nr-jl", {}), ("kdl-lma", LMA_STRICT)])
def test_solves_targets_near_the_seed(make_chain: Callable[[], Chain], name: str, options: dict[str, Any]) -> None:
    chain = make_chain()
    solver = make_solver(name, chain, timeout=0.05, **options)
    _, targets = near_targets(chain, 10, 0.3, rng_seed=1)
    for target in targets:
        result = solver.solve(target, chain.mid())
        assert result.success, result.reason
        ok, pos, rot = verify(chain, result.q, target, 1e-5)
        assert (
            ok and pos == pytest.approx(result.position_error_m) and rot == pytest.approx(result.orientation_error_rad)
        )
        assert result.iterations >= 1


def test_nr_jl_step_is_kdl_pinv_then_clamp() -> None:
    """One CartToJnt call: q + V S⁺ Uᵀ e (σ < 1e-5 dropped), clamped into the limits."""
    chain = panda()
    rng = np.random.default_rng(3)
    seed = chain.mid() + rng.uniform(-0.5, 0.5, chain.n)
    target = chain.fk(chain.random(rng))
    T, J = chain.fk_jacobian(seed)
    expected = chain.clamp(seed + np.linalg.pinv(J, rcond=1e-5 / np.linalg.norm(J, 2)) @ pose_error(T, target))
    one = make_solver("kdl-nr-jl", chain, timeout=1.0, max_calls=1).solve(target, seed)
    assert one.iterations == 1
    np.testing.assert_allclose(one.q, expected, atol=1e-12)


def test_nr_jl_never_leaves_the_limits() -> None:
    chain = panda()
    solver = make_solver("kdl-nr-jl", chain, timeout=1.0, max_calls=60)
    rng = np.random.default_rng(4)
    for target in chain.fk_batch(chain.random(rng, 25)):
        result = solver.solve(target, chain.mid())
        assert np.all(result.q >= chain.lower) and np.all(result.q <= chain.upper)


def test_target_reachable_only_outside_the_limits() -> None:
    """LMA ignores limits and converges there: our verification says no. NR_JL stays inside and fails."""
    chain = planar()
    q_out = np.array([2.0, 0.3, 0.2])  # joint 1 far beyond its 0.5 rad limit, in both elbow branches
    target = chain.fk(q_out)
    lma = make_solver("kdl-lma", chain, timeout=0.05, **LMA_STRICT).solve(target, chain.mid())
    assert not lma.success
    assert lma.reason == "converged outside the joint limits (LMA ignores them)"
    assert lma.position_error_m < 1e-5 and not chain.within_limits(lma.q)
    nr = make_solver("kdl-nr-jl", chain, timeout=0.01).solve(target, chain.mid())
    assert not nr.success and chain.within_limits(nr.q)


@pytest.mark.parametrize(("name", "options"), [("kdl-nr-jl", {}), ("kdl-lma", {})])
def test_deterministic_for_the_same_seed(name: str, options: dict[str, Any]) -> None:
    """Same target and seed → the same q bit for bit, solved or not (max_calls: a budget the clock cannot shift)."""
    chain = panda()
    rng = np.random.default_rng(5)
    targets = chain.fk_batch(chain.random(rng, 8))
    first = make_solver(name, chain, timeout=10.0, max_calls=40, **options)
    second = make_solver(name, chain, timeout=10.0, max_calls=40, **options)
    for target in targets:
        a, b, c = first.solve(target, chain.mid()), first.solve(target, chain.mid()), second.solve(target, chain.mid())
        assert np.array_equal(a.q, b.q) and np.array_equal(a.q, c.q)
        assert a.success == b.success == c.success and a.iterations == b.iterations == c.iterations


@pytest.mark.parametrize("name", ["kdl-nr-jl", "kdl-lma"])
def test_timeout_is_respected(name: str) -> None:
    """Unreachable targets run out the clock; one LMA call (500 iterations) must not overrun it."""
    chain = panda()
    timeout = 0.005
    solver = make_solver(name, chain, timeout=timeout)
    far = np.eye(4)
    far[:3, 3] = [3.0, 0.0, 0.5]  # 3 m away: the Panda reaches ~0.9 m
    rng = np.random.default_rng(6)
    for target in [far, *chain.fk_batch(chain.random(rng, 6))]:
        t0 = time.perf_counter()
        result = solver.solve(target, chain.mid())
        elapsed = time.perf_counter() - t0
        assert elapsed < timeout + 0.05
        if target is far:
            assert not result.success and result.reason == "timeout"


def test_kdl_default_lma_eps_is_weighted() -> None:
    """KDL's default eps (= tolerance) stops on ‖(Δp, 0.01·Δω)‖ < 1e-5: the answers it gives are
    within 1e-5 in position and 1e-3 rad in rotation, and our verdict says why it rejects the rest."""
    chain = panda()
    solver = make_solver("kdl-lma", chain, timeout=0.05)
    _, targets = near_targets(chain, 6, 0.3, rng_seed=7)
    for target in targets:
        result = solver.solve(target, chain.mid())
        assert result.position_error_m < 1e-5 and result.orientation_error_rad < 1e-3
        assert result.success or result.reason.startswith("KDL's test weights rotation by 0.01")
