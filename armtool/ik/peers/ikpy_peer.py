"""Peer `ikpy`: ikpy's scipy-based inverse_kinematics_frame (full pose), chain built from the URDF."""

from __future__ import annotations

import os
import tempfile
from typing import Any

import numpy as np
from lxml import etree

from armtool.ik.chain import Chain
from armtool.ik.solver import Array, IKResult, Solver


class IkPy(Solver):
    name = "ikpy"
    summary = "ikpy inverse_kinematics_frame (scipy least squares), orientation mode 'all'"

    def __init__(self, chain: Chain, root: etree._Element, *, timeout: float, tolerance: float) -> None:
        super().__init__(chain, timeout=timeout, tolerance=tolerance)
        from ikpy.chain import Chain as IkpyChain

        fd, path = tempfile.mkstemp(suffix=".urdf")
        try:
            with os.fdopen(fd, "wb") as handle:
                handle.write(etree.tostring(root))
            import warnings

            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # ikpy warns about fixed links in its default mask
                probe = IkpyChain.from_urdf_file(path, base_elements=[chain.base])
                names = [link.name for link in probe.links]
                mask = [name in chain.joint_names for name in names]
                self._chain: Any = IkpyChain.from_urdf_file(path, base_elements=[chain.base], active_links_mask=mask)
        finally:
            os.unlink(path)
        self._index = [names.index(j) for j in chain.joint_names]  # ikpy's vector has one entry per link

    def solve(self, target: Array, seed: Array) -> IKResult:
        full = np.zeros(len(self._chain.links))
        full[self._index] = seed
        out = self._chain.inverse_kinematics_frame(target, initial_position=full, orientation_mode="all")
        return self._result(np.asarray(out, dtype=float)[self._index], target, 0, "ikpy did not converge")
