"""Suite-wide settings. In CI (CI=true) hypothesis draws the same examples on every run
(derandomize): a CI run checks the code, it does not hunt for new inputs; hunting is what a local
run does, with fresh random examples each time."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
    settings.load_profile("ci")


# ---- the tree is left as it was ----------------------------------------------------------------
# A test writes only inside its temporary directory: files it leaves in the checkout (a stray
# ps.yaml at the root, once) would end up committed. `git status` before and after the session
# names any file that appeared or changed, and the run fails.

_ROOT = Path(__file__).resolve().parents[1]
_BEFORE: set[str] | None = None


def _tree_state() -> set[str] | None:
    """`git status --porcelain` lines of the checkout (untracked files listed one by one), or None
    outside a git checkout."""
    try:
        out = subprocess.run(
            ["git", "-C", str(_ROOT), "status", "--porcelain", "--untracked-files=all"],
            capture_output=True,
            text=True,
            timeout=60,
        )
    except (OSError, subprocess.TimeoutExpired):
        return None
    return set(out.stdout.splitlines()) if out.returncode == 0 else None


def pytest_sessionstart(session: pytest.Session) -> None:
    global _BEFORE
    _BEFORE = _tree_state()


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    if _BEFORE is None or getattr(session.config, "workerinput", None) is not None:
        return
    after = _tree_state()
    if after is None:
        return
    new = sorted(after - _BEFORE)
    if new:
        sys.stderr.write(
            "\nerror: the tests changed the checkout (a test must write in its tmp_path only):\n  "
            + "\n  ".join(new)
            + "\n"
        )
        session.exitstatus = pytest.ExitCode.TESTS_FAILED
