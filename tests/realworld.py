"""The real-world corpus (../shared/realworld beside the checkout, issue 10): where it is, its
score.py (imported, so the suite judges cases exactly as the corpus's own scorer does) and its
cases. Absent in a user's clone: the tests that use it skip."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType
from typing import Any

CORPUS = (Path(__file__).resolve().parents[1] / ".." / "shared" / "realworld").resolve()
PRESENT = (CORPUS / "cases.yaml").is_file() and (CORPUS / "score.py").is_file()


def score_module() -> ModuleType:
    spec = importlib.util.spec_from_file_location("realworld_score", CORPUS / "score.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def cases(*commands: str) -> list[dict[str, Any]]:
    """The corpus cases whose command is one of `commands`."""
    import yaml

    every = yaml.safe_load((CORPUS / "cases.yaml").read_text(encoding="utf-8"))
    return [c for c in every if str(c["cmd"][0]) in commands]
