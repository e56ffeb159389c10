"""Peer `pytracik`: TRAC-IK's own C++ through the pytracik 0.0.3 bindings, solve type Speed.

Configuration: `pytracik.TRAC_IK(base, tip, urdf, timeout, epsilon, SolveType.Speed)` with our
timeout, then `pytracik.ik(solver, seed, x, y, z, qx, qy, qz, qw)` → [rc, q...] (rc >= 0: found).

- epsilon = tolerance / √3. TRAC-IK races two solvers that test convergence differently: its KDL
  Newton thread tests every component of diff(FK, target) in the base frame (as we do), its SQP
  thread every component of diffRelative(target, FK), i.e. in the target's frame. A twist whose
  target-frame components are within eps has base-frame components within √3·eps, so with
  eps = tolerance/√3 every answer TRAC-IK accepts also passes our base-frame test (with eps =
  tolerance, 1-5 % of its answers fail our check on xArm7/Kinova).
- Joint limits: pytracik 0.0.3 reads the limits of joints that have a <safety_controller> as
  [0, min(upper, 0)] (all of Panda's), and stores the others as float32, which rounds some
  limits outward by 2e-7 rad. We set the URDF's limits as doubles (`set_joint_limits`), leaving
  continuous joints unbounded as TRAC-IK reads them.
- The URDF is the chain's path only (`path_urdf`): with the whole file, KDL prints a warning on
  stdout when the root link has an <inertial> (Panda, Kinova).
- TRAC-IK reports no iteration count: `iterations` is 0.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pinocchio as pin
from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik.peers import check_fk, path_urdf
from armtool.ik.solver import Answer, Array, Solver
from armtool.model.chain import Chain


class PyTracIK(Solver):
    name = "pytracik"
    summary = "TRAC-IK (C++, pytracik): KDL Newton with random restarts racing an NLopt SQP, solve type Speed"

    def __init__(self, chain: Chain, root: etree._Element, *, timeout: float, tolerance: float) -> None:
        Solver.__init__(self, chain, timeout=timeout, tolerance=tolerance)
        import pytracik

        urdf = etree.tostring(path_urdf(root, chain), encoding="unicode")
        self._solver: Any = pytracik.TRAC_IK(
            chain.base, chain.tip, urdf, self.timeout, self.tolerance / math.sqrt(3.0), pytracik.SolveType.Speed
        )
        n = pytracik.get_num_joints(self._solver)
        if n != chain.n:
            raise ArmtoolError(
                f"TRAC-IK sees {n} moving joints between '{chain.base}' and '{chain.tip}', armtool {chain.n}"
            )
        lower = np.where(chain.continuous, pytracik.get_joint_lower_bounds(self._solver), chain.lower)
        upper = np.where(chain.continuous, pytracik.get_joint_upper_bounds(self._solver), chain.upper)
        pytracik.set_joint_limits(self._solver, lower.tolist(), upper.tolist())
        self._ik = pytracik.ik
        check_fk(self.name, chain, lambda q: pytracik.fk(self._solver, q))

    def prepare(self, target: Array, seed: Array) -> tuple[Any, ...]:
        """pytracik's arguments: the seed, then the target as x, y, z and a quaternion x, y, z, w."""
        target = np.asarray(target, dtype=float)
        x, y, z, w = pin.Quaternion(target[:3, :3]).coeffs()
        return (np.asarray(seed, dtype=float), *target[:3, 3].tolist(), float(x), float(y), float(z), float(w))

    def call(self, prepared: tuple[Any, ...]) -> Any:
        return self._ik(self._solver, *prepared)

    def answer(self, raw: Any) -> Answer:
        out = np.asarray(raw, dtype=float)
        found = bool(out[0] >= 0)
        return Answer(out[1:], found, 0, "" if found else f"TRAC-IK found no solution (rc {out[0]:g})")
