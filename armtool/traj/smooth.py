"""`traj time` with jerk limits: the time-optimal path speed, smoothed by a moving average in time.

A time-optimal profile switches the path acceleration s̈ between its bounds (bang-bang), so its jerk
is unbounded. Replacing the path position s(t) by its mean over a window of w seconds,

    s_w(t) = (1/w) ∫ s(τ) dτ over [t − w/2, t + w/2]   (s = 0 before the start, L after the end),

gives ṡ_w(t) = (s(t + w/2) − s(t − w/2)) / w, s̈_w = the same difference of ṡ over w, and a path jerk
of at most 2·max|s̈| / w: the window spreads each switch of s̈ over w. It keeps what matters:

* the path: every sample is q(s_w(t)) on the same spline, only the timing changes;
* rest to rest, and s_w increases from 0 to L (a mean of a non-decreasing s);
* the speed and acceleration: a mean of ṡ and s̈ stays within their range along the window
  (up to the change of the limit along the path within the window, which the check below catches).

The window starts at w = max_j 2·a_j / j_j (the time to swing a joint's acceleration from −a_j to
+a_j at its jerk limit). The samples (uniform in time, at least as many as the timing grid) are
checked with `armtool.traj.check`'s Hermite model, exactly as `traj check` does; a joint over its
velocity or acceleration limit plans with a tighter one, a jerk over its limit widens the window,
and after three rounds also slows the path (a path's own curvature adds jerk q'''·ṡ³ that no window
removes). The result costs about w seconds more than the time-optimal one and passes `traj check`
with the jerk limits, or it is an error.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from armtool.errors import ArmtoolError
from armtool.traj.check import ACC_TOL, JERK_TOL, VEL_TOL, hermite_extremes
from armtool.traj.limits import JointLimits
from armtool.traj.path import JointPath
from armtool.traj.topp import Profile, parameterize
from armtool.traj.trajectory import Array, Trajectory

_MARGIN = 1e-3  # plan this far inside every limit
_ROUNDS = 12
_MIN_SAMPLES = 200
_MAX_SAMPLES = 20000  # 16 samples per window, at most this many


def _stage(p: Profile, t: Array) -> tuple[NDArray[np.intp], Array]:
    """Each time's stage index and its time into the stage (clipped to the profile)."""
    i = np.clip(np.searchsorted(p.t, t, side="right") - 1, 0, len(p.u) - 1)
    return i, np.clip(t, p.t[0], p.t[-1]) - p.t[i]


def _s(p: Profile, t: Array) -> tuple[Array, Array, Array, Array]:
    """s, ṡ, s̈ and ∫s dt of the profile at times t (constant s̈ per stage; at rest outside it)."""
    v = np.sqrt(np.maximum(p.x, 0.0))
    dt = np.diff(p.t)
    # ∫ s dt at the start of each stage: per stage s_i·T + v_i·T²/2 + u_i·T³/6.
    S0 = np.concatenate([[0.0], np.cumsum(p.s[:-1] * dt + v[:-1] * dt**2 / 2 + p.u * dt**3 / 6)])
    i, tau = _stage(p, t)
    s = p.s[i] + v[i] * tau + p.u[i] * tau**2 / 2
    S = S0[i] + p.s[i] * tau + v[i] * tau**2 / 2 + p.u[i] * tau**3 / 6
    inside = (t >= p.t[0]) & (t <= p.t[-1])
    sd = np.where(inside, v[i] + p.u[i] * tau, 0.0)
    sdd = np.where(inside, p.u[i], 0.0)
    after = t > p.t[-1]
    S = np.where(after, S0[-1] + p.s[-1] * (t - p.t[-1]), np.where(t < p.t[0], 0.0, S))
    return np.where(after, p.s[-1], s), sd, sdd, S


def smoothed(p: Profile, window_s: float, n_samples: int) -> tuple[Array, Array, Array, Array]:
    """Times (from 0) and s_w, ṡ_w, s̈_w of the profile averaged over `window_s`."""
    T = float(p.t[-1])
    t = np.linspace(0.0, T + window_s, n_samples)
    ahead, behind = _s(p, t), _s(p, t - window_s)  # the mean over [t − w, t] of the profile's time
    s = (ahead[3] - behind[3]) / window_s
    sd = (ahead[0] - behind[0]) / window_s
    sdd = (ahead[1] - behind[1]) / window_s
    s = np.clip(s, 0.0, p.s[-1])
    s[0], s[-1], sd[[0, -1]], sdd[[0, -1]] = 0.0, p.s[-1], 0.0, 0.0
    return t, s, sd, sdd


def jerk_limited(
    traj: Trajectory, lim: JointLimits, path: JointPath, s_grid: Array, vel: Array, acc: Array
) -> Trajectory:
    """`traj`'s path timed within velocity `vel`, acceleration `acc` and `lim.jerk` (joints already
    matched; `path` is its JointPath, `s_grid` the timing grid). See the module docstring."""
    jerk = lim.jerk
    limited = np.isfinite(jerk) & (jerk > 0)
    window = float(np.max(2 * acc[limited] / jerk[limited]))
    v_plan, a_plan = vel * (1 - _MARGIN), acc * (1 - _MARGIN)
    for round_ in range(_ROUNDS):
        profile = parameterize(path, v_plan, a_plan, s_grid)
        n = max(len(s_grid), _MIN_SAMPLES, min(_MAX_SAMPLES, int(np.ceil(16 * (profile.t[-1] + window) / window))))
        t, s, sd, sdd = smoothed(profile, window, n)
        q, dq, ddq = path.eval(s)
        qd = dq * sd[:, None]
        qdd = dq * sdd[:, None] + ddq * (sd**2)[:, None]
        vmax, amax, jmax = hermite_extremes(t, q, qd)
        v_ratio = np.max(np.concatenate([vmax, np.abs(qd)]), axis=0) / vel
        a_ratio = np.max(np.concatenate([amax, np.abs(qdd)]), axis=0) / acc
        j_ratio = np.where(limited, np.max(jmax, axis=0) / np.where(limited, jerk, 1.0), 0.0)
        if np.all(v_ratio <= 1 + VEL_TOL) and np.all(a_ratio <= 1 + ACC_TOL) and np.all(j_ratio <= 1 + JERK_TOL):
            return Trajectory(traj.joint_names, q, t, qd, qdd, traj.source, (), lim.prismatic)
        v_plan = np.where(v_ratio > 1, v_plan / np.maximum(v_ratio, 1.0) * (1 - _MARGIN), v_plan)
        a_plan = np.where(a_ratio > 1, a_plan / np.maximum(a_ratio, 1.0) * (1 - _MARGIN), a_plan)
        worst = float(np.max(j_ratio))
        if worst > 1:
            window *= min(2.0, worst * (1 + _MARGIN))
            if round_ >= 3:  # the path's own curvature: slow it down as well (jerk ~ ṡ³)
                v_plan = v_plan / worst ** (1 / 3) * (1 - _MARGIN)
                a_plan = a_plan / worst ** (2 / 3) * (1 - _MARGIN)
    raise ArmtoolError(
        "could not time the path within the jerk limits",
        traj.source,
        hint="the path may have a corner or a very tight curve; give it more waypoints, or raise the jerk limits",
    )
