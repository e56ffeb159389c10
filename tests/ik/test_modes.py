"""ik-bench's enums live in one numpy-free module that the core and the CLI share."""

from __future__ import annotations

import subprocess
import sys

from armtool.cli import ik_bench as cli
from armtool.ik import bench
from armtool.ik.modes import BenchFormat, SeedMode


def test_core_and_cli_use_the_same_enums() -> None:
    assert bench.SeedMode is SeedMode
    assert cli.SeedMode is SeedMode and cli.BenchFormat is BenchFormat
    assert [m.value for m in SeedMode] == ["mid", "random", "near"]


def test_modes_import_without_numpy() -> None:
    code = "import sys, armtool.ik.modes; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
