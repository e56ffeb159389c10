"""Peer `pykdl`: Orocos KDL's own `ChainIkSolverPos_NR_JL` (C++, through PyKDL), run as TRAC-IK's benchmark runs it.

The reference for our `kdl-nr-jl`. Configuration: `ChainIkSolverPos_NR_JL(chain, q_min, q_max,
ChainFkSolverPos_recursive, ChainIkSolverVel_pinv, maxiter, eps=tolerance)`, called from the
seed as `CartToJnt(q, target, result)` and again from the result until rc >= 0 or the timeout,
with no random restarts (TRAC-IK's ik_tests.cpp builds it with maxiter = 1). NR_JL keeps no state
between iterations, so `ITERATIONS_PER_CALL` iterations per call give the same iterates with
less Python overhead; the timeout is checked between calls. Continuous joints get ±max-float
limits (no clamping), as TRAC-IK and MoveIt pass them.

The KDL chain is built from armtool's chain (PyKDL ships no URDF reader; kdl_parser_py is a ROS
package): one segment per moving joint, its joint on the axis through the segment origin, as
kdl_parser builds it, and a fixed segment for the tip offset. Checked by FK at construction.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from lxml import etree

from armtool.ik.peers import check_fk
from armtool.ik.solver import Answer, Array, Solver
from armtool.model.chain import Chain

_FLT_MAX = float(np.finfo(np.float32).max)


class PyKdlNrJl(Solver):
    name = "pykdl"
    summary = "Orocos KDL ChainIkSolverPos_NR_JL (C++, PyKDL), looped until timeout from the seed, no restarts"

    ITERATIONS_PER_CALL = 10

    def __init__(self, chain: Chain, root: etree._Element, *, timeout: float, tolerance: float) -> None:
        Solver.__init__(self, chain, timeout=timeout, tolerance=tolerance)
        import PyKDL as kdl

        self._kdl: Any = kdl
        kchain = kdl.Chain()
        for j in chain.joints:
            R, p = j.origin[:3, :3], j.origin[:3, 3]
            axis = R @ j.axis  # kdl_parser: the axis in the parent segment's frame, through the joint origin
            kind = kdl.Joint.TransAxis if j.kind == "prismatic" else kdl.Joint.RotAxis
            joint = kdl.Joint(j.name, kdl.Vector(*p), kdl.Vector(*axis), kind)
            kchain.addSegment(kdl.Segment(j.name, joint, _frame(kdl, j.origin)))
        kchain.addSegment(kdl.Segment("tip", kdl.Joint(kdl.Joint.Fixed), _frame(kdl, chain.tip_offset)))
        self._chain = kchain
        self._fk = kdl.ChainFkSolverPos_recursive(kchain)
        self._vel = kdl.ChainIkSolverVel_pinv(kchain)
        self._q_min, self._q_max = kdl.JntArray(chain.n), kdl.JntArray(chain.n)
        for i in range(chain.n):
            self._q_min[i] = -_FLT_MAX if chain.continuous[i] else chain.lower[i]
            self._q_max[i] = _FLT_MAX if chain.continuous[i] else chain.upper[i]
        self._ik = kdl.ChainIkSolverPos_NR_JL(
            kchain, self._q_min, self._q_max, self._fk, self._vel, self.ITERATIONS_PER_CALL, self.tolerance
        )

        def fk(q: Array) -> Array:
            out = kdl.Frame()
            self._fk.JntToCart(self._joints(q), out)
            return _matrix(out)

        check_fk(self.name, chain, fk)

    def _joints(self, q: Array) -> Any:
        a = self._kdl.JntArray(self.chain.n)
        for i, v in enumerate(q):
            a[i] = float(v)
        return a

    def prepare(self, target: Array, seed: Array) -> tuple[Any, Any, Any]:
        """KDL's arguments: the target frame, the seed and the result as JntArrays."""
        return _frame(self._kdl, np.asarray(target, dtype=float)), self._joints(seed), self._kdl.JntArray(self.chain.n)

    def call(self, prepared: tuple[Any, Any, Any]) -> tuple[int, int, Any]:
        """TRAC-IK's benchmark loop for KDL: CartToJnt from the last result until it succeeds or the time is up."""
        goal, q, result = prepared
        deadline = self.clock() + self.timeout
        calls = 0
        while True:
            rc = self._ik.CartToJnt(q, goal, result)
            calls += 1
            if rc >= 0 or self.clock() >= deadline:
                return rc, calls, result
            q, result = result, q

    def answer(self, raw: tuple[int, int, Any]) -> Answer:
        rc, calls, result = raw
        q = np.array([result[i] for i in range(self.chain.n)])
        return Answer(q, rc >= 0, calls * self.ITERATIONS_PER_CALL, "" if rc >= 0 else "timeout")


def _frame(kdl: Any, T: Array) -> Any:
    R = kdl.Rotation(*(float(v) for v in T[:3, :3].ravel()))
    return kdl.Frame(R, kdl.Vector(*(float(v) for v in T[:3, 3])))


def _matrix(F: Any) -> Array:
    T = np.eye(4)
    for r in range(3):
        for c in range(3):
            T[r, c] = F.M[r, c]
        T[r, 3] = F.p[r]
    return T
