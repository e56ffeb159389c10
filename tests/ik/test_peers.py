"""Peer adapters: a missing peer is reported with its install command; present ones solve in chain order.

The solving tests skip (importorskip) when a peer's library is absent; `pip install 'armtool[peers]'`
brings pytracik, roboticstoolbox-python, ikpy, eaik and ik-geo; PyKDL comes from apt (python3-pykdl).
"""

from __future__ import annotations

import importlib
import importlib.util
from functools import cache
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik.peers import PEERS, make_peer, path_urdf, peer_names
from armtool.ik.solver import Solver
from armtool.model.chain import Chain, chain_from_xml
from armtool.model.load import load_robot_xml
from tests.ik.robots import ARMS, PLANAR_2R, erd


@cache
def _arm(name: str) -> tuple[Chain, etree._Element]:
    relative, base, tip = ARMS[name]
    root = load_robot_xml(erd(relative))
    return chain_from_xml(root, base, tip), root


def arm(name: str) -> tuple[Chain, etree._Element]:
    erd(ARMS[name][0])  # skip (not cached) when example-robot-data is absent
    return _arm(name)


def planar() -> tuple[Chain, etree._Element]:
    root = etree.fromstring(PLANAR_2R)
    return chain_from_xml(root), root


def peer(name: str, robot: str, timeout: float = 0.05) -> Solver:
    pytest.importorskip(PEERS[name][1])
    chain, root = arm(robot)
    solver = make_peer(name, chain, root, timeout=timeout, tolerance=1e-5)
    assert isinstance(solver, Solver), solver
    return solver


# ---- without any peer installed -------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(PEERS))
def test_missing_peer_returns_its_install_command(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    chain, root = planar()
    _, needs, install = PEERS[name]
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda mod, *a, **k: None if mod == needs else real(mod, *a, **k))
    assert make_peer(name, chain, root, timeout=0.005, tolerance=1e-5) == f"{needs} is not installed: {install}"


def test_install_commands() -> None:
    for name in ("pytracik", "rtb-lm", "ikpy", "eaik", "ik-geo"):
        assert "pip install 'armtool[peers]'" in PEERS[name][2]
    assert PEERS["pykdl"][1:] == ("PyKDL", "apt install python3-pykdl (ROS)")


def test_unknown_peer_lists_the_known_ones() -> None:
    chain, root = planar()
    with pytest.raises(ArmtoolError, match="unknown peer 'pytrac'.*did you mean 'pytracik'"):
        make_peer("pytrac", chain, root, timeout=0.005, tolerance=1e-5)
    assert peer_names() == list(PEERS)


@pytest.mark.parametrize("name", sorted(PEERS))
def test_registry_names_solver_classes_importable_without_the_peer(name: str) -> None:
    module, _, cls = PEERS[name][0].partition(":")
    peer_cls = getattr(importlib.import_module(module), cls)  # the peer library is imported only when built
    assert issubclass(peer_cls, Solver) and peer_cls.name == name and peer_cls.summary


def test_path_urdf_keeps_only_the_chain() -> None:
    chain, root = planar()
    path = path_urdf(root, chain)
    assert [j.get("name") for j in path.findall("joint")] == ["j1", "j2", "tool_joint"]
    again = chain_from_xml(path, chain.base, chain.tip)
    q = np.array([0.3, -0.7])
    np.testing.assert_allclose(again.fk(q), chain.fk(q), atol=1e-15)


def test_path_urdf_of_a_chain_that_starts_below_the_root() -> None:
    full, root = arm("ur5")
    chain = chain_from_xml(root, "shoulder_link", "wrist_3_link")
    path = path_urdf(root, chain)
    assert [j.get("name") for j in path.findall("joint")] == full.joint_names[1:]
    assert next(lk.get("name") for lk in path.findall("link")) == "shoulder_link"
    assert path.find("link/visual") is None
    again = chain_from_xml(path, chain.base, chain.tip)
    q = chain.mid() + 0.1
    np.testing.assert_allclose(again.fk(q), chain.fk(q), atol=1e-15)


# ---- with the peer installed ----------------------------------------------------------------------


CLOSED_FORM = {"eaik", "ik-geo"}  # 6R at most: on a spherical-wrist arm instead of Panda
SOLVED = [(name, robot) for name in sorted(PEERS) for robot in ("ur5", "kinova" if name in CLOSED_FORM else "panda")]


@pytest.mark.parametrize(("name", "robot"), SOLVED)
def test_peer_solves_fk_targets_in_chain_order(name: str, robot: str) -> None:
    solver = peer(name, robot)
    chain = solver.chain
    rng = np.random.default_rng(3)
    q_true = chain.random(rng, 5)
    seeds = chain.clamp(q_true + rng.uniform(-0.05, 0.05, q_true.shape))
    solved = 0
    for q, seed in zip(q_true, seeds):
        target = chain.fk(q)
        result = solver.solve(target, seed)
        assert isinstance(result.q, np.ndarray) and result.q.shape == (chain.n,)
        if result.success:
            solved += 1
            np.testing.assert_allclose(chain.fk(result.q), target, atol=2e-5)  # our FK, our joint order
            assert np.abs(result.q - q).max() < 0.5  # near the configuration it came from, not a permutation
        else:
            assert result.reason
    assert solved >= 4


@pytest.mark.parametrize("name", sorted(PEERS))
def test_unreachable_target_is_a_failure_with_a_reason(name: str) -> None:
    solver = peer(name, "ur5", timeout=0.005)
    target = solver.chain.fk(solver.chain.mid())
    target[:3, 3] += 10.0  # 10 m away
    result = solver.solve(target, solver.chain.mid())
    assert not result.success and result.reason and result.q.shape == (solver.chain.n,)


def test_pytracik_claiming_a_wrong_answer_is_not_trusted() -> None:
    solver: Any = peer("pytracik", "ur5")
    wrong = solver.chain.mid()
    solver._ik = lambda *args: np.concatenate([[1.0], wrong])  # rc 1: "found"
    result = solver.solve(solver.chain.fk(wrong + 0.3), wrong)
    assert not result.success and "FK check rejects" in result.reason


def test_rtb_claiming_a_wrong_answer_is_not_trusted() -> None:
    solver: Any = peer("rtb-lm", "ur5")
    wrong = solver.chain.mid()
    solver._ets = SimpleNamespace(
        ik_LM=lambda *a, **k: SimpleNamespace(q=wrong, success=True, iterations=1, searches=1)
    )
    result = solver.solve(solver.chain.fk(wrong + 0.3), wrong)
    assert not result.success and "FK check rejects" in result.reason


def test_peer_rejects_a_chain_it_reads_differently() -> None:
    pytest.importorskip("pytracik")
    chain, root = arm("ur5")
    shifted = etree.fromstring(etree.tostring(root))
    origin = shifted.find("joint[@name='elbow_joint']/origin")
    origin.set("xyz", "0 -0.2 0.425")  # what the peer reads (from the URDF) is no longer our chain
    with pytest.raises(ArmtoolError, match="reads world → tool0 differently"):
        make_peer("pytracik", chain, shifted, timeout=0.005, tolerance=1e-5)


# ---------------------------------------------------------------- native stderr


def test_native_stderr_is_captured_and_fd_2_restored(capfd: pytest.CaptureFixture[str]) -> None:
    """What native code writes on fd 2 inside the block lands in the capture, not on stderr; fd 2
    is stderr again after the block."""
    import os

    from armtool.ik.peers import native_stderr_captured

    with native_stderr_captured() as captured:
        os.write(2, b"thread '<unnamed>' panicked at src/lib.rs:1:2:\n")
        assert captured.text == ""  # filled in when the block ends
    os.write(2, b"after\n")
    assert captured.text == "thread '<unnamed>' panicked at src/lib.rs:1:2:\n"
    assert capfd.readouterr().err == "after\n"


def test_python_stderr_on_fd_2_keeps_writing_to_stderr(
    capfd: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A sys.stderr that writes on fd 2 (the rich console's, in a real run) is not captured: it is
    swapped for a stream on the original stderr for the block, and put back after."""
    import os
    import sys

    from armtool.ik.peers import native_stderr_captured

    on_fd_2 = open(2, "w", encoding="utf-8", closefd=False)  # closed below
    monkeypatch.setattr(sys, "stderr", on_fd_2)
    try:
        with native_stderr_captured() as captured:
            assert sys.stderr is not on_fd_2
            print("progress frame", file=sys.stderr)
            os.write(2, b"native\n")
        assert sys.stderr is on_fd_2
    finally:
        on_fd_2.close()
    assert captured.text == "native\n"
    assert capfd.readouterr().err == "progress frame\n"


def test_without_fd_2_the_block_runs_as_it_is() -> None:
    import os

    from armtool.ik.peers import native_stderr_captured

    saved = os.dup(2)
    os.close(2)
    try:
        ran = False
        with native_stderr_captured() as captured:
            ran = True
        with pytest.raises(OSError):
            os.fstat(2)  # still closed: nothing was put in its place
    finally:
        os.dup2(saved, 2)
        os.close(saved)
    assert ran and captured.text == ""


def test_ik_geo_says_it_prints_natively() -> None:
    from armtool.ik.peers.ik_geo_peer import IkGeo

    assert IkGeo.prints_natively and not Solver.prints_natively
