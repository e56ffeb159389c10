"""Peer `pytracik`: TRAC-IK's own C++ (pytracik bindings), Speed solve type, same timeout and epsilon."""

from __future__ import annotations

from typing import Any

import numpy as np
from lxml import etree

from armtool.ik.chain import Chain
from armtool.ik.solver import Array, IKResult, Solver


class PyTracIK(Solver):
    name = "pytracik"
    summary = "TRAC-IK (C++) through pytracik, solve type Speed"

    def __init__(self, chain: Chain, root: etree._Element, *, timeout: float, tolerance: float) -> None:
        super().__init__(chain, timeout=timeout, tolerance=tolerance)
        import pytracik

        self._pytracik: Any = pytracik
        self._solver = pytracik.TRAC_IK(chain.base, chain.tip, etree.tostring(root).decode(), timeout, tolerance,
                                        pytracik.SolveType.Speed)
        # pytracik 0.0.3 reads some URDFs' limits as all zero (Panda): hand it the URDF's limits.
        pytracik.set_joint_limits(self._solver, chain.lower.copy(), chain.upper.copy())

    def solve(self, target: Array, seed: Array) -> IKResult:
        import pinocchio as pin

        x, y, z, w = pin.Quaternion(target[:3, :3]).coeffs()  # pytracik takes x y z, qx qy qz qw
        out = np.asarray(self._pytracik.ik(self._solver, np.asarray(seed, dtype=float), *target[:3, 3], x, y, z, w))
        q = out[1:] if out.size == self.chain.n + 1 else np.asarray(seed, dtype=float)
        return self._result(q, target, 0, "TRAC-IK found no solution" if out[0] <= 0 else "")
