"""Peer adapters: a missing peer is reported with its install command; present ones solve in chain order."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.ik.chain import chain_from_xml
from armtool.ik.peers import PEERS, make_peer, peer_names
from armtool.model.load import load_robot_xml
from tests.ik.robots import ARMS, erd


def ur5():  # type: ignore[no-untyped-def]
    root = load_robot_xml(erd(ARMS["ur5"][0]))
    return chain_from_xml(root), root


def test_missing_peer_names_the_install_command(monkeypatch: pytest.MonkeyPatch) -> None:
    chain, root = ur5()
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "pytracik" else real(name, *a))
    reason = make_peer("pytracik", chain, root, timeout=0.005, tolerance=1e-5)
    assert isinstance(reason, str) and "pip install" in reason and "armtool[peers]" in reason


def test_unknown_peer_lists_the_known_ones() -> None:
    chain, root = ur5()
    with pytest.raises(ArmtoolError, match="unknown peer 'pytrac'.*did you mean 'pytracik'"):
        make_peer("pytrac", chain, root, timeout=0.005, tolerance=1e-5)
    assert set(peer_names()) == set(PEERS)


@pytest.mark.parametrize("name", sorted(PEERS))
def test_installed_peer_solves_in_chain_order(name: str) -> None:
    pytest.importorskip(PEERS[name][1])
    chain, root = ur5()
    peer = make_peer(name, chain, root, timeout=0.05, tolerance=1e-5)
    assert not isinstance(peer, str)
    rng = np.random.default_rng(3)
    solved = 0
    for q in chain.random(rng, 5):
        result = peer.solve(chain.fk(q), np.clip(q + 0.1, chain.lower, chain.upper))
        solved += result.success
        assert result.q.shape == (chain.n,)
    assert solved >= 4
