"""The lint cases of the real-world corpus (../shared/realworld, issue 10): real ROS packages and what a
correct tool must report on them. Every case must have 0 false alarms, 0 misses and no crash, as the
corpus's own score.py counts them (its matching is imported, not copied). Skipped in a user's clone,
where the corpus is absent. The cases run in-process (one `armtool lint` start-up saved per case)."""

from __future__ import annotations

import os
from typing import Any

import pytest
from typer.testing import CliRunner

from tests import realworld

if not realworld.PRESENT:
    pytest.skip("the real-world corpus (../shared/realworld) is not here", allow_module_level=True)
CORPUS = realworld.CORPUS
SCORE = realworld.score_module()
CASES = realworld.cases("lint", "lint-urdf")


@pytest.mark.parametrize("case", CASES, ids=[c["id"] for c in CASES])
def test_realworld_lint_case(case: dict[str, Any], monkeypatch: pytest.MonkeyPatch) -> None:
    from armtool.cli import app

    for var in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH", "CMAKE_PREFIX_PATH", "GITHUB_ACTIONS"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.chdir(CORPUS)
    argv = SCORE.build_cmd([], case, str(CORPUS))
    result = CliRunner().invoke(app, argv)
    err = result.stderr
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        err += f"\nTraceback (most recent call last): {type(result.exception).__name__}: {result.exception}"
    res: dict[str, Any] = {"crash": None, "false_alarms": [], "misses": []}
    SCORE.score_lint(case, result.exit_code, result.stdout, err, str(CORPUS), res)
    assert res["crash"] is None, res["crash"]
    assert res["false_alarms"] == [], "false alarms"
    assert res["misses"] == [], "missed defects"


def test_the_corpus_has_lint_cases() -> None:
    assert len(CASES) >= 50 and os.sep not in CASES[0]["id"].replace("/", "")
