"""The real-world corpus (../shared/realworld beside the checkout, issue 10): where it is, its
score.py (imported, so the suite judges cases exactly as the corpus's own scorer does), its cases,
and each lint case's run, made once per test session: the corpus cases (tests/lint/test_realworld.py)
and the ecosystem check (tests/test_ecosystem.py) judge the same runs. Absent in a user's clone:
the tests that use it skip."""

from __future__ import annotations

import functools
import importlib.util
from pathlib import Path
from types import ModuleType
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
CORPUS = (ROOT / ".." / "shared" / "realworld").resolve()
PRESENT = (CORPUS / "cases.yaml").is_file() and (CORPUS / "score.py").is_file()


def _load(name: str, path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@functools.cache
def score_module() -> ModuleType:
    return _load("realworld_score", CORPUS / "score.py")


@functools.cache
def ecosystem() -> ModuleType:
    """tools/ecosystem.py: how a lint case is run and its findings stored."""
    return _load("ecosystem", ROOT / "tools" / "ecosystem.py")


def cases(*commands: str) -> list[dict[str, Any]]:
    """The corpus cases whose command is one of `commands`."""
    import yaml

    every = yaml.safe_load((CORPUS / "cases.yaml").read_text(encoding="utf-8"))
    return [c for c in every if str(c["cmd"][0]) in commands]


@functools.cache
def _lint_cases() -> dict[str, dict[str, Any]]:
    return {c["id"]: c for c in cases("lint", "lint-urdf")}


@functools.cache
def lint_outcome(case_id: str) -> Any:
    """The lint case's run (ecosystem.Outcome: exit code, stdout, stderr), made once per session."""
    return ecosystem().run_case(_lint_cases()[case_id], score_module(), CORPUS)
