"""Every IK solver by name. A new solver is one module plus one line here (imported on use)."""

from __future__ import annotations

import importlib
from typing import Any

from armtool.errors import ArmtoolError
from armtool.ik.solver import Solver
from armtool.model.chain import Chain

SOLVERS: dict[str, str] = {
    "lm": "armtool.ik.solvers.lm:LevenbergMarquardt",
    "dls": "armtool.ik.solvers.dls:DampedLeastSquares",
    "kdl-nr-jl": "armtool.ik.solvers.kdl_nr_jl:KdlNewtonRaphsonJL",
    "kdl-lma": "armtool.ik.solvers.kdl_lma:KdlLevenbergMarquardt",
    "trac": "armtool.ik.solvers.trac:TracIK",
    "analytic": "armtool.ik.solvers.analytic:Analytic",
    "search": "armtool.ik.solvers.search:Search",
}


def solver_names() -> list[str]:
    """Solvers whose module is present (the registry may name solvers still being written)."""
    import importlib.util

    return [n for n, target in SOLVERS.items() if importlib.util.find_spec(target.partition(":")[0]) is not None]


def solver_class(name: str) -> type[Solver]:
    if name not in SOLVERS:
        from armtool.suggest import did_you_mean

        raise ArmtoolError(
            f"unknown solver '{name}'{did_you_mean(name, SOLVERS)}", hint="solvers: " + ", ".join(SOLVERS)
        )
    module, _, cls = SOLVERS[name].partition(":")
    return getattr(importlib.import_module(module), cls)  # type: ignore[no-any-return]


def make_solver(name: str, chain: Chain, timeout: float = 0.005, tolerance: float = 1e-5, **options: Any) -> Solver:
    """A ready solver: `solver.solve(target_4x4, seed) -> IKResult`."""
    return solver_class(name)(chain, timeout=timeout, tolerance=tolerance, **options)
