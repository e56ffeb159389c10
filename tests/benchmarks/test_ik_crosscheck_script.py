"""benchmarks/ik_crosscheck.py times each solver's raw call as armtool's benchmark does, with the
peers' settings taken from armtool's adapters, and lm's own input check inside its timed call."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.model.chain import chain_from_xml
from armtool.model.load import load_robot_xml
from tests.benchmarks import load_script
from tests.ik.robots import ARMS, erd


def ur5() -> tuple[Any, Any]:
    relative, base, tip = ARMS["ur5"]
    root = load_robot_xml(erd(relative))
    return root, chain_from_xml(root, base, tip)


def test_lm_is_timed_with_its_input_check() -> None:
    # lm's prepare only converts; the check of its inputs is its own work, inside the timed call.
    script = load_script("ik_crosscheck")
    root, chain = ur5()
    targets = chain.fk_batch(chain.random(np.random.default_rng(1), 2))
    targets[1, 0, 3] = np.nan
    calls = script.callers(root, chain, targets, chain.mid())  # prepares every target: no error yet
    q = script.answer_q("lm", chain, calls["lm"](0))
    assert q.shape == (chain.n,) and np.allclose(chain.fk(q), targets[0], atol=1e-4)
    with pytest.raises(ArmtoolError, match="finite"):
        calls["lm"](1)


def test_peers_run_with_their_adapters_settings(monkeypatch: pytest.MonkeyPatch) -> None:
    # The cross-check calls rtb's ik_LM and pytracik directly, but with the adapters' settings and
    # input form: change an adapter's and the cross-check follows.
    rtb = pytest.importorskip("roboticstoolbox")
    pytest.importorskip("pytracik")
    from armtool.ik.peers import make_peer
    from armtool.ik.peers.pytracik_peer import PyTracIK
    from armtool.ik.peers.rtb_lm import RtbLM

    script = load_script("ik_crosscheck")
    root, chain = ur5()
    targets = chain.fk_batch(chain.random(np.random.default_rng(2), 2))
    seed = chain.mid()
    monkeypatch.setattr(RtbLM, "ILIMIT", 7)
    monkeypatch.setattr(RtbLM, "SLIMIT", 3)
    seen: list[dict[str, Any]] = []
    real = rtb.ETS.ik_LM

    def ik_LM(self: Any, *args: Any, **kwargs: Any) -> Any:
        seen.append({k: v for k, v in kwargs.items() if k != "q0"})
        return real(self, *args, **kwargs)

    monkeypatch.setattr(rtb.ETS, "ik_LM", ik_LM)
    prepared: list[Any] = []
    real_prepare = PyTracIK.prepare

    def prepare(self: Any, target: Any, seed: Any) -> Any:
        prepared.append(real_prepare(self, target, seed))
        return prepared[-1]

    monkeypatch.setattr(PyTracIK, "prepare", prepare)
    calls = script.callers(root, chain, targets, seed)
    calls["rtb-lm"](0)
    peer = make_peer("rtb-lm", chain, root, timeout=script.TIMEOUT, tolerance=script.TOLERANCE)
    assert isinstance(peer, RtbLM)
    peer.call(peer.prepare(targets[0], seed))
    assert len(seen) == 2 and seen[0] == seen[1] and seen[0]["ilimit"] == 7 and seen[0]["slimit"] == 3
    assert len(prepared) == 2  # pytracik's inputs are its adapter's, one per target
    raw = calls["pytracik"](0)
    assert np.array_equal(script.answer_q("pytracik", chain, raw), np.asarray(raw, dtype=float)[1:])
