"""ik-bench results as a rich table (humans, stdout; its notes on stderr), JSON (scripts, `schema_version`)
or CSV (spreadsheets)."""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import asdict

from armtool.ik.bench import TIMING, BenchConfig, NotApplicable, SolverReport
from armtool.model.chain import Chain

# 2: times exclude armtool's FK check of the answers (TIMING); failure_reasons per solver.
# 3: closed-form rows: distinct_solutions (verified, distinct, per target) replaces mean_solutions;
#    missing_solutions and targets_missing_solutions against the other closed-form rows; method.
SCHEMA_VERSION = 3
Row = SolverReport | NotApplicable


def _us(value: float) -> str:
    if math.isnan(value):
        return "-"
    return f"{value:,.0f}" if value >= 100 else f"{value:.1f}"


def _sci(value: float) -> str:
    return "-" if math.isnan(value) else f"{value:.1e}"


def _title(chain: Chain, config: BenchConfig) -> str:
    goal = ", position only (position_only_ik)" if config.position_only else ""
    return (
        f"{chain.name} {chain.base} → {chain.tip} ({chain.n} joints), {config.samples} targets{goal}, "
        f"seed {config.seed_mode.value}, timeout {config.timeout * 1e3:g} ms"
    )


def main_failure(r: SolverReport) -> str:
    """The most common reason of a row's failures, with its count: a row at 0 % says why."""
    if not r.failure_reasons:
        return "-"
    reason, count = next(iter(r.failure_reasons.items()))
    return f"{reason} ({count} of {r.failures})"


def missing_cell(r: SolverReport) -> str:
    """A closed-form row's solutions missing against the others: "count (targets)", "-" when not compared."""
    if r.missing_solutions is None:
        return "-"
    return str(r.missing_solutions) + (f" ({r.targets_missing_solutions} targets)" if r.missing_solutions else "")


def _caption(reports: list[Row]) -> str:
    methods = [
        f"{r.solver}: {r.method}" for r in reports if isinstance(r, SolverReport) and r.method and r.mode == "single"
    ]
    lines = [f"Timing: {TIMING}."]
    if any(isinstance(r, SolverReport) and r.distinct_solutions is not None for r in reports):
        lines.append(
            "solutions: distinct solutions per target that pass the check (closed-form rows; a row is solved when any "
            "does); missing: the other closed-form solvers' solutions (their union) this row lacks."
        )
    if methods:
        lines.append("Methods: " + "; ".join(methods) + ".")
    return "\n".join(lines)


def render_table(chain: Chain, config: BenchConfig, reports: list[Row]) -> None:
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    table = Table(title=escape(_title(chain, config)), caption=escape(_caption(reports)), caption_justify="left")
    for col in (
        "solver",
        "success %",
        "failures (stalled)",
        "median µs",
        "p95 µs",
        "max µs",
        "solves/s",
        "max pos err m",
        "max rot err rad",
        "median seed dist",
        "repeatable %",
        "solutions",
        "missing",
        "cond@fail",
        "main failure reason",
    ):
        table.add_column(col, justify="left" if col in ("solver", "main failure reason") else "right")
    for r in reports:
        if isinstance(r, NotApplicable):
            table.add_row(escape(r.solver), "n/a", *["-"] * 12, escape(r.reason))
            continue
        table.add_row(
            escape(r.solver + (" (batch)" if r.mode == "batch" else "")),
            f"{100 * r.success_rate:.1f}",
            str(r.failures) + ("" if r.stalled_failures is None else f" ({r.stalled_failures})"),
            _us(r.wall_us["median"]),
            _us(r.wall_us["p95"]) if r.mode == "single" else "-",
            _us(r.wall_us["max"]) if r.mode == "single" else "-",
            f"{r.solves_per_s:,.0f}",
            _sci(r.position_error_m["max"]),
            "-" if config.position_only else _sci(r.orientation_error_rad["max"]),
            "-" if math.isnan(r.seed_distance["median"]) else f"{r.seed_distance['median']:.2f}",
            "-" if r.repeatability is None else f"{100 * r.repeatability:.0f}",
            "-" if r.distinct_solutions is None else f"{r.distinct_solutions:.2f}",
            missing_cell(r),
            "-" if r.failures == 0 else _sci(r.failed_condition_numbers["median"]),
            escape(main_failure(r)),
        )
    import sys

    Console(highlight=False, width=None if sys.stdout.isatty() else 240).print(table)
    from armtool.console import stderr

    err = stderr()
    for r in reports:
        if isinstance(r, SolverReport) and r.claimed_but_wrong:
            err.print(
                f"[yellow]{escape(r.solver)}: {r.claimed_but_wrong} answers claimed success but failed our FK check[/yellow]"
            )
    if any(isinstance(r, SolverReport) and r.stalled_failures for r in reports):
        err.print(
            "failures (stalled): failed solves that ran past the timeout with less than half of it on the CPU (a busy machine)"
        )


def _row_json(r: Row) -> dict[str, object]:
    if isinstance(r, NotApplicable):
        return {"solver": r.solver, "mode": r.mode, "applicable": False, "reason": r.reason, "success_rate": None}
    hidden = ("wall_times_us", "solved", "verified")
    return {"applicable": True, **{k: v for k, v in asdict(r).items() if k not in hidden}}


def render_json(chain: Chain, config: BenchConfig, reports: list[Row]) -> str:
    doc = {
        "schema_version": SCHEMA_VERSION,
        "robot": chain.name,
        "base": chain.base,
        "tip": chain.tip,
        "joints": chain.joint_names,
        "locked": {name: value for _, name, value in chain.locks},  # ik-bench --lock: held out of `joints`
        "timing": TIMING,
        "config": {
            "samples": config.samples,
            "rng_seed": config.rng_seed,
            "seed_mode": config.seed_mode.value,
            "timeout_s": config.timeout,
            "tolerance": config.tolerance,
            "position_only": config.position_only,
        },
        "solvers": [_row_json(r) for r in reports],
    }
    return json.dumps(_clean(doc), indent=2, allow_nan=False)


def _clean(value: object) -> object:
    """NaN/inf → null: JSON has no NaN."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_clean(v) for v in value]
    return value


def render_csv(reports: list[Row]) -> str:
    buf = io.StringIO()
    writer = csv.writer(buf)
    writer.writerow(
        [
            "solver",
            "mode",
            "samples",
            "success_rate",
            "median_us",
            "p95_us",
            "max_us",
            "cpu_median_us",
            "solves_per_s",
            "max_position_error_m",
            "max_orientation_error_rad",
            "median_seed_distance",
            "repeatability",
            "distinct_solutions",
            "missing_solutions",
            "targets_missing_solutions",
            "failures",
            "claimed_but_wrong",
            "stalled_failures",
            "main_failure_reason",
            "method",
            "not_applicable",
        ]
    )
    for r in reports:
        if isinstance(r, NotApplicable):
            writer.writerow([r.solver, r.mode] + [""] * 19 + [r.reason])
            continue
        writer.writerow(
            [
                r.solver,
                r.mode,
                r.samples,
                f"{r.success_rate:.4f}",
                f"{r.wall_us['median']:.1f}",
                f"{r.wall_us['p95']:.1f}",
                f"{r.wall_us['max']:.1f}",
                f"{r.cpu_us['median']:.1f}",
                f"{r.solves_per_s:.0f}",
                r.position_error_m["max"],
                r.orientation_error_rad["max"],
                r.seed_distance["median"],
                "" if r.repeatability is None else r.repeatability,
                "" if r.distinct_solutions is None else r.distinct_solutions,
                "" if r.missing_solutions is None else r.missing_solutions,
                "" if r.targets_missing_solutions is None else r.targets_missing_solutions,
                r.failures,
                r.claimed_but_wrong,
                "" if r.stalled_failures is None else r.stalled_failures,
                main_failure(r) if r.failures else "",
                r.method,
                "",
            ]
        )
    return buf.getvalue()
