"""Many files are linted by forked workers (armtool.lint.engine._lint_forked): the findings, their
order and the errors must be those of a serial run."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from armtool.errors import ArmtoolError
from armtool.lint import engine
from armtool.lint.engine import LintOptions, lint_paths

from .helpers import LINK, revolute, robot

needs_fork = pytest.mark.skipif(not hasattr(os, "fork") or engine._cpus() < 2, reason="needs fork and 2 CPUs")


def _robots(tmp_path: Path, count: int) -> list[Path]:
    paths = []
    for i in range(count):
        # Every file has findings (velocity 0, rpy in degrees), some with a fix; sizes differ.
        extra = "".join(f'<link name="x{k}"/>' for k in range(i))
        joint = revolute("j1", "base", "l1", limit=f'lower="-1" upper="1" effort="{i}" velocity="0"')
        body = f'<link name="base"/>\n{LINK.format(name="l1")}\n{joint}\n<joint name="j2" type="fixed"><origin rpy="0 0 90"/><parent link="l1"/><child link="l2"/></joint>\n<link name="l2"/>{extra}'
        path = tmp_path / f"robot_{i:02d}.urdf"
        path.write_text(robot(body), encoding="utf-8")
        paths.append(path)
    return paths


@needs_fork
def test_forked_run_equals_serial_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    paths = _robots(tmp_path, 20)
    forked = lint_paths(paths, LintOptions())
    monkeypatch.setattr(engine, "PARALLEL_MIN_FILES", 10**6)
    serial = lint_paths(paths, LintOptions())
    assert len(forked.findings) > 40
    assert forked == serial  # every field, edits included, in the same order


@needs_fork
def test_forked_run_reports_the_first_failing_file(tmp_path: Path) -> None:
    paths = _robots(tmp_path, 18)
    for name in ("robot_05.urdf", "robot_11.urdf"):
        with open(tmp_path / name, "r+b") as fh:
            fh.truncate(engine.MAX_BYTES + 1)  # sparse: over the size limit without writing it
    with pytest.raises(ArmtoolError) as raised:
        lint_paths(paths, LintOptions())
    assert raised.value.where == str(tmp_path / "robot_05.urdf")
