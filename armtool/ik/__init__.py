"""Inverse kinematics: chains from URDF, solvers, and the benchmark behind `armtool ik-bench`.

from armtool.ik import load_chain, make_solver
chain = load_chain("panda.urdf", base="panda_link0", tip="panda_hand")
solver = make_solver("lm", chain, timeout=0.005, tolerance=1e-5)
result = solver.solve(target_4x4, seed)
"""

from __future__ import annotations

from typing import Any

__all__ = ["load_chain", "make_solver", "solver_names"]

# Bounds of ik-bench's inputs (light constants: the CLI's option callbacks use them before numpy loads).
# Per-solve budget: 200x the largest kinematics_solver_timeout in 15 real MoveIt configs (0.05 s).
MAX_TIMEOUT_S = 10.0
# Targets: 10x the TRAC-IK paper's 10,000; measured ~0.8 KB per target per solver row (20,000
# targets: +15 MB RSS for one row), so about 1 GB for the 11 rows of every solver and batch.
MAX_SAMPLES = 100_000


def __getattr__(name: str) -> Any:
    # Lazy: `import armtool.ik` must not import numpy/pinocchio until used.
    if name == "load_chain":
        from armtool.model.chain import load_chain

        return load_chain
    if name in ("make_solver", "solver_names"):
        from armtool.ik import registry

        return getattr(registry, name)
    raise AttributeError(name)
