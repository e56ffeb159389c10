"""The figure of `ik-bench --plot FILE` (PNG, SVG or PDF): per solver, the fraction of targets
solved within a time (a CDF of the timed solve calls on a log axis; failures never count as solved,
so a curve ends at its success rate), and each row's success rate as a bar.

Drawn with matplotlib in armtool's one style (`armtool.plotting`), as `calibrate fit --plot` and
`traj plot` are.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from armtool import plotting
from armtool.ik.bench import SolverReport

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def bench_figure(reports: list[SolverReport], title: str) -> Figure:
    """The figure of one run's rows; `title` says which chain and how many targets."""
    singles = [r for r in reports if r.mode == "single" and r.wall_times_us]
    with plotting.style():
        fig = plotting.figure(12.0, max(4.8, 1.4 + 0.3 * len(reports)))
        cdf, bars = fig.subplots(1, 2, width_ratios=[1.7, 1.0])
        colors = {name: f"C{k % 10}" for k, name in enumerate(dict.fromkeys(r.solver for r in reports))}
        for r in singles:
            times = np.asarray(r.wall_times_us, dtype=np.float64)
            solved = np.sort(times[np.asarray(r.solved, dtype=bool)]) if r.solved else np.zeros(0)
            if solved.size == 0:
                continue
            fraction = np.arange(1, solved.size + 1) / times.size
            cdf.step(solved, fraction, where="post", color=colors[r.solver], label=r.solver)
        cdf.set_xscale("log")
        cdf.set_ylim(0, 1.02)
        cdf.set_title("solve time of the solved targets (one timed call each)")
        cdf.set_xlabel("solve time (µs, log)")
        cdf.set_ylabel("fraction of targets solved within")
        if singles:
            cdf.legend(loc="upper left")
        labels = [r.solver + (" (batch)" if r.mode == "batch" else "") for r in reports]
        y = np.arange(len(reports))
        rates = [100.0 * r.success_rate for r in reports]
        drawn = bars.barh(y, rates, color=[colors[r.solver] for r in reports], edgecolor="white")
        for patch, r in zip(drawn, reports):
            patch.set_hatch("//" if r.mode == "batch" else "")
        for k, rate in enumerate(rates):
            bars.annotate(f"{rate:.1f} %", (rate, k), xytext=(3, 0), textcoords="offset points", va="center")
        bars.set_yticks(y, labels)
        bars.set_ylim(len(reports) - 0.5, -0.5)
        bars.set_xlim(0, 118)
        bars.set_xticks([0, 25, 50, 75, 100])
        bars.grid(axis="y", visible=False)
        bars.set_title("success (checked by armtool's FK)")
        bars.set_xlabel("targets solved (%)")
        fig.suptitle(title, horizontalalignment="left", x=0.01)
    return fig


def write_plot(path: Path, reports: list[SolverReport], title: str) -> None:
    plotting.save(bench_figure(reports, title), path)
