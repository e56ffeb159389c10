"""The ecosystem check (tools/ecosystem.py): every finding armtool gives on the real-world corpus
equals the committed baseline (tests/ecosystem/baseline.json). A rule change that adds or removes
findings fails here until the baseline is rewritten (`make ecosystem-update`) in the same commit,
whose message reviews each change. Skipped where the corpus is absent."""

from __future__ import annotations

from typing import Any

import pytest

from tests import realworld

eco = realworld.ecosystem()


def _snap(*rows: list[Any], exit_code: int = 1) -> dict[str, Any]:
    return {"schema": 1, "cases": {"c": {"exit": exit_code, "findings": [list(r) for r in rows]}}}


def test_compare_names_added_and_removed_findings_per_rule() -> None:
    old = _snap(["a.urdf", 3, "U204", "warning", "effort 0"], ["a.urdf", 9, "U101", "error", "x"])
    new = _snap(["a.urdf", 3, "U204", "warning", "effort 0"], ["b.srdf", 2, "S111", "warning", "y"])
    lines = eco.compare(old, new)
    assert lines == ["S111: +1 -0", "  + c: b.srdf:2 warning y", "U101: +0 -1", "  - c: a.urdf:9 error x"]
    assert eco.compare(old, old) == []


def test_compare_names_a_changed_exit_code() -> None:
    assert eco.compare(_snap(exit_code=0), _snap(exit_code=2)) == ["case c: exit 0 -> 2"]


def test_dump_is_json_with_one_finding_per_line() -> None:
    import json

    snap = _snap(["a.urdf", 3, "U204", "warning", 'effort 0 "q"'], ["a.urdf", 4, "U204", "warning", "é"])
    text = eco.dump(snap)
    assert json.loads(text) == snap
    assert text.count("\n") == 9


@pytest.mark.skipif(not realworld.PRESENT, reason="the real-world corpus (../shared/realworld) is not here")
def test_the_findings_on_the_corpus_equal_the_baseline() -> None:
    score = realworld.score_module()
    cases = realworld.cases("lint", "lint-urdf")
    current = eco.snapshot(((c, realworld.lint_outcome(c["id"])) for c in cases), score, realworld.CORPUS)
    text = eco.dump(current)
    assert str(realworld.CORPUS) not in text and str(realworld.ROOT) not in text, "the snapshot names local paths"
    diff = eco.compare(eco.load_baseline(), current)
    assert diff == [], "findings changed on the corpus (review them, then `make ecosystem-update`):\n" + "\n".join(
        diff[:200]
    )
