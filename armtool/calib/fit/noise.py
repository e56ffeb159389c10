"""The noise of each residual block, estimated from the fit's own residuals.

Why: a pose measurement mixes metres and radians, and how much a millimetre counts against a
tenth of a degree depends on the device (a ChArUco pipeline, a tracker). Guessed weights either
throw the rotations away or let them dominate. The fit instead weights each block by 1/σ and
re-estimates each σ from its block's residuals (iterated re-weighting, a feasible generalised
least squares), a few rounds until the σ's settle.

Each block's σ² is its sum of squares divided by its share of the degrees of freedom: the n_b
coordinates of the block less its share (n_b / n) of the p fitted parameters, which removes the
fit's own optimism (σ² would come out (n − p)/n too small).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from armtool.calib.fit.problems import Problem
from armtool.calib.model.se3 import Array

SETTLED = 0.05  # the σ's changed by less than 5 %: stop re-weighting (the solution moves far less)
ROUNDS = 6  # at most this many fits for the weights to settle
FLOOR = 1e-9  # relative to the first estimate: exact (simulated) data must not divide by zero


def estimate(problem: Problem, x: Array, parameters: int, rows: Sequence[int] | None = None) -> Array:
    """σ per block (internal units) from the residuals of `rows` (default: all) at x."""
    r = problem.raw(x)
    seen = problem.seen
    if rows is not None:
        r, seen = r[list(rows)], seen[list(rows)]
    total = max(int(seen.sum()), 1)
    sigma = np.empty(len(problem.blocks))
    for b in range(len(problem.blocks)):
        cols = problem.column_blocks == b
        n_b = int(seen[:, cols].sum())
        dof = max(n_b - parameters * n_b / total, 1.0)
        sigma[b] = float(np.sqrt((r[:, cols] ** 2).sum() / dof))
    scale = float(sigma.max()) if sigma.size and sigma.max() > 0 else 1.0
    out: Array = np.maximum(sigma, FLOOR * scale) if scale > 0 else np.ones_like(sigma)
    return out


def settled(old: Array, new: Array) -> bool:
    """Whether a re-weighting round still matters: the largest relative change of a σ."""
    return bool(np.all(np.abs(new - old) <= SETTLED * np.maximum(old, 1e-300)))
