"""Peer `rtb-lm`: roboticstoolbox-python's C++ `ik_LM` (Levenberg–Marquardt with restarts).

Configured as shipped (Chan's damping, 30 iterations × 100 searches, joint limits on), except
`tol`: rtb's tol bounds E = ½eᵀe, and its default 1e-6 accepts errors near 1e-3; 1e-12 asks for
the same 1e-5 precision as every other solver in the table. The URDF is handed over without
<visual>/<collision> (rtb would try to resolve their mesh packages; kinematics do not need them).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from lxml import etree

from armtool.ik.chain import Chain
from armtool.ik.solver import Array, IKResult, Solver


class RtbLM(Solver):
    name = "rtb-lm"
    summary = "roboticstoolbox-python ik_LM (C++), joint limits on, tol 1e-12"

    def __init__(self, chain: Chain, root: etree._Element, *, timeout: float, tolerance: float) -> None:
        super().__init__(chain, timeout=timeout, tolerance=tolerance)
        import copy

        import roboticstoolbox as rtb
        from roboticstoolbox.models.URDF.URDFRobot import _parse_urdf

        bare = copy.deepcopy(root)
        for el in bare.xpath("//visual|//collision"):
            el.getparent().remove(el)
        links, name = _parse_urdf(etree.tostring(bare).decode(), source=chain.name)
        self._ets: Any = rtb.Robot(links, name=name).ets(start=chain.base, end=chain.tip)

    def solve(self, target: Array, seed: Array) -> IKResult:
        sol = self._ets.ik_LM(target, q0=np.asarray(seed, dtype=float), joint_limits=True, tol=1e-12)
        return self._result(np.asarray(sol.q, dtype=float), target, int(sol.iterations), "ik_LM found no solution")
