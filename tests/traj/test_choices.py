"""The numpy-free choices stay in step with what they name."""

from __future__ import annotations

from armtool.ik.registry import SOLVERS
from armtool.traj.choices import PathSolver


def test_path_solvers_are_the_registered_solvers() -> None:
    assert [s.value for s in PathSolver] == ["auto", *SOLVERS]
