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
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import IO, Any

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


@dataclass
class Captured:
    """What native code wrote on file descriptor 2 inside a native_stderr_captured block (filled in
    when the block ends)."""

    text: str = ""


@contextmanager
def native_stderr_captured() -> Iterator[Captured]:
    """File descriptor 2 points at a temporary file while the block runs; what was written there
    is the yielded Captured's text once the block ends.

    For native code that writes on fd 2 itself, past sys.stderr: Rust's panic hook prints
    "thread '<unnamed>' panicked at ..." (and, with RUST_BACKTRACE set, a backtrace) on fd 2 before
    pyo3 turns the panic into an exception, in the middle of ik-bench's progress bar.

    Python's own stderr is not captured: when sys.stderr writes on fd 2, it is swapped for a stream
    on a duplicate of the original fd 2 for the duration and put back after. The rich console (and
    its progress bar) looks sys.stderr up at every write, so its refreshes stay on the terminal and
    out of what is captured; letting them go to the file too would lose the frames and fill the
    capture with them. (A logging handler made before the block keeps the stream it was given: its
    lines inside the block are captured. A sys.stderr on another descriptor, as under a test runner,
    is left as it is: fd 2 is not where it writes.) C stdio buffers are flushed before fd 2 is
    restored. Without a usable fd 2 (closed) or a temporary file, the block runs as it is and
    nothing is captured. A process that
    dies inside the block (a native abort) takes what was captured with it.
    """
    captured = Captured()
    try:
        saved = os.dup(2)
    except OSError:
        saved = -1
    sink: IO[bytes] | None = None
    if saved >= 0:
        try:
            sink = tempfile.TemporaryFile()
        except OSError:
            os.close(saved)
            saved = -1
    if sink is None:
        yield captured
        return
    python_stderr = sys.stderr
    ours = _stream_on(saved, python_stderr)
    if ours is not None:
        sys.stderr = ours
    try:
        python_stderr.flush()  # what Python had buffered for fd 2 goes out before fd 2 moves
    except (OSError, ValueError, AttributeError):
        pass
    try:
        os.dup2(sink.fileno(), 2)
        moved = True
    except OSError:
        moved = False
    try:
        yield captured
    finally:
        if moved:
            _flush_c_stdio()
            os.dup2(saved, 2)
        if ours is not None:
            try:
                ours.flush()
            except (OSError, ValueError):
                pass
            sys.stderr = python_stderr
            ours.close()  # closefd=False: the duplicate itself is closed next
        os.close(saved)
        sink.seek(0)
        captured.text = sink.read().decode("utf-8", "replace")
        sink.close()


def _stream_on(fd: int, stream: IO[str] | None) -> IO[str] | None:
    """A text stream on fd (a duplicate of fd 2) like `stream`, if `stream` writes on fd 2; else None."""
    try:
        if stream is None or stream.fileno() != 2:
            return None
    except (OSError, ValueError, AttributeError):  # no descriptor (a StringIO), or closed
        return None
    return open(  # closed by native_stderr_captured
        fd,
        "w",
        buffering=1,
        encoding=getattr(stream, "encoding", None) or "utf-8",
        errors=getattr(stream, "errors", None) or "backslashreplace",
        closefd=False,
    )


def _flush_c_stdio() -> None:
    """fflush(NULL): whatever C code printf-ed into stdio's buffers goes out now (to stderr)."""
    try:
        import ctypes

        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError, TypeError):  # no C library to ask (Windows: CDLL(None) fails)
        pass
