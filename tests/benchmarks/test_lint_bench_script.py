"""benchmarks/lint_bench.py's measuring pieces: CPU time of the child processes beside the wall
clock, and which kind of armtool install is being measured."""

from __future__ import annotations

import sys
from pathlib import Path

from tests.benchmarks import BENCHMARKS, load_script


def test_a_loop_reports_the_cpu_its_children_used_beside_the_wall_clock() -> None:
    bench = load_script("lint_bench")
    busy = [sys.executable, "-c", "sum(i * i for i in range(3_000_000))"]
    idle = [sys.executable, "-c", "import time; time.sleep(0.3)"]
    wall_busy, cpu_busy = bench.run_loop([busy], bench.child_env())
    wall_idle, cpu_idle = bench.run_loop([idle], bench.child_env())
    assert cpu_busy > 0.05 and wall_busy >= cpu_busy * 0.5
    assert wall_idle >= 0.3 and cpu_idle < wall_idle - 0.2  # sleeping is waiting, not work


def test_the_install_kind_is_read_from_the_distribution() -> None:
    bench = load_script("lint_bench")
    import armtool

    # An editable install imports armtool from this checkout; a regular one from site-packages.
    from_checkout = Path(armtool.__file__).resolve().is_relative_to(BENCHMARKS.parent)
    assert bench.install_kind(sys.executable) == ("editable" if from_checkout else "regular")
