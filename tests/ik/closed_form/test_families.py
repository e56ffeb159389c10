"""Every closed-form family on rendered chains of known geometry (and on the chain read from its tip),
and on real arms with a locked joint: the family detected, every returned solution FK-verified, and
the solutions counted against an independent enumeration (lm from many random seeds)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.ik import load_chain, make_solver
from armtool.ik.closed_form import kernel as K
from armtool.ik.solver import Array, rotation_error_batch, verify
from armtool.model.chain import Chain
from tests.ik.robots import ARMS, erd
from tests.ik.test_analytic import UR_LIKE, check_all_solutions, dh_chain, wrapped_distance

# Standard DH rows (d, a, α) after joints 1..6: a spherical wrist is a4 = a5 = d5 = 0 (axes 4, 5, 6
# meet); axes i and i+1 are parallel where α_i = 0, intersect where a_i = 0 (α_i ≠ 0).
WRIST = [(0.33, 0.0, 1.3), (0.0, 0.0, -1.7), (0.07, 0.01, 0.4)]
FAMILY_TABLES = {
    K.WRIST_12_PARALLEL: [(0.3, 0.25, 0.0), (0.1, 0.05, 1.2), (0.05, 0.1, 1.4), *WRIST],
    K.WRIST_23_PARALLEL: [(0.3, 0.05, 1.3), (0.12, 0.43, 0.0), (-0.04, 0.02, 1.5708), *WRIST],
    K.WRIST_12_INTERSECTING: [(0.3, 0.0, 1.1), (0.1, 0.4, 0.7), (0.05, 0.1, 1.3), *WRIST],
    K.WRIST_23_INTERSECTING: [(0.3, 0.15, 1.1), (0.1, 0.0, 0.7), (0.05, 0.1, 1.3), *WRIST],
    K.WRIST_GENERAL: [(0.3, 0.1, 1.2), (0.1, 0.4, 0.3), (0.0, 0.3, 1.4), *WRIST],
    K.UR: UR_LIKE,
}
# The wrist at the base end: axes 1, 2, 3 meet (a1 = a2 = d2 = 0); the rest as a family read from the tip.
REVERSED_TABLES = {
    K.WRIST_23_PARALLEL: [
        (0.3, 0.0, 1.3),
        (0.0, 0.0, -1.7),
        (0.2, 0.1, 1.1),
        (0.1, 0.4, 0.0),
        (0.05, 0.08, 1.2),
        (0.1, 0.0, 0.0),
    ],
    K.WRIST_12_INTERSECTING: [
        (0.3, 0.0, 1.3),
        (0.0, 0.0, -1.7),
        (0.2, 0.1, 1.1),
        (0.1, 0.4, 0.9),
        (0.05, 0.0, 1.2),
        (0.1, 0.0, 0.0),
    ],
    K.WRIST_GENERAL: [
        (0.3, 0.0, 1.3),
        (0.0, 0.0, -1.7),
        (0.2, 0.1, 1.1),
        (0.1, 0.4, 0.9),
        (0.05, 0.2, 1.2),
        (0.1, 0.0, 0.0),
    ],
}


def enumerated(chain: Chain, target: Array, starts: int = 2000, steps: int = 60) -> list[Array]:
    """The distinct solutions that damped Newton steps reach from `starts` random configurations (an
    enumeration independent of the closed form; no joint limits in the steps), each verified and with
    an equivalent modulo 2π within the limits; distinct at 1e-6 rad modulo 2π."""
    Q = chain.random(np.random.default_rng(2), starts)
    for _ in range(steps):
        T, J = chain.fk_jacobian_batch(Q)
        assert J is not None
        e = np.concatenate([target[:3, 3] - T[:, :3, 3], rotation_error_batch(T[:, :3, :3], target[:3, :3])], axis=1)
        JT = J.transpose(0, 2, 1)
        Q = Q + np.linalg.solve(JT @ J + 1e-10 * np.eye(6), (JT @ e[:, :, None]))[:, :, 0]
    found: list[Array] = []
    for q in Q:
        shifted = np.array([_into(v, lo, hi) for v, lo, hi in zip(q, chain.lower, chain.upper)])
        if not np.all(np.isfinite(shifted)) or not verify(chain, shifted, target, 1e-9)[0]:
            continue
        if all(wrapped_distance(shifted, x) > 1e-6 for x in found):
            found.append(shifted)
    return found


def _into(v: float, lo: float, hi: float) -> float:
    """v moved by whole turns into [lo, hi], or NaN."""
    v = lo + (v - lo) % (2 * math.pi)
    return v if v <= hi + 1e-9 else math.nan


def check_family(chain: Chain, code: int, reverse: bool, targets: int = 30, enumerate_first: int = 3) -> None:
    solver = make_solver("analytic", chain)
    assert (solver.geometry.code, solver.geometry.reversed, solver.geometry.near) == (code, reverse, False)
    assert solver.returns_all_solutions and solver.method.startswith("closed form: ")
    rng = np.random.default_rng(code)
    Q = chain.random(rng, targets)
    mid = chain.mid()
    for k, (q, target) in enumerate(zip(Q, chain.fk_batch(Q))):
        result = solver.solve(target, mid)
        check_all_solutions(chain, result, target, mid)
        assert min(wrapped_distance(x, q) for x in result.solutions) < 1e-7
        if k < enumerate_first:
            other = enumerated(chain, target)
            assert len(other) == len(result.solutions), (len(other), len(result.solutions))
            for x in other:
                assert min(wrapped_distance(x, y) for y in result.solutions) < 1e-6


@pytest.mark.parametrize("code", sorted(FAMILY_TABLES))
def test_rendered_family(code: int) -> None:
    check_family(dh_chain(FAMILY_TABLES[code], seed=5), code, reverse=False)


@pytest.mark.parametrize("code", sorted(REVERSED_TABLES))
def test_rendered_family_with_the_wrist_at_the_base(code: int) -> None:
    check_family(dh_chain(REVERSED_TABLES[code], seed=6), code, reverse=True)


# Franka Panda locked at one joint: the families EAIK 1.2.2 reports for the same locks (see ik-bench.md).
PANDA_LOCKS = [
    ("panda_joint7", 0.3, K.WRIST_12_INTERSECTING, True),
    ("panda_joint6", 1.2, K.WRIST_12_INTERSECTING, True),
    ("panda_joint6", 0.0, K.WRIST_12_PARALLEL, True),
    ("panda_joint5", 0.3, K.WRIST_GENERAL, True),
    ("panda_joint5", 0.0, K.WRIST_23_PARALLEL, True),
    ("panda_joint4", -1.5, K.WRIST_23_INTERSECTING, True),
]


@pytest.mark.parametrize(("joint", "value", "code", "reverse"), PANDA_LOCKS)
def test_panda_with_a_locked_joint(joint: str, value: float, code: int, reverse: bool) -> None:
    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip).locked({joint: value})
    check_family(chain, code, reverse, targets=20, enumerate_first=2)


def test_panda_locked_at_the_shoulder_has_no_closed_form() -> None:
    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip).locked({"panda_joint1": 0.0})
    with pytest.raises(ArmtoolError, match="no supported closed form"):
        make_solver("analytic", chain)


def test_seven_joints_hint_at_locking() -> None:
    relative, base, tip = ARMS["panda"]
    with pytest.raises(ArmtoolError) as info:
        make_solver("analytic", load_chain(erd(relative), base, tip))
    assert "Chain.locked" in (info.value.hint or "") and "--lock JOINT=VALUE" in (info.value.hint or "")


def test_locked_solutions_expand_to_the_full_arm() -> None:
    """A locked chain's solutions, expanded, are configurations of the 7-DOF arm that reach the target."""
    relative, base, tip = ARMS["panda"]
    full = load_chain(erd(relative), base, tip)
    chain = full.locked({"panda_joint7": 0.3})
    q7 = full.mid()
    q7[6] = 0.3
    target = full.fk(q7)
    result = make_solver("analytic", chain).solve(target, chain.mid())
    assert result.success
    for x in result.solutions:
        assert np.allclose(full.fk(chain.expand(x)), target, atol=1e-9)
    assert min(wrapped_distance(chain.expand(x), q7) for x in result.solutions) < 1e-7
    assert math.isclose(chain.expand(result.q)[6], 0.3)
