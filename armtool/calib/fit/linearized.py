"""A fit's residual problem linearised at its solution: what the cross-validation folds are fitted on.

Why: choosing the parameter set by (nested) k-fold cross-validation fits every candidate set on
every training fold, 120 fits on a 5-fold nested ladder of four sets, and each fit of 1000
tracker poses costs a second: the default fit took 24 times as long as the plain one. A training
fold holds most of the samples the full fit used, so its solution is a small step from the full
fit's, over which the model is linear to far below its noise: the residuals move by
J·Δx + O(|Δx|² / L), with corrections of hundredths of a millimetre against links of 0.1–1 m.
So each fold is fitted by the same procedure as the full fit (`fit_set`: robust rounds, outliers
named, the noise re-estimated, the combinations its own samples determine), on the residuals and
Jacobian of the full fit, r(x) = r̂ + Ĵ·(x − x̂), sliced to the fold's rows: no chain is built in a
fold's fit. The held-out samples are then scored with the real model at the fold's solution.

Two Jacobians are kept: at the full fit's solution (the fit's steps) and at the nominal robot
(where `fit_set` judges what the data determine). The full fits themselves are fitted on the
problem linearised at the nominal robot (`at_nominal`, from the Jacobian the identifiability
analysis took there), and only the chosen set on the real model (`calibration._full_ladder`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from armtool.calib.fit.problems import Problem
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.se3 import Array


class LinearizedProblem(Problem):
    """`base`'s samples with raw residuals r̂ + Ĵ·(x − x̂)[free] (`jacobian` at x̂, or at the nominal point)."""

    linear = True

    def __init__(
        self,
        base: Problem,
        x_hat: Array,
        free: Sequence[int],
        r_hat: Array,
        J_hat: Array,
        nominal: Array,
        J_nominal: Array,
        sigma: Array | None = None,
        nominal_rows: list[int] | None = None,
    ) -> None:
        self.blocks = base.blocks
        self.column_blocks = base.column_blocks
        self.base, self.x_hat, self.free = base, x_hat, list(free)
        self.r_hat, self.J_hat = r_hat, J_hat  # (N, k) and (N, k, len(free)), raw units
        self.nominal = nominal
        self._J_nominal, self._nominal_rows = J_nominal, nominal_rows  # sliced when asked (a fold never is)
        super().__init__(base.model, base.Q, base.sigma if sigma is None else sigma)

    @property
    def J_nominal(self) -> Array:
        """(N, k, len(free)) the Jacobian at the nominal point, raw units."""
        if self._nominal_rows is not None:
            self._J_nominal, self._nominal_rows = self._J_nominal[self._nominal_rows], None
        return self._J_nominal

    @classmethod
    def at(cls, problem: Problem, x_hat: Array, free: Sequence[int], start: LinearizedProblem) -> LinearizedProblem:
        """`problem` linearised at x̂ over `free` (a subset of `start`'s parameters): its Jacobian
        at x̂ (one chain build), and at the nominal point `start`'s, which is linearised there."""
        raw = problem.with_sigma(np.ones(len(problem.blocks)))  # Jacobians in raw units
        N, k = problem.samples, len(problem.column_blocks)
        J_hat = raw.jacobian(x_hat, free).reshape(N, k, len(free))
        J_nominal = start.J_hat[:, :, start._columns(free)]
        return cls(problem, x_hat, free, problem.raw(x_hat), J_hat, start.x_hat, J_nominal)

    @classmethod
    def at_nominal(cls, problem: Problem, nominal: Array, free: Sequence[int], J: Array) -> LinearizedProblem:
        """`problem` linearised at the nominal point from its Jacobian J there (noise-weighted, as
        `Problem.jacobian` gives it): the full fit's ladder is fitted on it, without a chain build."""
        N, k = problem.samples, len(problem.column_blocks)
        J_raw = J.reshape(N, k, len(free)) / problem.weights()[None, :, None]
        return cls(problem, nominal, free, problem.raw(nominal), J_raw, nominal, J_raw)

    def _columns(self, free: Sequence[int]) -> NDArray[np.intp]:
        position = {p: c for c, p in enumerate(self.free)}
        return np.array([position[p] for p in free], dtype=np.intp)

    def raw(self, x: Array) -> Array:
        out: Array = self.r_hat + self.J_hat @ (x[self.free] - self.x_hat[self.free])
        return out

    def jacobian(self, x: Array, free: Sequence[int], h: float = 0.0) -> Array:
        """∂ `residuals` / ∂ `free` (a subset of the linearised parameters): Ĵ, or the nominal
        robot's Jacobian when x is the nominal point; noise-weighted as `Problem.jacobian`."""
        J = self.J_nominal if np.array_equal(x, self.nominal) else self.J_hat
        if list(free) != self.free:  # a fold's fit takes every column: no copy to pick them
            J = J[:, :, self._columns(free)]
        out: Array = (J * self.weights()[None, :, None]).reshape(-1, len(free))
        return out

    def _residuals(self, C: Array) -> Array:
        raise NotImplementedError("a linearised problem has residuals only through `raw`")

    @property
    def seen(self) -> NDArray[np.bool_]:
        return self.base.seen

    def subset(self, rows: Sequence[int]) -> LinearizedProblem:
        """The same linearisation on some rows (itself when they are all its rows, in order: a
        fit without outliers takes that subset several times per fit)."""
        rows = list(rows)
        if rows == list(range(self.samples)):
            return self
        pending = rows if self._nominal_rows is None else [self._nominal_rows[r] for r in rows]
        return LinearizedProblem(
            self.base.subset(rows),
            self.x_hat,
            self.free,
            self.r_hat[rows],
            self.J_hat[rows],
            self.nominal,
            self._J_nominal,
            self.sigma,
            pending,
        )

    def with_model(self, model: CalibModel) -> LinearizedProblem:
        """The same linearisation (its model is the full fit's; a fold never changes it)."""
        return LinearizedProblem(
            self.base,
            self.x_hat,
            self.free,
            self.r_hat,
            self.J_hat,
            self.nominal,
            self._J_nominal,
            self.sigma,
            self._nominal_rows,
        )

    def _closed_form_frames(self) -> tuple[Array, Array]:
        raise NotImplementedError("a linearised problem starts from the fit it linearises")
