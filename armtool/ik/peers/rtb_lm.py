"""Peer `rtb-lm`: roboticstoolbox-python's C++ `ETS.ik_LM` (Levenberg–Marquardt with random restarts).

Configuration, as shipped except `tol`:
- `ik_LM(Tep, q0=seed, ilimit=30, slimit=100, tol=tolerance²/2, joint_limits=True,
  method="chan", k=1.0)`: its defaults are 30 iterations per search × 100 searches, each
  search after the first from a random configuration within the limits (std::rand).
- `tol`: rtb accepts when E = ½‖e‖² < tol, e = [p_target − p; angle-axis of R_target Rᵀ] in the
  base frame (our error). Its default 1e-6 accepts ‖e‖ up to 1.4e-3; tolerance²/2 accepts
  ‖e‖ < tolerance, so every component is within the tolerance, like every other solver here.
- No timeout: ik_LM has none, so a failing solve runs all 100 searches (it may take longer than
  the protocol's timeout; benchmarks/ik_bench.py counts those).
- The robot is read with rtb's own URDF reader (`URDF_file`) from the chain's path only
  (`path_urdf`): no meshes to resolve, and the base is the root, so `robot.ets(start=base,
  end=tip)` holds exactly the chain's joints in chain order (checked by FK at construction).
"""

from __future__ import annotations

import io
from typing import Any

import numpy as np
from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik.peers import check_fk, path_urdf
from armtool.ik.solver import Answer, Array, Solver
from armtool.model.chain import Chain


class RtbLM(Solver):
    name = "rtb-lm"
    summary = "roboticstoolbox-python ik_LM (C++, Chan damping), 30 iterations × 100 searches, joint limits on"

    ILIMIT = 30  # rtb's default iterations per search
    SLIMIT = 100  # rtb's default number of searches

    def __init__(self, chain: Chain, root: etree._Element, *, timeout: float, tolerance: float) -> None:
        Solver.__init__(self, chain, timeout=timeout, tolerance=tolerance)
        import roboticstoolbox as rtb
        from roboticstoolbox.models.URDF.URDFRobot import URDF_file

        text = etree.tostring(path_urdf(root, chain), encoding="unicode")
        links, name, _ = URDF_file(io.StringIO(text))
        self._ets: Any = rtb.Robot(links, name=name).ets(start=chain.base, end=chain.tip)
        if self._ets.n != chain.n:
            raise ArmtoolError(
                f"rtb sees {self._ets.n} moving joints between '{chain.base}' and '{chain.tip}', armtool {chain.n}"
            )
        self._tol = 0.5 * self.tolerance**2
        check_fk(self.name, chain, lambda q: self._ets.fkine(q).A)

    def call(self, prepared: tuple[Array, Array]) -> Any:
        target, seed = prepared
        return self._ets.ik_LM(
            target, q0=seed, ilimit=self.ILIMIT, slimit=self.SLIMIT, tol=self._tol, joint_limits=True
        )

    def answer(self, raw: Any) -> Answer:
        reason = "" if raw.success else f"ik_LM found no solution in {raw.searches} searches"
        return Answer(np.asarray(raw.q, dtype=float), bool(raw.success), int(raw.iterations), reason)
