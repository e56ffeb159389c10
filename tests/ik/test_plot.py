"""`ik-bench --plot`'s figure, read from the matplotlib Figure: a solve-time CDF per single-call row
that ends at the row's success rate, and a success bar per row (batch rows hatched)."""

from __future__ import annotations

import numpy as np
from matplotlib.colors import to_rgba
from matplotlib.patches import Rectangle

from armtool.ik.bench import SolverReport
from armtool.ik.plot import bench_figure


def _report(solver: str, mode: str, times_us: list[float], solved: list[bool]) -> SolverReport:
    n = len(solved)
    nan = {"median": float("nan")}
    return SolverReport(
        solver=solver,
        mode=mode,
        samples=n,
        success_rate=sum(solved) / n,
        wall_us=nan,
        cpu_us=nan,
        solves_per_s=0.0,
        position_error_m=nan,
        orientation_error_rad=nan,
        seed_distance=nan,
        repeatability=None,
        distinct_solutions=None,
        failed_condition_numbers={},
        failures=n - sum(solved),
        claimed_but_wrong=0,
        failure_reasons={},
        wall_times_us=times_us if mode == "single" else [],
        solved=solved,
    )


def test_the_cdf_ends_at_the_success_rate_and_every_row_has_a_bar() -> None:
    reports = [
        _report("lm", "single", [12.0, 15.0, 40.0, 5000.0], [True, True, True, False]),
        _report("dls", "single", [300.0, 800.0, 900.0, 2000.0], [True, False, True, False]),
        _report("lm", "batch", [], [True, True, True, True]),
    ]
    fig = bench_figure(reports, "arm.urdf: base → tool, 4 targets, timeout 5 ms")
    assert fig.get_suptitle() == "arm.urdf: base → tool, 4 targets, timeout 5 ms"
    cdf, bars = fig.get_axes()
    assert cdf.get_xscale() == "log" and cdf.get_xlabel() == "solve time (µs, log)"
    assert cdf.get_ylabel() == "fraction of targets solved within"
    lines = {line.get_label(): line for line in cdf.get_lines()}
    assert set(lines) == {"lm", "dls"}  # the batch row has no per-target times
    assert np.allclose(lines["lm"].get_xdata(), [12.0, 15.0, 40.0])  # the failure is never "solved"
    assert np.asarray(lines["lm"].get_ydata())[-1] == 0.75 and np.asarray(lines["dls"].get_ydata())[-1] == 0.5
    assert [t.get_text() for t in bars.get_yticklabels()] == ["lm", "dls", "lm (batch)"]
    widths = [patch.get_width() for patch in bars.patches if isinstance(patch, Rectangle)]
    assert widths == [75.0, 50.0, 100.0]
    assert [patch.get_hatch() or "" for patch in bars.patches] == ["", "", "//"]
    assert [t.get_text() for t in bars.texts] == ["75.0 %", "50.0 %", "100.0 %"]
    # one colour per solver, in both panels: lm's curve, lm's bar and lm's batch bar
    lm = to_rgba(lines["lm"].get_color())
    assert bars.patches[0].get_facecolor() == lm == bars.patches[2].get_facecolor() != bars.patches[1].get_facecolor()
