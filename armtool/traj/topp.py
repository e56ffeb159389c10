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


def _u_bounds(dq: Array, ddq: Array, acc: Array) -> tuple[Array, Array, Array, Array, float]:
    """Acceleration rows at one point as bounds on u affine in x: u ≤ c + d x (upper), u ≥ c + d x (lower),
    plus a bound x ≤ xmax from joints that do not move along the path there (q'_j ≈ 0)."""
    moving = np.abs(dq) > _EPS
    still = ~moving
    xmax = float(np.min(acc[still] / np.maximum(np.abs(ddq[still]), _EPS))) if still.any() else np.inf
    dqm, ddqm, am = dq[moving], ddq[moving], acc[moving]
    # q'u + q''x ≤ a  and  q'u + q''x ≥ -a
    hi_c = np.where(dqm > 0, am / np.where(dqm > 0, dqm, 1), -am / np.where(dqm < 0, dqm, 1))
    lo_c = -hi_c
    slope = -ddqm / dqm
    return hi_c, slope, lo_c, slope, xmax


def _feasible_x(up_c: Array, up_d: Array, lo_c: Array, lo_d: Array, xlo: float, xhi: float) -> tuple[float, float]:
    """[x_min, x_max] within [xlo, xhi] such that max_k(lo_c + lo_d x) ≤ min_m(up_c + up_d x); empty: (1, 0)."""
    # every pair: lo_c[k] + lo_d[k] x ≤ up_c[m] + up_d[m] x  ⇔  (lo_d[k] - up_d[m]) x ≤ up_c[m] - lo_c[k]
    coef = (lo_d[:, None] - up_d[None, :]).ravel()
    rhs = (up_c[None, :] - lo_c[:, None]).ravel()
    pos, neg, zero = coef > _EPS, coef < -_EPS, np.abs(coef) <= _EPS
    if zero.any() and np.min(rhs[zero]) < -1e-12 * (1 + np.max(np.abs(rhs[zero]))):
        return 1.0, 0.0
    hi = min(xhi, float(np.min(rhs[pos] / coef[pos]))) if pos.any() else xhi
    lo = max(xlo, float(np.max(rhs[neg] / coef[neg]))) if neg.any() else xlo
    return lo, hi


def parameterize(path: JointPath, velocity: Array, acceleration: Array, s_grid: Array | None = None) -> Profile:
    """The time-optimal rest-to-rest profile of `path` under |q̇_j| ≤ velocity_j, |q̈_j| ≤ acceleration_j."""
    s = grid(path) if s_grid is None else s_grid
    _, dq, ddq = path.eval(s)
    n_stages = len(s) - 1
    delta = np.diff(s)
    with np.errstate(divide="ignore"):
        xv = np.min(np.where(np.abs(dq) > _EPS, (velocity / np.maximum(np.abs(dq), _EPS)) ** 2, np.inf), axis=1)
    rows = [_u_bounds(dq[i], ddq[i], acceleration) for i in range(len(s))]
    xcap = np.minimum(xv, [r[4] for r in rows])

    def stage_bounds(i: int, lo_next: float, hi_next: float) -> tuple[Array, Array, Array, Array]:
        """u-bounds of stage i as affine functions of x_i (rows at s_i, rows at s_{i+1}, and K_{i+1})."""
        up_c, up_d, lo_c, lo_d, _ = rows[i]
        # at s_{i+1} with x' = x + 2Δu:  q'u + q''(x + 2Δu) within ±a  ⇔  (q' + 2Δq'')u + q''x within ±a
        d2 = 2 * delta[i]
        b = dq[i + 1] + d2 * ddq[i + 1]
        nu_c, nu_d, nl_c, nl_d, _ = _u_bounds(b, ddq[i + 1], acceleration)
        # x_{i+1} ≤ xcap_{i+1} is part of K_{i+1}
        return (np.concatenate([up_c, nu_c, [hi_next / d2]]), np.concatenate([up_d, nu_d, [-1.0 / d2]]),
                np.concatenate([lo_c, nl_c, [lo_next / d2]]), np.concatenate([lo_d, nl_d, [-1.0 / d2]]))

    lo = np.zeros(n_stages + 1)
    hi = np.zeros(n_stages + 1)  # K_N = {0}: at rest at the end
    for i in range(n_stages - 1, -1, -1):
        bounds = stage_bounds(i, lo[i + 1], min(hi[i + 1], xcap[i + 1]))
        a, b = _feasible_x(*bounds, 0.0, float(xcap[i]))
        if a > b + 1e-12:
            raise ArmtoolError(f"the path cannot be followed within the limits near s = {s[i]:.4g} (stage {i})",
                               hint="check the acceleration limits; a path with a corner needs a stop there")
        lo[i], hi[i] = a, max(a, b)
    if lo[0] > 1e-12:
        raise ArmtoolError("the path cannot start at rest within the limits")
    x = np.zeros(n_stages + 1)
    u = np.zeros(n_stages)
    for i in range(n_stages):
        up_c, up_d, lo_c, lo_d = stage_bounds(i, lo[i + 1], min(hi[i + 1], xcap[i + 1]))
        u_max = float(np.min(up_c + up_d * x[i]))
        u_min = float(np.max(lo_c + lo_d * x[i]))
        u[i] = max(u_max, u_min) if u_max >= u_min - 1e-9 else u_min
        x[i + 1] = min(max(x[i] + 2 * delta[i] * u[i], lo[i + 1], 0.0), hi[i + 1])
        u[i] = (x[i + 1] - x[i]) / (2 * delta[i])
    x[-1] = 0.0
    u[-1] = (x[-1] - x[-2]) / (2 * delta[-1])
    v = np.sqrt(np.maximum(x, 0.0))
    speed_sum = v[:-1] + v[1:]
    if np.any(speed_sum <= 0):
        raise ArmtoolError("the path cannot be traversed within the limits (zero speed inside the path)",
                           hint="check the velocity and acceleration limits")
    t = np.concatenate([[0.0], np.cumsum(2 * delta / speed_sum)])
    return Profile(s, x, u, t)
