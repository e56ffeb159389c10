"""A joint path q(s) through waypoints, over the cumulative joint-space chord length s.

Time-optimal parameterization needs q'(s) and q''(s) along the path. Each joint is a piecewise
cubic through its waypoint values, stored in Hermite form (value and slope at every knot):

* by default a natural cubic spline (C2: its q'' is continuous, so the acceleration is too);
* for a joint whose natural spline leaves the joint's position limits between two waypoints
  (it overshoots where the path turns back near a limit: Panda's joint 2), a shape-preserving
  cubic (PCHIP, Fritsch and Carlson's monotone slopes). On each segment PCHIP stays between the
  values at its two ends, so it never leaves limits that the waypoints respect. It is only C1:
  q'' may jump at a knot, so both one-sided values are given (`eval(..., side=)`).

Written with numpy (a tridiagonal solve, the PCHIP slope formula) rather than scipy.interpolate,
whose import alone costs about a second of CPU in every `armtool traj` call; tests compare both
with scipy. Consecutive duplicate waypoints are dropped (zero length).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from armtool.errors import ArmtoolError
from armtool.traj.trajectory import Array

Side = Literal["left", "right"]
NATURAL = "natural cubic spline"
PCHIP = "shape-preserving cubic (PCHIP)"


def natural_slopes(s: Array, y: Array) -> Array:
    """q'(s) at the knots of the natural cubic spline (zero second derivative at both ends) through
    (s_i, y_i), y: (K, n)."""
    h = np.diff(s)
    K = len(s)
    m = np.zeros_like(y)  # second derivatives at the knots
    slope = np.diff(y, axis=0) / h[:, None]
    if K > 2:
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
    out = np.empty_like(y)
    out[:-1] = slope - h[:, None] * (2 * m[:-1] + m[1:]) / 6  # derivative at each segment's start
    out[-1] = slope[-1] + h[-1] * (m[-2] + 2 * m[-1]) / 6  # and at the last segment's end
    return out


def pchip_slopes(s: Array, y: Array) -> Array:
    """q'(s) at the knots of the monotone piecewise cubic (Fritsch-Carlson, as scipy's
    PchipInterpolator): zero where the data turn, else a weighted harmonic mean of the two secants;
    the ends by the three-point formula, limited so the end segments do not overshoot either."""
    h = np.diff(s)[:, None]
    delta = np.diff(y, axis=0) / h
    d = np.zeros_like(y)
    if len(s) == 2:
        d[:] = delta[0]
        return d
    w1 = 2 * h[1:] + h[:-1]
    w2 = h[1:] + 2 * h[:-1]
    same_sign = (np.sign(delta[:-1]) * np.sign(delta[1:])) > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        harmonic = (w1 + w2) / (w1 / delta[:-1] + w2 / delta[1:])
    d[1:-1] = np.where(same_sign, harmonic, 0.0)
    d[0] = _pchip_end(h[0], h[1], delta[0], delta[1])
    d[-1] = _pchip_end(h[-1], h[-2], delta[-1], delta[-2])
    return d


def _pchip_end(h0: Array, h1: Array, m0: Array, m1: Array) -> Array:
    d = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
    d = np.where(np.sign(d) != np.sign(m0), 0.0, d)
    return np.where((np.sign(m0) != np.sign(m1)) & (np.abs(d) > np.abs(3 * m0)), 3 * m0, d)


class HermiteCubic:
    """Piecewise cubic through (s_i, y_i) with slopes d_i at the knots; y, d: (K, n)."""

    def __init__(self, s: Array, y: Array, d: Array) -> None:
        self.s, self.y, self.d = s, y, d
        self.h = np.diff(s)

    def __call__(self, x: Array, nu: int = 0, side: Side = "right") -> Array:
        """Value (nu=0), q' (1) or q'' (2) at x; at a knot, of the segment after it (`right`) or before it."""
        s, h = self.s, self.h
        x = np.asarray(x, dtype=np.float64)
        i = np.clip(np.searchsorted(s, x, side=side) - 1, 0, len(s) - 2)
        hi = h[i][:, None]
        t = ((x - s[i]) / h[i])[:, None]
        y0, y1, d0, d1 = self.y[i], self.y[i + 1], self.d[i] * hi, self.d[i + 1] * hi
        # p(t) = y0 + d0 t + c2 t² + c3 t³ on t in [0, 1]
        c2 = 3 * (y1 - y0) - 2 * d0 - d1
        c3 = 2 * (y0 - y1) + d0 + d1
        if nu == 0:
            out: Array = y0 + t * (d0 + t * (c2 + t * c3))
        elif nu == 1:
            out = (d0 + t * (2 * c2 + 3 * t * c3)) / hi
        elif nu == 2:
            out = (2 * c2 + 6 * t * c3) / hi**2
        else:
            raise ValueError(f"derivative order {nu} not supported")
        return out


@dataclass(frozen=True)
class JointPath:
    s: Array  # (K,) knot parameters, s[0] = 0
    waypoints: Array  # (K, n)
    spline: HermiteCubic
    shape_preserving: tuple[int, ...] = ()  # joints interpolated with PCHIP instead of the natural spline

    @property
    def length(self) -> float:
        return float(self.s[-1])

    def eval(self, s: Array, side: Side = "right") -> tuple[Array, Array, Array]:
        """q, q', q'' at s (each (len(s), n)); at a knot, the one-sided values of `side`."""
        return self.spline(s, 0, side), self.spline(s, 1, side), self.spline(s, 2, side)

    def interpolation(self, names: tuple[str, ...]) -> str:
        """Which interpolation each joint follows, for the user."""
        if not self.shape_preserving:
            return f"{NATURAL} through the waypoints"
        which = ", ".join(f"'{names[j]}'" for j in self.shape_preserving)
        return (
            f"{PCHIP} for {which}, whose natural spline left the joint limits between waypoints; "
            f"{NATURAL} for the other joints"
        )


def chord_parameters(waypoints: Array) -> Array:
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(waypoints, axis=0), axis=1))])


def joint_path(
    waypoints: Array, source: str = "path", lower: Array | None = None, upper: Array | None = None
) -> JointPath:
    """The path through `waypoints`: a natural cubic spline per joint, or, with position limits
    given, PCHIP for each joint whose natural spline would leave its limits between waypoints."""
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
    slopes = natural_slopes(s, q)
    natural = HermiteCubic(s, q, slopes)
    leaving: tuple[int, ...] = ()
    if lower is not None and upper is not None:
        dense = natural(np.linspace(0.0, float(s[-1]), 20 * len(s)))
        over = np.any((dense < lower - 1e-9) | (dense > upper + 1e-9), axis=0)
        leaving = tuple(int(j) for j in np.flatnonzero(over))
    if not leaving:
        return JointPath(s, q, natural)
    shaped = slopes.copy()
    shaped[:, list(leaving)] = pchip_slopes(s, q[:, list(leaving)])
    return JointPath(s, q, HermiteCubic(s, q, shaped), leaving)
