"""The lanes (closed_form/lanes.py) against the general kernel, family by family: the same solutions
(to ~1e-9 rad), counts and statuses as single calls (kernel.solve_one, what `call` runs), every one
FK-verified; the special cases left to the kernel (then equal bit for bit); the polynomial atan2
against libm's."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from armtool.ik import load_chain, make_solver
from armtool.ik.closed_form import kernel as K
from armtool.ik.closed_form import lanes
from armtool.ik.solver import Array, verify
from armtool.model.chain import Chain
from tests.ik.closed_form.test_families import FAMILY_TABLES, REVERSED_TABLES
from tests.ik.robots import ARMS, erd
from tests.ik.test_analytic import UR, dh_chain

SPHERICAL = (K.WRIST_12_PARALLEL, K.WRIST_23_PARALLEL, K.WRIST_12_INTERSECTING, K.WRIST_23_INTERSECTING)


def test_atan2_matches_libm() -> None:
    rng = np.random.default_rng(0)
    ys, xs = rng.normal(size=2000) * 10.0 ** rng.uniform(-8, 8, 2000), rng.normal(size=2000)
    special = [(0.0, 1.0), (0.0, -1.0), (1.0, 0.0), (-1.0, 0.0), (1.0, 1.0), (-1.0, -1.0), (0.0, 0.0), (1e-300, -1.0)]
    for y, x in [*zip(ys, xs), *special]:
        assert abs(lanes.atan2(y, x) - math.atan2(y, x)) <= 4.5e-16 * max(1.0, abs(math.atan2(y, x)))
    assert math.isnan(lanes.atan2(math.nan, 1.0))


def singles(solver: object, targets: Array, seeds: Array) -> Array:
    """Each target solved by kernel.solve_one, as `call` does."""
    rows = K.empty_out(len(targets))
    for row, target, seed in zip(rows, targets, seeds):
        K.solve_one(solver._model, target, seed, row)  # type: ignore[attr-defined]
    return rows


def batch(chain: Chain, Q: Array, family: int) -> tuple[object, Array, Array, Array]:
    """The lanes' rows and single calls' rows for FK of Q from the middle (the solver's lanes are `family`'s)."""
    solver = make_solver("analytic", chain)
    assert solver._lanes == family  # type: ignore[attr-defined]
    targets = np.ascontiguousarray(chain.fk_batch(Q))
    seeds = np.tile(chain.mid(), (len(Q), 1))
    ours = K.empty_out(len(Q))
    assert lanes.solve(family, solver._model, targets, seeds, ours) == K.SOLVED  # type: ignore[attr-defined]
    return solver, targets, ours, singles(solver, targets, seeds)


def compare(chain: Chain, Q: Array, family: int) -> None:
    """Equal headers (counts, status, seed), solutions within 1e-9 rad, each one FK-verified."""
    _, targets, ours, general = batch(chain, Q, family)
    assert np.array_equal(ours[:, : K.OUT_HEAD - 12], general[:, : K.OUT_HEAD - 12])
    assert ours[:, 0].sum() > 0
    for a, b, target in zip(ours, general, targets):
        n = int(a[0]) * K.ROW
        assert np.allclose(a[K.OUT_HEAD : K.OUT_HEAD + n], b[K.OUT_HEAD : K.OUT_HEAD + n], rtol=0.0, atol=1e-9)
        for q in a[K.OUT_HEAD : K.OUT_HEAD + n].reshape(-1, K.ROW)[:, :6]:
            assert chain.within_limits(q) and verify(chain, q, target, 1e-5)[0]


def assert_left_to_the_kernel(chain: Chain, Q: Array, family: int) -> None:
    """Targets the lanes must not solve themselves: their rows equal single calls' bit for bit."""
    _, _, ours, general = batch(chain, Q, family)
    for a, b in zip(ours, general):
        n = int(b[0]) * K.ROW
        assert np.array_equal(a[: K.OUT_HEAD - 12], b[: K.OUT_HEAD - 12])
        assert np.array_equal(a[K.OUT_HEAD : K.OUT_HEAD + n], b[K.OUT_HEAD : K.OUT_HEAD + n])


@pytest.mark.parametrize("arm", ["ur5", "ur10"])
def test_lanes_equal_the_kernel_on_real_ur_arms(arm: str) -> None:
    chain = load_chain(erd(UR[arm]))
    compare(chain, chain.random(np.random.default_rng(1), 300), K.UR)


# Real spherical-wrist arms (example-robot-data): Kinova j2s6s200, and the Panda at one joint locked, whose
# families are EAIK's (tests/ik/closed_form/test_families.py::PANDA_LOCKS); every lanes family but UR.
SPHERICAL_ARMS = [
    ("kinova", None, K.WRIST_23_PARALLEL),
    ("panda", ("panda_joint7", 0.3), K.WRIST_12_INTERSECTING),
    ("panda", ("panda_joint6", 0.0), K.WRIST_12_PARALLEL),
    ("panda", ("panda_joint5", 0.0), K.WRIST_23_PARALLEL),
    ("panda", ("panda_joint4", -1.5), K.WRIST_23_INTERSECTING),
]


def real_arm(arm: str, lock: tuple[str, float] | None) -> Chain:
    relative, base, tip = ARMS[arm]
    chain = load_chain(erd(relative), base, tip)
    return chain.locked({lock[0]: lock[1]}) if lock else chain


@pytest.mark.parametrize(("arm", "lock", "family"), SPHERICAL_ARMS)
def test_lanes_equal_the_kernel_on_real_spherical_wrists(arm: str, lock: tuple[str, float] | None, family: int) -> None:
    chain = real_arm(arm, lock)
    compare(chain, chain.random(np.random.default_rng(6), 300), family)


@pytest.mark.parametrize("family", [K.UR, *SPHERICAL])
def test_lanes_equal_the_kernel_on_rendered_families(family: int) -> None:
    chain = dh_chain(FAMILY_TABLES[family], seed=5)
    compare(chain, chain.random(np.random.default_rng(2), 300), family)


@pytest.mark.parametrize("family", [f for f in SPHERICAL if f in REVERSED_TABLES])
def test_lanes_equal_the_kernel_with_the_wrist_at_the_base(family: int) -> None:
    chain = dh_chain(REVERSED_TABLES[family], seed=5)
    compare(chain, chain.random(np.random.default_rng(7), 300), family)


def test_ur_special_cases_are_the_kernels() -> None:
    """Wrist singularity (θ5 = 0), stretched elbow (θ3 = 0), wrist centre on axis 1: solved by the kernel."""
    chain = load_chain(erd(UR["ur5"]))
    Q = chain.random(np.random.default_rng(3), 12)
    Q[0:4, 4] = 0.0
    Q[4:8, 2] = 0.0
    Q[8:12, 4] = math.pi
    assert_left_to_the_kernel(chain, Q, K.UR)


# ---- Kinova's special cases, found on its geometry (IK-Geo's form: joint i turns about H[i] by q_i) ----------


def _form(chain: Chain) -> tuple[Array, Array]:
    model = make_solver("analytic", chain)._model  # type: ignore[attr-defined]
    return model[K.H : K.H + 18].reshape(6, 3), model[K.P : K.P + 21].reshape(7, 3)


def wrist_singular(chain: Chain, q: Array) -> Array:
    """q with q5 where axes 4 and 6 line up (the Jacobian's angular columns 4 and 6 parallel)."""

    def apart(v: float) -> float:
        x = q.copy()
        x[4] = v
        J = chain.jacobian(x)
        return 1.0 - abs(float(J[3:, 3] @ J[3:, 5]))

    grid = np.linspace(-math.pi, math.pi, 721)
    start = grid[int(np.argmin([apart(v) for v in grid]))]
    best = minimize_scalar(apart, bounds=(start - 0.01, start + 0.01), method="bounded", options={"xatol": 1e-12})
    assert best.fun < 1e-12
    x = q.copy()
    x[4] = best.x
    return x


def stretched(chain: Chain, q: Array, folded: bool) -> Array:
    """q with q3 where ‖p23 + R3 p34‖ is largest (the elbow stretched: the reach boundary) or smallest."""
    H, P = _form(chain)
    h3, p23, p34 = H[2], P[2], P[3]
    A = float(p23 @ (p34 - (h3 @ p34) * h3))
    B = float(p23 @ np.cross(h3, p34))
    x = q.copy()
    x[2] = math.atan2(B, A) + (math.pi if folded else 0.0)
    return x


def test_kinova_special_cases_are_the_kernels() -> None:
    """Wrist singular, elbow stretched (the reach boundary) and folded: the lanes leave each to the kernel, so
    the rows equal single calls' exactly, and the singular wrist is still solved. (Kinova's wrist centre
    cannot reach axis 1: its shoulder offset keeps it 9.8 mm away; the UR5 test above has that case.)"""
    chain = real_arm("kinova", None)
    Q = chain.random(np.random.default_rng(8), 4)
    cases = np.array(
        [wrist_singular(chain, q) for q in Q] + [stretched(chain, q, folded) for q in Q for folded in (False, True)]
    )
    assert_left_to_the_kernel(chain, cases, K.WRIST_23_PARALLEL)
    solver = make_solver("analytic", chain)
    targets = chain.fk_batch(cases)
    counts, _ = solver.all_solutions(targets, np.tile(chain.mid(), (len(cases), 1)))  # type: ignore[attr-defined]
    assert counts[:4].min() >= 1  # the singular wrist: θ4 from the seed, θ6 the rest


def test_bad_target_in_a_batch_is_flagged() -> None:
    chain = load_chain(erd(UR["ur5"]))
    solver = make_solver("analytic", chain)
    targets = np.ascontiguousarray(chain.fk_batch(chain.random(np.random.default_rng(4), 5)))
    targets[2, 0, 3] = math.nan
    out = K.empty_out(5)
    assert lanes.solve(K.UR, solver._model, targets, np.tile(chain.mid(), (5, 1)), out) == K.BAD_INPUT
    assert out[2, 3] == K.BAD_INPUT and all(out[i, 3] == K.SOLVED and out[i, 0] > 0 for i in (0, 1, 3, 4))


def test_general_first_three_axes_stay_on_the_kernel() -> None:
    """SP5's quartic (Panda at joint 5 locked off zero) has no lanes: its batch is the kernel's."""
    chain = real_arm("panda", ("panda_joint5", 0.3))
    solver = make_solver("analytic", chain)
    assert solver.geometry.code == K.WRIST_GENERAL and solver._lanes is None  # type: ignore[attr-defined]
    with pytest.raises(ValueError, match="no lanes"):
        lanes.solve(K.WRIST_GENERAL, solver._model, np.zeros((0, 4, 4)), np.zeros((0, 6)), K.empty_out(0))  # type: ignore[attr-defined]
