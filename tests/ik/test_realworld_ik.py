"""The ik-bench cases of the real-world corpus (../shared/realworld, issue 10): the chain a MoveIt group
or the default choice gives on real packages (joints, base, tip), whether the closed form applies, and
the exit code, as the corpus's own score.py judges them (its matching is imported, not copied). Skipped
in a user's clone, where the corpus is absent. Cases run in-process with fewer targets than the
corpus asks for: what is scored is the chain and the solvers' applicability, not their success rate."""

from __future__ import annotations

from typing import Any

import pytest
from typer.testing import CliRunner

from armtool.errors import ArmtoolError
from tests import realworld

if not realworld.PRESENT:
    pytest.skip("the real-world corpus (../shared/realworld) is not here", allow_module_level=True)
pytest.importorskip("pinocchio")
CORPUS = realworld.CORPUS
SCORE = realworld.score_module()
CASES = realworld.cases("ik-bench")


def _fewer_samples(argv: list[str], samples: str = "10") -> list[str]:
    out = list(argv)
    if "--samples" in out:
        out[out.index("--samples") + 1] = samples
    else:
        out += ["--samples", samples]
    return out + ["--no-batch"]


@pytest.mark.parametrize("case", CASES, ids=[c["id"] for c in CASES])
def test_realworld_ik_case(case: dict[str, Any], monkeypatch: pytest.MonkeyPatch) -> None:
    from armtool.cli import app

    for var in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH", "CMAKE_PREFIX_PATH", "GITHUB_ACTIONS"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.chdir(CORPUS)
    argv = _fewer_samples(SCORE.build_cmd([], case, str(CORPUS)))
    result = CliRunner().invoke(app, argv)
    err, exit_code = result.stderr, result.exit_code
    if isinstance(result.exception, ArmtoolError):  # what armtool.cli.main does with it: exit 2, said on stderr
        err, exit_code = err + f"error: {result.exception}\n", 2
    elif result.exception is not None and not isinstance(result.exception, SystemExit):
        err += f"\nTraceback (most recent call last): {type(result.exception).__name__}: {result.exception}"
    res: dict[str, Any] = {"crash": None, "ik_mismatches": []}
    SCORE.score_ik(case, exit_code, result.stdout, err, res)
    assert res["crash"] is None, res["crash"]
    assert res["ik_mismatches"] == [], res["ik_mismatches"]


def test_the_corpus_has_ik_cases() -> None:
    assert len(CASES) >= 10
