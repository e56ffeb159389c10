"""The lint cases of the real-world corpus (../shared/realworld, issue 10): real ROS packages and what a
correct tool must report on them. Every case must have 0 false alarms, 0 misses and no crash, as the
corpus's own score.py counts them (its matching is imported, not copied). Skipped in a user's clone,
where the corpus is absent. The cases run in-process, once per session (tests/realworld.py): the
ecosystem check compares the same runs with its baseline."""

from __future__ import annotations

import os
from typing import Any

import pytest

from tests import realworld

if not realworld.PRESENT:
    pytest.skip("the real-world corpus (../shared/realworld) is not here", allow_module_level=True)
CORPUS = realworld.CORPUS
SCORE = realworld.score_module()
CASES = realworld.cases("lint", "lint-urdf")


@pytest.mark.parametrize("case", CASES, ids=[c["id"] for c in CASES])
def test_realworld_lint_case(case: dict[str, Any]) -> None:
    outcome = realworld.lint_outcome(case["id"])
    res: dict[str, Any] = {"crash": None, "false_alarms": [], "misses": []}
    SCORE.score_lint(case, outcome.exit_code, outcome.stdout, outcome.stderr, str(CORPUS), res)
    assert res["crash"] is None, res["crash"]
    assert res["false_alarms"] == [], "false alarms"
    assert res["misses"] == [], "missed defects"


def test_the_corpus_has_lint_cases() -> None:
    assert len(CASES) >= 50 and os.sep not in CASES[0]["id"].replace("/", "")
