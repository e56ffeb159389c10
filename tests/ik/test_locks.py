"""`--lock JOINT=VALUE` (armtool.ik.locks): parsing, the locked chain as a peer's URDF reads it, and
`ik-bench --lock` on Panda: the analytic row (and EAIK's, with its own fixed_axes) solved."""

from __future__ import annotations

import importlib.util
import json

import numpy as np
import pytest
from typer.testing import CliRunner

from armtool.cli import app
from armtool.errors import ArmtoolError
from armtool.ik.locks import full_joint_names, locked_urdf, parse_locks
from armtool.model.chain import chain_from_xml
from armtool.model.load import load_robot_xml
from tests.ik.robots import erd


def test_parse_locks_takes_repeats_and_comma_lists() -> None:
    assert parse_locks(["a=0.5,b=-1", "c = 2"]) == {"a": 0.5, "b": -1.0, "c": 2.0}
    assert parse_locks(None) == {}
    for bad, what in (["a"], "not JOINT=VALUE"), (["a=nan"], "finite"), (["a=1", "a=2"], "twice"), ([","], "no joint"):
        with pytest.raises(ArmtoolError, match=what):
            parse_locks(bad)


def test_locked_urdf_is_the_locked_chain() -> None:
    root = load_robot_xml(erd("panda_description/urdf/panda.urdf"))
    locked = chain_from_xml(root, "panda_link0", "panda_hand").locked({"panda_joint4": -1.2})
    assert full_joint_names(locked) == [f"panda_joint{i}" for i in range(1, 8)]
    read = chain_from_xml(locked_urdf(root, locked), "panda_link0", "panda_hand")
    assert read.joint_names == locked.joint_names
    for q in np.random.default_rng(0).uniform(locked.lower, locked.upper, (5, 6)):
        np.testing.assert_allclose(read.fk(q), locked.fk(q), atol=1e-12)


def _bench(*extra: str) -> dict[str, dict[str, object]]:
    urdf = erd("panda_description/urdf/panda.urdf")
    args = ["ik-bench", str(urdf), "--base", "panda_link0", "--tip", "panda_hand", "--samples", "30", "--no-batch"]
    result = CliRunner().invoke(app, [*args, "--format", "json", *extra])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    locked = {"panda_joint7": 0.785} if "--lock" in extra else {}
    assert doc["locked"] == locked and len(doc["joints"]) == 7 - len(locked)
    return {r["solver"]: r for r in doc["solvers"]}


def test_ik_bench_lock_solves_panda_in_closed_form() -> None:
    rows = _bench("--solvers", "analytic,lm", "--lock", "panda_joint7=0.785")
    assert rows["analytic"]["applicable"] and rows["analytic"]["success_rate"] == 1.0
    assert rows["lm"]["applicable"]
    unlocked = _bench("--solvers", "analytic")
    assert unlocked["analytic"]["applicable"] is False  # 7 joints: no closed form without the lock


@pytest.mark.skipif(importlib.util.find_spec("eaik") is None, reason="eaik not installed")
def test_ik_bench_lock_gives_eaik_its_fixed_axes() -> None:
    rows = _bench("--solvers", "analytic", "--peers", "eaik", "--lock", "panda_joint7=0.785")
    assert rows["eaik"]["applicable"] and rows["eaik"]["success_rate"] == 1.0
    assert rows["eaik"]["missing_solutions"] == 0 and rows["analytic"]["missing_solutions"] == 0
    unlocked = _bench("--solvers", "lm", "--peers", "eaik")
    assert unlocked["eaik"]["applicable"] is False and "--lock" in str(unlocked["eaik"]["reason"])


def test_ik_bench_lock_of_an_unknown_joint_is_an_error() -> None:
    urdf = erd("panda_description/urdf/panda.urdf")
    result = CliRunner().invoke(app, ["ik-bench", str(urdf), "--samples", "5", "--lock", "panda_joint9=0"])
    assert isinstance(result.exception, ArmtoolError) and "did you mean" in str(result.exception)
