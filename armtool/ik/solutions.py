"""Solution sets of closed-form solvers: placing each solution within the limits, telling distinct
solutions apart, and which of another solver's solutions a set misses.

A closed-form solver (armtool's `analytic`, the peers `eaik` and `ik-geo`) returns every solution of
a target. Two of them are the same solution when every joint differs by less than DISTINCT_RAD,
revolute joints compared modulo 2π (q and q + 2π are one configuration of the arm; which of the two a
solver returns is a matter of representation). A solution counts only if armtool's FK check passes
and it lies within the limits after its revolute angles are moved by whole turns (`place`), as
`analytic` places its own.

Solutions are compared as the exact solutions they approximate (`refine`): a solver on the nearest
model of a family (IK-Geo on Lite6, whose URDF rounds π/2 to 1.5708: its model is 3e-7 off the
chain) passes the 1e-5 check with joints more than DISTINCT_RAD from the exact solution, and would
otherwise be counted as missing every solution that an exact solver finds (measured: 490 of 666
on 100 Lite6 targets).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from armtool.ik.solver import Answer, Array, pose_error_batch
from armtool.model.chain import Chain

DISTINCT_RAD = 1e-6  # joint difference (rad, or m on a prismatic joint) below which two solutions are one
LIMIT_SLACK = 1e-9  # a value this far outside a limit is rounding: clamped onto it
REFINE_STEPS = 3  # Gauss-Newton steps from a verified solution (within 1e-5) to the exact one: quadratic
TAU = 2.0 * math.pi


def refine(chain: Chain, Q: Array, target: Array) -> Array:
    """Each solution (row of Q, each verified against the target) moved onto the exact solution it
    approximates by Gauss-Newton steps on the chain (the Jacobian's pseudo-inverse: the smallest
    step, so a solution on a continuum, at a singularity, stays where it is along it). A step is
    kept only where it lowers the pose error and stays within the limits."""
    Q = np.array(Q, dtype=float).reshape(-1, chain.n)
    if Q.shape[0] == 0:
        return Q
    targets = np.broadcast_to(np.asarray(target, dtype=float), (Q.shape[0], 4, 4))
    T, J = chain.fk_jacobian_batch(Q)
    e = pose_error_batch(T, targets)
    for _ in range(REFINE_STEPS):
        assert J is not None
        step = np.einsum("kij,kj->ki", np.linalg.pinv(J), e)
        moved = Q + step
        T2, J2 = chain.fk_jacobian_batch(moved)
        e2 = pose_error_batch(T2, targets)
        inside = np.all(
            (moved >= chain.lower - LIMIT_SLACK) & (moved <= chain.upper + LIMIT_SLACK) | chain.continuous, axis=1
        )
        better = inside & (np.linalg.norm(e2, axis=1) < np.linalg.norm(e, axis=1))
        if not better.any():
            break
        Q[better], e[better] = moved[better], e2[better]
        assert J2 is not None
        J = np.where(better[:, None, None], J2, J)
    return Q


def place(chain: Chain, Q: Array, seed: Array) -> Array:
    """Each solution (row of Q) with its revolute angles moved by whole turns to the value nearest the
    seed's, then, where that is outside the limits, by the fewest whole turns into them; solutions
    with a joint that no whole turn brings within its limits (or a NaN) are dropped. Continuous
    joints keep the value nearest the seed."""
    Q = np.asarray(Q, dtype=float).reshape(-1, chain.n)
    turns = np.where(chain.revolute, np.round((Q - seed) / TAU), 0.0)
    near = Q - TAU * turns
    lo, hi = chain.lower, chain.upper
    below = near < lo - LIMIT_SLACK
    above = near > hi + LIMIT_SLACK
    up = np.where(below & chain.revolute, np.ceil((lo - near) / TAU), 0.0)
    down = np.where(above & chain.revolute, np.ceil((near - hi) / TAU), 0.0)
    placed = near + TAU * (up - down)
    bounded = np.clip(placed, lo, hi)
    inside = np.abs(placed - bounded) <= LIMIT_SLACK
    keep = np.all(np.where(chain.continuous, np.isfinite(near), inside), axis=1)
    out: Array = np.where(chain.continuous, near, bounded)[keep]
    return out


def nearest_first(Q: Array, seed: Array) -> Array:
    """The solutions sorted by Euclidean joint distance to the seed, nearest first."""
    order = np.argsort(np.linalg.norm(Q - seed, axis=1), kind="stable")
    out: Array = Q[order]
    return out


def _difference(chain: Chain, a: Array, b: Array) -> Array:
    """|a − b| per joint, revolute joints modulo 2π (broadcasting)."""
    d = a - b
    d = np.where(chain.revolute, (d + math.pi) % TAU - math.pi, d)
    out: Array = np.abs(d)
    return out


def distinct(chain: Chain, Q: Array) -> Array:
    """The solutions with repeats (every joint within DISTINCT_RAD, modulo 2π) removed, first kept."""
    kept: list[Array] = []
    for q in np.asarray(Q, dtype=float).reshape(-1, chain.n):
        if not any(float(_difference(chain, q, k).max()) < DISTINCT_RAD for k in kept):
            kept.append(q)
    return np.array(kept).reshape(-1, chain.n)


def missing(chain: Chain, found: Array, others: Array) -> int:
    """How many of `others` (distinct solutions) have no equal in `found`."""
    if others.shape[0] == 0:
        return 0
    if found.shape[0] == 0:
        return int(others.shape[0])
    d = _difference(chain, others[:, None, :], found[None, :, :]).max(axis=2)  # (others, found)
    return int((d.min(axis=1) >= DISTINCT_RAD).sum())


def closed_form_answer(chain: Chain, name: str, Q: Array, least_squares: Any, seed: Array) -> Answer:
    """A peer's closed-form output as an Answer: its solutions (rows of Q) placed within the limits
    (`place`), nearest the seed first, q the nearest; claimed when one of them is exact (not a
    least-squares approximation: the peer's `is_LS` flags). Why it failed otherwise."""
    Q = np.asarray(Q, dtype=float).reshape(-1, chain.n)
    exact = ~np.asarray(least_squares, dtype=bool).reshape(-1)
    if Q.shape[0] == 0:
        return Answer(np.asarray(seed, dtype=float), False, 0, f"{name} returned no solution")
    placed_exact = place(chain, Q[exact], seed)
    placed_ls = place(chain, Q[~exact], seed)
    if placed_exact.shape[0]:
        solutions = nearest_first(np.vstack([placed_exact, placed_ls]), seed)
        return Answer(solutions[0], True, 0, "", tuple(solutions))
    if placed_ls.shape[0]:
        solutions = nearest_first(placed_ls, seed)
        why = f"{name} returned least-squares (approximate) solutions only ({Q.shape[0]})"
        return Answer(solutions[0], False, 0, why, tuple(solutions))
    q = nearest_first(Q, seed)[0]
    why = (
        f"{name}: {int(exact.sum())} exact solution(s), none within the joint limits"
        if exact.any()
        else f"{name} returned least-squares (approximate) solutions only ({Q.shape[0]}), none within the joint limits"
    )
    return Answer(np.where(np.isfinite(q), q, seed), False, 0, why)


def enumerate_by_least_squares(chain: Chain, target: Array, seeds: Array) -> Array:
    """Every solution SciPy's least squares (bounded by the limits) reaches from the seeds, verified,
    refined and distinct: an enumeration independent of any closed form or search, to count theirs
    against (tests, benchmarks/ik_search.py). Slow: ~3 ms a seed."""
    from scipy.optimize import least_squares

    from armtool.ik.solver import rotation_error, verify

    def residual(q: Array) -> Array:
        T = chain.fk(q)
        return np.concatenate([target[:3, 3] - T[:3, 3], rotation_error(T[:3, :3], target[:3, :3])])

    found = []
    for seed in np.asarray(seeds, dtype=float).reshape(-1, chain.n):
        x = least_squares(residual, seed, bounds=(chain.lower, chain.upper), xtol=1e-15, ftol=1e-15, gtol=1e-15).x
        if verify(chain, x, target, 1e-5)[0]:
            found.append(x)
    return distinct(chain, refine(chain, np.array(found).reshape(-1, chain.n), target))
