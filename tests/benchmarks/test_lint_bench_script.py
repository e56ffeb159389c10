"""benchmarks/lint_bench.py's measuring pieces: CPU time of the child processes beside the wall
clock, and which kind of armtool install is being measured."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from typing import Any

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "lint_bench.py"


def load_script() -> Any:
    spec = importlib.util.spec_from_file_location("lint_bench_script", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up by name
    spec.loader.exec_module(module)
    return module


def test_a_loop_reports_the_cpu_its_children_used_beside_the_wall_clock() -> None:
    bench = load_script()
    busy = [sys.executable, "-c", "sum(i * i for i in range(3_000_000))"]
    idle = [sys.executable, "-c", "import time; time.sleep(0.3)"]
    wall_busy, cpu_busy = bench.run_loop([busy], bench.child_env())
    wall_idle, cpu_idle = bench.run_loop([idle], bench.child_env())
    assert cpu_busy > 0.05 and wall_busy >= cpu_busy * 0.5
    assert wall_idle >= 0.3 and cpu_idle < wall_idle - 0.2  # sleeping is waiting, not work


def test_the_install_kind_is_read_from_the_distribution() -> None:
    bench = load_script()
    import armtool

    # An editable install imports armtool from this checkout; a regular one from site-packages.
    from_checkout = Path(armtool.__file__).resolve().is_relative_to(SCRIPT.parents[1])
    assert bench.install_kind(sys.executable) == ("editable" if from_checkout else "regular")
