"""Time-optimal path parameterization by reachability analysis (TOPP-RA, Pham & Pham 2018),
for per-joint velocity and acceleration box limits, rest to rest.

Along a path q(s) the motion is fixed by x(s) = ṡ², u = s̈; then q̇ = q' ṡ, q̈ = q' u + q'' x.
On a grid s_0..s_N with x_{i+1} = x_i + 2 Δ_i u_i (constant u per stage):

* velocity: x_i ≤ min_j (v_j / |q'_j(s_i)|)²;
* acceleration: |q'_j u_i + q''_j x_i| ≤ a_j, imposed at both ends of the stage (at s_{i+1} with
  x_{i+1} = x_i + 2Δ u_i): TOPP-RA's first-order interpolation scheme.

A backward pass computes each stage's controllable set K_i = [lo_i, hi_i] (the x from which the
rest of the path can still be followed and stop at the end); a forward pass takes the largest u
that keeps x_{i+1} in K_{i+1}. With box limits each stage's LP has two variables, and it is solved
exactly: for a fixed x every constraint bounds u from one side, so x is feasible iff every lower
bound on u lies below every upper bound, a set of linear inequalities in x alone.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armtool.errors import ArmtoolError
from armtool.traj.path import JointPath
from armtool.traj.trajectory import Array

_EPS = 1e-12


@dataclass(frozen=True)
class Profile:
    s: Array  # (N+1,) grid
    x: Array  # (N+1,) ṡ² at the grid points
    u: Array  # (N,) s̈ on each stage
    t: Array  # (N+1,) time at the grid points


def grid(path: JointPath, min_stages: int = 200, per_segment: int = 2) -> Array:
    """The knots of the path, each spline segment split into `per_segment` stages or more."""
    pieces = []
    step = path.length / max(min_stages, 1)
    for a, b in zip(path.s[:-1], path.s[1:]):
        k = max(per_segment, int(np.ceil((b - a) / step)))
        pieces.append(np.linspace(a, b, k + 1)[:-1])
    return np.concatenate(pieces + [path.s[-1:]])


def _rows(b: Array, c: Array, acc: Array) -> tuple[Array, Array, Array, Array, Array]:
    """|b u + c x| ≤ a per joint, for many points at once (b, c: (M, n)), as bounds on u affine in x:
    u ≤ up_c + d x and u ≥ lo_c + d x; a joint with b ≈ 0 bounds x alone (x ≤ a / |c|), returned as xmax (M,)."""
    moving = np.abs(b) > _EPS
    safe_b = np.where(moving, b, 1.0)
    up_c = np.where(moving, acc / np.abs(safe_b), np.inf)
    d = np.where(moving, -c / safe_b, 0.0)
    with np.errstate(divide="ignore"):
        still = np.where(moving, np.inf, acc / np.abs(c))
    return up_c, -up_c, d, d, np.min(still, axis=1)


def _x_interval(coef: Array, rhs: Array, xlo: Array, xhi: Array) -> tuple[Array, Array]:
    """Along the last axis, the x with coef·x ≤ rhs for every row, within [xlo, xhi]; empty: lo > hi."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = rhs / coef
    hi = np.minimum(xhi, np.min(np.where(coef > _EPS, ratio, np.inf), axis=-1))
    lo = np.maximum(xlo, np.max(np.where(coef < -_EPS, ratio, -np.inf), axis=-1))
    bad = np.any((np.abs(coef) <= _EPS) & (rhs < -1e-12), axis=-1)
    return lo, np.where(bad, -np.inf, hi)


def parameterize(path: JointPath, velocity: Array, acceleration: Array, s_grid: Array | None = None) -> Profile:
    """The time-optimal rest-to-rest profile of `path` under |q̇_j| ≤ velocity_j, |q̈_j| ≤ acceleration_j."""
    s = grid(path) if s_grid is None else s_grid
    _, dq, ddq = path.eval(s)
    # A stage's end is reached from the segment before it: a C1 path (PCHIP) may change q'' at a knot.
    _, dq_end, ddq_end = path.eval(s, side="left")
    n_stages = len(s) - 1
    delta = np.diff(s)
    d2 = 2 * delta
    with np.errstate(divide="ignore"):
        xv = np.min(np.where(np.abs(dq) > _EPS, (velocity / np.maximum(np.abs(dq), _EPS)) ** 2, np.inf), axis=1)
    # Stage i's acceleration rows, at s_i and at s_{i+1} (with x_{i+1} = x_i + 2Δu: b = q' + 2Δq'').
    a_up, a_lo, a_dup, a_dlo, a_x = _rows(dq[:-1], ddq[:-1], acceleration)
    b_up, b_lo, b_dup, b_dlo, b_x = _rows(dq_end[1:] + d2[:, None] * ddq_end[1:], ddq_end[1:], acceleration)
    up_c, lo_c = np.concatenate([a_up, b_up], axis=1), np.concatenate([a_lo, b_lo], axis=1)
    up_d, lo_d = np.concatenate([a_dup, b_dup], axis=1), np.concatenate([a_dlo, b_dlo], axis=1)
    xcap = np.concatenate([np.minimum(xv[:-1], np.minimum(a_x, b_x)), xv[-1:]])
    # Pairs of acceleration rows (every lower bound on u below every upper one) do not depend on
    # the next stage: all stages at once.
    s_lo, s_hi = _x_interval(
        (lo_d[:, :, None] - up_d[:, None, :]).reshape(n_stages, -1),
        (up_c[:, None, :] - lo_c[:, :, None]).reshape(n_stages, -1),
        np.zeros(n_stages),
        xcap[:-1],
    )
    lo = np.zeros(n_stages + 1)
    hi = np.zeros(n_stages + 1)  # K_N = {0}: at rest at the end
    for i in range(n_stages - 1, -1, -1):
        # With K_{i+1} = [lo', hi']: u ≤ (hi' − x)/2Δ against every lower row, u ≥ (lo' − x)/2Δ against every upper row.
        k = 1.0 / d2[i]
        coef = np.concatenate([lo_d[i] + k, -k - up_d[i]])
        rhs = np.concatenate([hi[i + 1] * k - lo_c[i], up_c[i] - lo[i + 1] * k])
        lo_i, hi_i = _x_interval(coef, rhs, s_lo[i], s_hi[i])
        a, b = float(lo_i), float(hi_i)
        if a > b + 1e-12 * max(1.0, abs(b)):
            raise ArmtoolError(
                f"the path cannot be followed within the limits near s = {s[i]:.4g} (stage {i})",
                hint="check the acceleration limits; a path with a corner needs a stop there",
            )
        lo[i], hi[i] = a, max(a, b)
    x = np.zeros(n_stages + 1)
    u = np.zeros(n_stages)
    for i in range(n_stages):
        u_max = min(float(np.min(up_c[i] + up_d[i] * x[i])), (hi[i + 1] - x[i]) / d2[i])
        u_min = max(float(np.max(lo_c[i] + lo_d[i] * x[i])), (lo[i + 1] - x[i]) / d2[i])
        ui = u_max if u_max >= u_min else u_min
        x[i + 1] = min(max(x[i] + d2[i] * ui, lo[i + 1], 0.0), hi[i + 1])
    x[-1] = 0.0
    u = (x[1:] - x[:-1]) / d2
    v = np.sqrt(np.maximum(x, 0.0))
    speed_sum = v[:-1] + v[1:]
    if np.any(speed_sum <= 0):
        raise ArmtoolError(
            "the path cannot be traversed within the limits (zero speed inside the path)",
            hint="check the velocity and acceleration limits",
        )
    t = np.concatenate([[0.0], np.cumsum(2 * delta / speed_sum)])
    return Profile(s, x, u, t)
