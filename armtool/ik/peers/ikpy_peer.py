"""Peer `ikpy`: ikpy's `Chain.inverse_kinematics_frame` (scipy least squares on the full pose).

Configuration: `ikpy.chain.Chain.from_urdf_file(file, base_elements=[base], active_links_mask)`
on the chain's path only (`path_urdf`, written to a temporary file once: ikpy reads files, and
on the whole URDF it follows the tree past our tip, e.g. into a finger), then
`inverse_kinematics_frame(target, initial_position=full, orientation_mode="all")` with ikpy's
defaults otherwise (optimizer "least_squares", scipy's tolerances, symbolic FK).

ikpy's q vector has one entry per ikpy link: an origin link first, then one per URDF joint on
the path, fixed ones included; only the moving joints are active (the mask), and our q is
scattered into / gathered from those entries. ikpy has no timeout, no restarts and no success
flag: one local solve from the seed, judged by our FK.
"""

from __future__ import annotations

import os
import tempfile
import warnings
from typing import Any

import numpy as np
from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik.peers import check_fk, path_urdf
from armtool.ik.solver import Answer, Array, Solver
from armtool.model.chain import Chain


class IkPy(Solver):
    name = "ikpy"
    summary = "ikpy inverse_kinematics_frame (scipy least squares, orientation 'all'); no timeout, no restarts"

    def __init__(self, chain: Chain, root: etree._Element, *, timeout: float, tolerance: float) -> None:
        Solver.__init__(self, chain, timeout=timeout, tolerance=tolerance)
        from ikpy.chain import Chain as IkpyChain

        urdf = path_urdf(root, chain)
        mask = [False] + [j.get("type") != "fixed" for j in urdf.findall("joint")]  # origin link, then one per joint
        fd, path = tempfile.mkstemp(suffix=".urdf")
        try:
            with os.fdopen(fd, "wb") as handle:
                handle.write(etree.tostring(urdf))
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # ikpy warns about the fixed links it reads
                self._chain: Any = IkpyChain.from_urdf_file(
                    path, base_elements=[chain.base], active_links_mask=mask, name=chain.name
                )
        finally:
            os.unlink(path)
        names = [link.name for link in self._chain.links]
        if len(names) != len(mask) or [n for n, m in zip(names, mask) if m] != chain.joint_names:
            raise ArmtoolError(
                f"ikpy reads the joints of '{chain.base}' → '{chain.tip}' as {names[1:]}",
                hint=f"expected {chain.joint_names}",
            )
        self._mask = np.array(mask)
        self._full = np.zeros(len(mask))

        def fk(q: Array) -> Array:
            full = self._full.copy()
            full[self._mask] = q
            return np.asarray(self._chain.forward_kinematics(full), dtype=float)

        check_fk(self.name, chain, fk)

    def prepare(self, target: Array, seed: Array) -> tuple[Array, Array]:
        """ikpy's arguments: the target, and the seed spread over ikpy's links (fixed ones at 0)."""
        full = self._full.copy()
        full[self._mask] = seed
        return np.asarray(target, dtype=float), full

    def call(self, prepared: tuple[Array, Array]) -> Any:
        target, full = prepared
        return self._chain.inverse_kinematics_frame(target, initial_position=full, orientation_mode="all")

    def answer(self, raw: Any) -> Answer:
        # ikpy returns its local optimum without a verdict: our check is the only one.
        return Answer(np.asarray(raw, dtype=float)[self._mask], False, 0, "ikpy's local solve did not reach the target")
