"""Peer IK solvers (optional extra `armtool[peers]`), run in the same process on the same targets.

Each adapter is one module with a Solver subclass; PEERS maps its name to the module and
to the command that installs what it needs. Adapters import their peer library only when
built, take q in the chain's joint order, and never trust the peer's own success flag:
`Solver.judge` re-verifies every answer with our FK. Each adapter's `call` is the peer's own solve
call and nothing else: converting the target into the peer's form is `prepare`, reading its
output back is `answer`, both untimed, as armtool's own solvers are timed.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik.solver import Array, Solver
from armtool.model.chain import Chain

# name -> ("module:Class", python module it needs, how to install it)
PEERS: dict[str, tuple[str, str, str]] = {
    "pytracik": (
        "armtool.ik.peers.pytracik_peer:PyTracIK",
        "pytracik",
        "pip install 'armtool[peers]' (or pip install pytracik)",
    ),
    "rtb-lm": (
        "armtool.ik.peers.rtb_lm:RtbLM",
        "roboticstoolbox",
        "pip install 'armtool[peers]' (or pip install roboticstoolbox-python)",
    ),
    "ikpy": ("armtool.ik.peers.ikpy_peer:IkPy", "ikpy", "pip install 'armtool[peers]' (or pip install ikpy)"),
    "pykdl": ("armtool.ik.peers.pykdl_peer:PyKdlNrJl", "PyKDL", "apt install python3-pykdl (ROS)"),
    "eaik": ("armtool.ik.peers.eaik_peer:Eaik", "eaik", "pip install 'armtool[peers]' (or pip install eaik)"),
    "ik-geo": ("armtool.ik.peers.ik_geo_peer:IkGeo", "ik_geo", "pip install 'armtool[peers]' (or pip install ik-geo)"),
}


def peer_names() -> list[str]:
    return list(PEERS)


def check_peer_name(name: str) -> None:
    """An ArmtoolError (exit 2) for a name that is not a peer, with the closest one."""
    if name not in PEERS:
        from armtool.suggest import did_you_mean

        raise ArmtoolError(f"unknown peer '{name}'{did_you_mean(name, PEERS)}", hint="peers: " + ", ".join(PEERS))


def make_peer(name: str, chain: Chain, root: etree._Element, *, timeout: float, tolerance: float) -> Solver | str:
    """A ready peer solver, or the reason it cannot run here (with the install command). A peer that
    cannot take this chain (a closed form's family, its joint count) raises ArmtoolError saying why.
    A locked chain's peers read a URDF with the locked joints fixed at their values, except a peer
    whose class says it `takes_locks` itself (EAIK's fixed_axes)."""
    check_peer_name(name)
    target, needs, install = PEERS[name]
    if importlib.util.find_spec(needs) is None:
        return f"{needs} is not installed: {install}"
    module, _, cls = target.partition(":")
    peer_cls: Any = getattr(importlib.import_module(module), cls)
    if chain.locks and not getattr(peer_cls, "takes_locks", False):
        from armtool.ik.locks import locked_urdf

        root = locked_urdf(root, chain)  # the locked joints fixed at their values: the chain the peer reads
    return peer_cls(chain, root, timeout=timeout, tolerance=tolerance)  # type: ignore[no-any-return]


def path_urdf(root: etree._Element, chain: Chain) -> etree._Element:
    """A kinematics-only URDF of the chain: the links and joints from chain.base to chain.tip.

    Peers parse it with their own URDF readers. Handing them only the path keeps them on our
    chain (ikpy follows the tree past the last element it is given; rtb's `ets(start=link)`
    includes that link's own joint unless the link is the root) and keeps out what they trip on
    (rtb resolves `package://` mesh paths; KDL prints a warning on stdout when the root link has
    an <inertial>). Joints are copied whole: origin, axis, limits.
    """
    by_child = {j.find("child").get("link"): j for j in root.findall("joint") if j.find("child") is not None}
    joints: list[etree._Element] = []
    link = chain.tip
    while link != chain.base:
        joint = by_child[link]
        joints.append(joint)
        link = joint.find("parent").get("link", "")
    out = etree.Element("robot", name=root.get("name", "robot"))
    etree.SubElement(out, "link", name=chain.base)
    for joint in reversed(joints):
        etree.SubElement(out, "link", name=joint.find("child").get("link", ""))
    for joint in reversed(joints):
        out.append(etree.fromstring(etree.tostring(joint)))
    return out


def check_fk(name: str, chain: Chain, fk: Callable[[Array], Array]) -> None:
    """Raise if the peer's FK (q in chain order → 4x4 tip pose in the base frame) disagrees with ours."""
    rng = np.random.default_rng(0)
    worst = 0.0
    for q in [chain.mid(), *chain.random(rng, 3)]:
        worst = max(worst, float(np.abs(np.asarray(fk(q), dtype=float) - chain.fk(q)).max()))
    if not worst < 1e-9:
        raise ArmtoolError(
            f"peer '{name}' reads {chain.base} → {chain.tip} differently from armtool (FK differs by {worst:.3g})",
            hint="its answers could not be compared; please report this with the URDF",
        )


def tool_transform(chain: Chain, fk: Callable[[Array], Array]) -> Array:
    """The constant C with chain.fk(q) = fk(q)·C, for a peer whose tool frame is not the chain's tip
    but moves with the last joint (EAIK, IK-Geo: the last joint's point, turned to the base's
    orientation); measured at q = 0. check_fk then proves it on other configurations."""
    zero = np.zeros(chain.n)
    out: Array = np.linalg.inv(np.asarray(fk(zero), dtype=float)) @ chain.fk(zero)
    return out


def check_closed_form_chain(peer: str, chain: Chain, *, max_joints: int, beyond: str) -> None:
    """Raise (the row's reason) unless the chain is all revolute with at most max_joints joints:
    what the closed-form peers take. `beyond` says what the peer does with more joints."""
    prismatic = [j.name for j in chain.joints if j.kind == "prismatic"]
    if prismatic:
        raise ArmtoolError(f"{peer} takes revolute joints only; {', '.join(prismatic)} is prismatic")
    if chain.n > max_joints:
        raise ArmtoolError(f"{peer} cannot take {chain.n} joints: {beyond}")


@contextmanager
def native_stdout_to_stderr() -> Iterator[None]:
    """File descriptor 1 points at stderr while the block runs, then back at stdout.

    Peers are C/C++ libraries that print on the process's stdout themselves (TRAC-IK's
    `WARNING:NLOpt_IK ...` on every solve of a 1-joint chain, KDL's warnings), past Python's
    sys.stdout, where ik-bench's JSON or CSV goes. C stdio buffers are flushed before fd 1 is
    restored, so nothing buffered inside the block lands on stdout later. Without a usable fd 1
    or fd 2 (closed), the block runs as it is.
    """
    try:
        sys.stdout.flush()
    except (OSError, ValueError):  # closed or broken: nothing of ours is pending
        pass
    try:
        saved = os.dup(1)
    except OSError:
        saved = -1
    if saved >= 0:
        try:
            os.dup2(2, 1)
        except OSError:
            os.close(saved)
            saved = -1
    try:
        yield
    finally:
        if saved >= 0:
            _flush_c_stdio()
            os.dup2(saved, 1)
            os.close(saved)


def _flush_c_stdio() -> None:
    """fflush(NULL): whatever C code printf-ed into stdio's buffers goes out now (to stderr)."""
    try:
        import ctypes

        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError, TypeError):  # no C library to ask (Windows: CDLL(None) fails)
        pass
