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
                # ikpy follows the chain named by base_elements: base link, joint, link, ... down to our tip.
                elements = _path_elements(root, chain.base, chain.tip)
                probe = IkpyChain.from_urdf_file(path, base_elements=elements)
                names = [link.name for link in probe.links]
                # ikpy keeps following the tree past the last element: cut at the joint into our tip.
                names = names[: names.index(elements[-2]) + 1] if len(elements) > 1 else names
                mask = [name in chain.joint_names for name in names]
                self._chain: Any = IkpyChain(probe.links[: len(names)], active_links_mask=mask, name=chain.name)
        finally:
            os.unlink(path)
        self._index = [names.index(j) for j in chain.joint_names]  # ikpy's vector has one entry per link

    def solve(self, target: Array, seed: Array) -> IKResult:
        full = np.zeros(len(self._chain.links))
        full[self._index] = seed
        out = self._chain.inverse_kinematics_frame(target, initial_position=full, orientation_mode="all")
        return self._result(np.asarray(out, dtype=float)[self._index], target, 0, "ikpy did not converge")


def _path_elements(root: etree._Element, base: str, tip: str) -> list[str]:
    """[base, joint, link, joint, ..., tip] along the URDF tree."""
    by_child = {j.find("child").get("link"): j for j in root.findall("joint") if j.find("child") is not None}
    out = [tip]
    while out[-1] != base:
        joint = by_child[out[-1]]
        out += [joint.get("name", ""), joint.find("parent").get("link", "")]  # type: ignore[union-attr]
    return list(reversed(out))
