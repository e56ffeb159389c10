"""armtool's `lm` solver: every answer verified, limits respected, batch equals single in quality."""

from __future__ import annotations

from typing import Any

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


def _near_singular(chain, count: int, rng_seed: int = 7) -> np.ndarray:
    """Configurations whose Jacobian's smallest singular value is below 0.003 (targets near a singular pose)."""
    Q = chain.random(np.random.default_rng(rng_seed), 8000)
    _, J = chain.fk_jacobian_batch(Q)
    smallest = np.linalg.svd(J, compute_uv=False)[:, -1]
    return Q[smallest < 0.003][:count]


@pytest.mark.parametrize(("arm", "mean_limit", "max_limit"), [("panda", 30, 150), ("ur5", 24, 100)])
def test_near_singular_targets_take_few_iterations(arm: str, mean_limit: float, max_limit: int) -> None:
    # Around singular poses a monotone LM (reject a step that raises the error) crawls: on these
    # 40 targets it needed 68-142 (Panda) / 29 (UR5) iterations on average and up to 1562 / 140;
    # this one 17 / 19, and at most 62 / 55.
    relative, base, tip = ARMS[arm]
    chain = load_chain(erd(relative), base, tip)
    Q = _near_singular(chain, 40)
    assert len(Q) == 40
    solver = make_solver("lm", chain, timeout=0.5)  # no timeout in play: iterations are deterministic
    results = [solver.solve(t, chain.mid()) for t in chain.fk_batch(Q)]
    assert all(r.success for r in results)
    iterations = [r.iterations for r in results]
    assert np.mean(iterations) < mean_limit and max(iterations) <= max_limit


def test_first_try_starts_from_the_seed() -> None:
    # A target next to the seed is answered next to the seed, in a few iterations, not from a restart.
    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver("lm", chain, timeout=0.05)
    rng = np.random.default_rng(3)
    for seed in chain.random(rng, 10) * 0.8:
        target = chain.fk(seed + rng.uniform(-0.05, 0.05, chain.n))
        r = solver.solve(target, seed)
        assert r.success and r.iterations <= 8
        assert np.linalg.norm(r.q - seed) < 0.2


def test_continuous_joints_come_back_wrapped() -> None:
    chain = load_chain(erd(ARMS["kinova"][0]))
    assert chain.continuous.any()
    solver = make_solver("lm", chain, timeout=0.05)
    Q = chain.random(np.random.default_rng(4), 30)
    Q[:, chain.continuous] += 2 * np.pi  # seeds a turn away: the answers still come back in [-π, π)
    targets = chain.fk_batch(Q)
    for results in ([solver.solve(t, q) for t, q in zip(targets, Q)], solver.solve_batch(targets, Q)):
        assert sum(r.success for r in results) >= 29
        for r, t in zip(results, targets):
            c = r.q[chain.continuous]
            assert np.all((c >= -np.pi) & (c < np.pi))
            assert r.success == verify(chain, r.q, t, 1e-5)[0]


def test_answers_keep_both_error_norms_within_tolerance() -> None:
    relative, base, tip = ARMS["ur5"]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver("lm", chain, timeout=0.05, tolerance=1e-4)
    targets = chain.fk_batch(chain.random(np.random.default_rng(5), 40))
    seeds = np.tile(chain.mid(), (40, 1))
    for results in ([solver.solve(t, s) for t, s in zip(targets, seeds)], solver.solve_batch(targets, seeds)):
        ok = [r for r in results if r.success]
        assert len(ok) >= 39
        assert all(r.position_error_m <= 1e-4 and r.orientation_error_rad <= 1e-4 for r in ok)


def test_far_seed_starts_from_the_nearest_table_pose() -> None:
    # The target is a table pose's own; from the mid-range seed (far from it) the first try starts at
    # that table pose, which is already the answer: no iteration at all. From the seed it takes ~7.
    # Any table pose, not only the cells' centres: a pose is in the cell of the centre nearest it.
    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver("lm", chain, timeout=0.05)
    table = solver.table()[3]  # type: ignore[attr-defined]
    for i in (0, 17, solver.FIRST_TABLE - 1, solver.FIRST_TABLE, 5000, solver.TABLE_SIZE - 1):  # type: ignore[attr-defined]
        target = chain.fk(table[i])
        r = solver.solve(target, chain.mid())
        assert r.success and r.iterations == 0
        assert np.allclose(r.q, table[i])


def first_tries(solver: Any, target: np.ndarray, seed: np.ndarray) -> tuple[int, np.ndarray]:
    """lm's compiled first tries on one target: (table row tried or -1, the kernel's out vector)."""
    from armtool.ik.solvers import lm_kernel

    out = np.empty(lm_kernel.OUT_HEAD + 2 * solver.chain.n)
    scores, cell_scores, bounds, table_q = solver.table()
    tried = lm_kernel.first_tries(
        solver._geometry, solver._settings, scores, cell_scores, bounds, table_q, target, seed, out
    )
    return int(tried), out


def test_near_seed_is_kept_without_a_table_lookup() -> None:
    # A seed whose pose is already the target is the answer: the table is not consulted.
    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver("lm", chain, timeout=0.05)
    for seed in chain.random(np.random.default_rng(6), 5):
        tried, out = first_tries(solver, chain.fk(seed), seed)
        assert tried == -1 and out[0] == 1 and out[1] == 0
        r = solver.solve(chain.fk(seed), seed)
        assert r.success and r.iterations == 0 and np.allclose(r.q, seed)
    # A far seed does consult it.
    target = chain.fk(chain.random(np.random.default_rng(7)))
    assert first_tries(solver, target, chain.mid())[0] >= 0


def test_the_seed_is_tried_when_the_table_pose_fails() -> None:
    # The first try from a table pose that cannot reach the target (a joint pinned far away) stalls;
    # the second try starts from the seed, so a target next to the seed is still solved next to it.
    relative, base, tip = ARMS["ur5"]
    chain = load_chain(erd(relative), base, tip)
    solver: Any = make_solver("lm", chain, timeout=0.05)
    seed = chain.mid()
    target = chain.fk(seed + 0.4)
    scores, cell_scores, bounds, table_q = solver.table()
    # Every table pose's score says "nearer than the seed", but every configuration is the one with
    # all joints at their lower limits: far from the answer near the seed.
    solver._table = (scores, cell_scores, bounds, np.tile(chain.lower, (len(table_q), 1)))
    tried, _ = first_tries(solver, target, seed)
    assert tried >= 0  # the table pose was tried first
    r = solver.solve(target, seed)
    assert r.success
    assert np.linalg.norm(r.q - (seed + 0.4)) < 1e-3


def test_restart_seeds_are_near_the_target() -> None:
    # The cells of the nearest centres hold the target's nearest table poses, or poses almost as near.
    from armtool.ik.solvers import lm_kernel
    from armtool.ik.solvers.lm import _pose_features

    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip)
    solver: Any = make_solver("lm", chain)
    scores, cell_scores, bounds, table_q = solver.table()
    F = _pose_features(chain.fk_batch(table_q))
    exact_first = 0
    targets = chain.fk_batch(chain.random(np.random.default_rng(8), 40))
    for target in targets:
        rows = lm_kernel.restart_rows(scores, cell_scores, bounds, target, solver.RESTART_CELLS, solver.TABLE_SEEDS, -1)
        f = np.concatenate((target[:3, 3], 0.2 * target[:3, :3].reshape(9)))
        exact = np.sort(np.linalg.norm(F - f, axis=1))[: len(rows)]
        got = np.linalg.norm(F[rows] - f, axis=1)
        assert len(rows) == solver.TABLE_SEEDS
        assert np.all(np.diff(got) >= -1e-12)  # nearest first
        assert got[-1] <= 1.5 * exact[-1]
        exact_first += bool(abs(got[0] - exact[0]) < 1e-9)
        skipped = lm_kernel.restart_rows(
            scores, cell_scores, bounds, target, solver.RESTART_CELLS, solver.TABLE_SEEDS, rows[0]
        )
        assert rows[0] not in skipped and list(skipped[:3]) == list(rows[1:4])  # the first try's pose is skipped
    assert exact_first >= 0.7 * len(targets)


def test_joint_pinned_at_its_limit_is_solved() -> None:
    # Targets that need a joint exactly at its limit: steps that push it outward leave it there and
    # re-plan the others (what the list-based limit check must keep doing).
    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver("lm", chain, timeout=0.1)
    rng = np.random.default_rng(9)
    for j in (1, 3, 5):
        for bound in (chain.lower, chain.upper):
            q = chain.random(rng)
            q[j] = bound[j]
            r = solver.solve(chain.fk(q), chain.mid())
            assert r.success and chain.within_limits(r.q)
            assert verify(chain, r.q, chain.fk(q), 1e-5)[0]


def test_the_compiled_kernel_is_cached_on_disk() -> None:
    # The first run compiles lm's loop (and says so); the machine code is then on disk for later runs.
    from armtool.ik.solvers.lm import compiled_on_disk

    relative, base, tip = ARMS["ur5"]
    make_solver("lm", load_chain(erd(relative), base, tip))
    assert compiled_on_disk() in (True, None)  # None: a Numba that does not say where its cache is


def test_a_seed_or_target_of_the_wrong_shape_or_not_finite_is_refused() -> None:
    # The compiled loop reads its arrays without bounds checks: they are checked before it runs.
    relative, base, tip = ARMS["ur5"]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver("lm", chain)
    target, mid = chain.fk(chain.mid()), chain.mid()
    for bad_target, bad_seed, match in (
        (target, mid[:3], "seed values"),
        (target[:3], mid, "4x4"),
        (target, np.full(6, np.nan), "finite"),
        (np.full((4, 4), np.inf), mid, "finite"),
    ):
        with pytest.raises(ArmtoolError, match=match):
            solver.solve(bad_target, bad_seed)
    with pytest.raises(ArmtoolError, match="finite"):
        solver.solve_batch(np.stack([target, target]), np.stack([mid, np.full(6, np.nan)]))


def test_a_lazy_table_is_built_outside_the_solve_budget() -> None:
    # lazy_table (`traj cartesian`) builds the table on the first solve that needs it, ~1 s of CPU:
    # that solve's budget starts after the build, so its restarts still run. Targets whose first tries
    # fail, from a far seed (the table is asked for a start) and from a near one (the seed is tried
    # as it is, and only the restarts need the table); one at a time and in a batch.
    from armtool.ik.solvers import lm_kernel

    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip)
    mid = chain.mid()
    targets = chain.fk_batch(chain.random(np.random.default_rng(5), 400))
    for far in (1e-3, np.inf):  # lm's FAR, and "every seed is near"
        eager: Any = make_solver("lm", chain, timeout=0.05)
        eager._settings[7] = far
        hard = np.array([t for t in targets if first_tries(eager, t, mid)[1][0] != lm_kernel.SOLVED][:3])
        assert len(hard) == 3
        for target in hard:
            lazy: Any = make_solver("lm", chain, timeout=0.05, lazy_table=True)
            lazy._settings[7] = far
            assert lazy._table is None
            r, e = lazy.solve(target, mid), eager.solve(target, mid)
            assert r.success and e.success, (r.reason, r.iterations, e.iterations)
            assert lazy._table is not None
        lazy = make_solver("lm", chain, timeout=0.05, lazy_table=True)
        lazy._settings[7] = far
        assert all(r.success for r in lazy.solve_batch(hard, np.tile(mid, (len(hard), 1))))


def test_the_input_check_is_part_of_the_timed_call() -> None:
    # lm's check of its inputs (the compiled loop reads them without bounds checks) is its own work,
    # as roboticstoolbox's checks are inside its ik_LM: `prepare` only converts, `call` refuses.
    relative, base, tip = ARMS["ur5"]
    chain = load_chain(erd(relative), base, tip)
    solver = make_solver("lm", chain)
    target, mid = chain.fk(chain.mid()), chain.mid()
    for bad_target, bad_seed, match in (
        (target, mid[:3], "seed values"),
        (target[:3], mid, "4x4"),
        (target, np.full(6, np.nan), "finite"),
        (np.where(np.eye(4) > 0, np.inf, target), mid, "finite"),
    ):
        prepared = solver.prepare(bad_target, bad_seed)
        with pytest.raises(ArmtoolError, match=match):
            solver.call(prepared)
    prepared = solver.prepare_batch(np.stack([target, target]), np.stack([mid, np.full(6, -np.inf)]))
    with pytest.raises(ArmtoolError, match="finite"):
        solver.call_batch(prepared)
