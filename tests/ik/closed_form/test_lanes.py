"""The UR-type lanes (closed_form/lanes.py) against the general kernel: the same solutions (to ~1e-10
rad), counts and statuses; the special cases left to the kernel; the polynomial atan2 against libm's."""

from __future__ import annotations

import math

import numpy as np
import pytest

from armtool.ik import load_chain, make_solver
from armtool.ik.closed_form import kernel as K
from armtool.ik.closed_form import lanes
from armtool.model.chain import Chain
from tests.ik.closed_form.test_families import FAMILY_TABLES
from tests.ik.robots import ARMS, erd
from tests.ik.test_analytic import UR, dh_chain


def test_atan2_matches_libm() -> None:
    rng = np.random.default_rng(0)
    ys, xs = rng.normal(size=2000) * 10.0 ** rng.uniform(-8, 8, 2000), rng.normal(size=2000)
    special = [(0.0, 1.0), (0.0, -1.0), (1.0, 0.0), (-1.0, 0.0), (1.0, 1.0), (-1.0, -1.0), (0.0, 0.0), (1e-300, -1.0)]
    for y, x in [*zip(ys, xs), *special]:
        assert abs(lanes.atan2(y, x) - math.atan2(y, x)) <= 4.5e-16 * max(1.0, abs(math.atan2(y, x)))
    assert math.isnan(lanes.atan2(math.nan, 1.0))


def compare(chain: Chain, Q: np.ndarray) -> None:
    """lanes.solve and kernel.solve_many on FK of Q from the middle: equal headers, solutions within 1e-9."""
    solver = make_solver("analytic", chain)
    assert solver._lanes == K.UR
    targets = np.ascontiguousarray(chain.fk_batch(Q))
    seeds = np.tile(chain.mid(), (len(Q), 1))
    ours, general = K.empty_out(len(Q)), K.empty_out(len(Q))
    assert lanes.solve(K.UR, solver._model, targets, seeds, ours) == K.SOLVED
    assert K.solve_many(solver._model, targets, seeds, general) == K.SOLVED
    assert np.array_equal(ours[:, : K.OUT_HEAD - 12], general[:, : K.OUT_HEAD - 12])  # counts, status, seed
    for a, b in zip(ours, general):
        n = int(a[0]) * K.ROW
        assert np.allclose(a[K.OUT_HEAD : K.OUT_HEAD + n], b[K.OUT_HEAD : K.OUT_HEAD + n], rtol=0.0, atol=1e-9)


@pytest.mark.parametrize("arm", ["ur5", "ur10"])
def test_lanes_equal_the_kernel_on_real_ur_arms(arm: str) -> None:
    chain = load_chain(erd(UR[arm]))
    compare(chain, chain.random(np.random.default_rng(1), 300))


def test_lanes_equal_the_kernel_on_a_rendered_ur_type() -> None:
    chain = dh_chain(FAMILY_TABLES[K.UR], seed=5)
    compare(chain, chain.random(np.random.default_rng(2), 300))


def test_special_cases_are_the_kernels() -> None:
    """Wrist singularity (θ5 = 0), stretched elbow (θ3 = 0), wrist centre on axis 1: solved by the kernel,
    so the rows equal kernel.solve_one's exactly."""
    chain = load_chain(erd(UR["ur5"]))
    Q = chain.random(np.random.default_rng(3), 12)
    Q[0:4, 4] = 0.0
    Q[4:8, 2] = 0.0
    Q[8:12, 4] = math.pi
    solver = make_solver("analytic", chain)
    targets = np.ascontiguousarray(chain.fk_batch(Q))
    seeds = np.tile(chain.mid(), (len(Q), 1))
    out = K.empty_out(len(Q))
    lanes.solve(K.UR, solver._model, targets, seeds, out)
    for row, target, seed in zip(out, targets, seeds):
        one = K.empty_out()
        K.solve_one(solver._model, target, seed, one)
        n = int(one[0]) * K.ROW
        assert np.array_equal(row[: K.OUT_HEAD - 12], one[: K.OUT_HEAD - 12])
        assert np.array_equal(row[K.OUT_HEAD : K.OUT_HEAD + n], one[K.OUT_HEAD : K.OUT_HEAD + n])


def test_bad_target_in_a_batch_is_flagged() -> None:
    chain = load_chain(erd(UR["ur5"]))
    solver = make_solver("analytic", chain)
    targets = np.ascontiguousarray(chain.fk_batch(chain.random(np.random.default_rng(4), 5)))
    targets[2, 0, 3] = math.nan
    out = K.empty_out(5)
    assert lanes.solve(K.UR, solver._model, targets, np.tile(chain.mid(), (5, 1)), out) == K.BAD_INPUT
    assert out[2, 3] == K.BAD_INPUT and all(out[i, 3] == K.SOLVED and out[i, 0] > 0 for i in (0, 1, 3, 4))


def test_spherical_wrist_batches_stay_on_the_kernel() -> None:
    relative, base, tip = ARMS["kinova"]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver("analytic", chain)
    assert solver.geometry.kind == "spherical-wrist" and solver._lanes is None
    with pytest.raises(ValueError, match="no lanes"):
        lanes.solve(solver.geometry.code, solver._model, np.zeros((0, 4, 4)), np.zeros((0, 6)), K.empty_out(0))
