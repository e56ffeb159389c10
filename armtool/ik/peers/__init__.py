"""Peer IK solvers (optional extra `armtool[peers]`), run in the same process on the same targets.

Each adapter is one module with a Solver subclass; PEERS maps its name to the module and
to the pip command that installs what it needs.
"""

from __future__ import annotations

import importlib
import importlib.util
from typing import Any

from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik.chain import Chain
from armtool.ik.solver import Solver

# name -> ("module:Class", python module it needs, how to install it)
PEERS: dict[str, tuple[str, str, str]] = {
    "pytracik": ("armtool.ik.peers.pytracik_peer:PyTracIK", "pytracik", "pip install 'armtool[peers]' (or pip install pytracik)"),
    "rtb-lm": ("armtool.ik.peers.rtb_lm:RtbLM", "roboticstoolbox", "pip install 'armtool[peers]' (or pip install roboticstoolbox-python)"),
    "ikpy": ("armtool.ik.peers.ikpy_peer:IkPy", "ikpy", "pip install 'armtool[peers]' (or pip install ikpy)"),
}


def peer_names() -> list[str]:
    return list(PEERS)


def make_peer(name: str, chain: Chain, root: etree._Element, *, timeout: float, tolerance: float) -> Solver | str:
    """A ready peer solver, or the reason it cannot run here (with the install command)."""
    if name not in PEERS:
        from armtool.lint.suggest import did_you_mean

        raise ArmtoolError(f"unknown peer '{name}'{did_you_mean(name, PEERS)}", hint="peers: " + ", ".join(PEERS))
    target, needs, install = PEERS[name]
    if importlib.util.find_spec(needs) is None:
        return f"{needs} is not installed: {install}"
    module, _, cls = target.partition(":")
    peer_cls: Any = getattr(importlib.import_module(module), cls)
    return peer_cls(chain, root, timeout=timeout, tolerance=tolerance)  # type: ignore[no-any-return]
