"""A joint path q(s) through waypoints: a natural cubic spline over the cumulative joint-space chord length.

Time-optimal parameterization needs q'(s) and q''(s) along the path; a C2 cubic spline gives both
and passes through every waypoint. Written with numpy (a tridiagonal solve) rather than
scipy.interpolate, whose import alone costs about a second of CPU in every `armtool traj` call.
Consecutive duplicate waypoints are dropped (zero length).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armtool.errors import ArmtoolError
from armtool.traj.trajectory import Array


class NaturalCubic:
    """Natural cubic spline (zero second derivative at both ends) through (s_i, y_i), y: (K, n)."""

    def __init__(self, s: Array, y: Array) -> None:
        self.s, self.y = s, y
        h = np.diff(s)
        self.h = h
        K = len(s)
        m = np.zeros_like(y)  # second derivatives at the knots
        if K > 2:
            slope = np.diff(y, axis=0) / h[:, None]
            rhs = 6 * (slope[1:] - slope[:-1])  # (K-2, n)
            diag = 2 * (h[:-1] + h[1:])
            off = h[1:-1]
            # Thomas algorithm on the (K-2) interior knots
            c = np.zeros(K - 2)
            d = np.zeros_like(rhs)
            c[0] = off[0] / diag[0] if K > 3 else 0.0
            d[0] = rhs[0] / diag[0]
            for i in range(1, K - 2):
                den = diag[i] - off[i - 1] * c[i - 1]
                c[i] = off[i] / den if i < K - 3 else 0.0
                d[i] = (rhs[i] - off[i - 1] * d[i - 1]) / den
            for i in range(K - 4, -1, -1):
                d[i] -= c[i] * d[i + 1]
            m[1:-1] = d
        self.m = m

    def __call__(self, x: Array, nu: int = 0) -> Array:
        s, y, m, h = self.s, self.y, self.m, self.h
        x = np.asarray(x, dtype=np.float64)
        i = np.clip(np.searchsorted(s, x, side="right") - 1, 0, len(s) - 2)
        hi = h[i][:, None]
        a = (s[i + 1] - x)[:, None]  # distance to the right knot
        b = (x - s[i])[:, None]  # distance from the left knot
        m0, m1, y0, y1 = m[i], m[i + 1], y[i], y[i + 1]
        if nu == 0:
            out: Array = (m0 * a**3 + m1 * b**3) / (6 * hi) + (y0 / hi - m0 * hi / 6) * a + (y1 / hi - m1 * hi / 6) * b
        elif nu == 1:
            out = (-m0 * a**2 + m1 * b**2) / (2 * hi) - (y0 / hi - m0 * hi / 6) + (y1 / hi - m1 * hi / 6)
        elif nu == 2:
            out = (m0 * a + m1 * b) / hi
        else:
            raise ValueError(f"derivative order {nu} not supported")
        return out


@dataclass(frozen=True)
class JointPath:
    s: Array  # (K,) knot parameters, s[0] = 0
    waypoints: Array  # (K, n)
    spline: NaturalCubic

    @property
    def length(self) -> float:
        return float(self.s[-1])

    def eval(self, s: Array) -> tuple[Array, Array, Array]:
        """q, q', q'' at s (each (len(s), n))."""
        return self.spline(s), self.spline(s, 1), self.spline(s, 2)


def chord_parameters(waypoints: Array) -> Array:
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(waypoints, axis=0), axis=1))])


def joint_path(waypoints: Array, source: str = "path") -> JointPath:
    q = np.asarray(waypoints, dtype=np.float64)
    if q.ndim != 2 or q.shape[0] < 2:
        raise ArmtoolError(
            f"a path needs at least two points, {source} has {q.shape[0] if q.ndim == 2 else 0}",
            source,
            "give the start and the goal at least",
        )
    keep = np.concatenate([[True], np.linalg.norm(np.diff(q, axis=0), axis=1) > 1e-12])
    q = q[keep]
    if q.shape[0] < 2:
        raise ArmtoolError("every point of the path is the same configuration: nothing to time", source)
    s = chord_parameters(q)
    return JointPath(s, q, NaturalCubic(s, q))
