"""A joint path q(s) through waypoints: a cubic spline over the cumulative joint-space chord length.

Time-optimal parameterization needs q'(s) and q''(s) along the path; a C2 cubic spline gives both,
and passes through every waypoint. Consecutive duplicate waypoints are dropped (zero length).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from armtool.errors import ArmtoolError
from armtool.traj.trajectory import Array


@dataclass(frozen=True)
class JointPath:
    s: Array  # (K,) knot parameters, s[0] = 0
    waypoints: Array  # (K, n)
    spline: Any  # scipy CubicSpline

    @property
    def length(self) -> float:
        return float(self.s[-1])

    def eval(self, s: Array) -> tuple[Array, Array, Array]:
        """q, q', q'' at s (each (len(s), n))."""
        return self.spline(s), self.spline(s, 1), self.spline(s, 2)


def chord_parameters(waypoints: Array) -> Array:
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(waypoints, axis=0), axis=1))])


def joint_path(waypoints: Array, source: str = "path") -> JointPath:
    from scipy.interpolate import CubicSpline

    q = np.asarray(waypoints, dtype=np.float64)
    if q.ndim != 2 or q.shape[0] < 2:
        raise ArmtoolError(f"a path needs at least two points, {source} has {q.shape[0] if q.ndim == 2 else 0}",
                           source, "give the start and the goal at least")
    keep = np.concatenate([[True], np.linalg.norm(np.diff(q, axis=0), axis=1) > 1e-12])
    q = q[keep]
    if q.shape[0] < 2:
        raise ArmtoolError("every point of the path is the same configuration: nothing to time", source)
    s = chord_parameters(q)
    return JointPath(s, q, CubicSpline(s, q, axis=0))
