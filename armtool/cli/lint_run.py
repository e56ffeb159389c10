"""What `armtool lint` does once its arguments are read: lint, fix or diff, report, pick the exit
code. No Typer here: `armtool lint PATH...` with paths only, how pre-commit runs it on every
commit, comes straight here from armtool.cli.main (`run_plain`), and importing and building the
parser would be most of its start-up. The Typer command (armtool.cli.lint) reads options and calls
`run` with the same request.
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass, field
from pathlib import Path

from armtool.errors import ArmtoolError, ExitCode
from armtool.lint.finding import Severity
from armtool.output.registry import OutputFormat


@dataclass(frozen=True)
class LintRequest:
    """One `armtool lint` run, as its options give it; the defaults are the options' defaults."""

    paths: list[Path]
    output_format: OutputFormat | None = None
    fail_on: Severity | None = None
    exit_zero: bool = False
    fix: bool = False
    diff: bool = False
    select: str | None = None
    ignore: str | None = None
    xacro_args: dict[str, str] = field(default_factory=dict)
    package_paths: list[Path] = field(default_factory=list)
    moveit_config: Path | None = None
    urdf: Path | None = None
    srdf: Path | None = None
    config: Path | None = None


def run(request: LintRequest) -> int:
    """Lint as asked and return the exit code: 1 for findings at or above --fail-on (unless
    --exit-zero), else 0; input and configuration errors raise ArmtoolError (exit 2)."""
    from armtool.console import stderr, write_stdout
    from armtool.lint.config import load_config, parse_selectors
    from armtool.lint.engine import LintOptions, lint_paths
    from armtool.lint.locate import display_path
    from armtool.output.base import LintReport
    from armtool.output.registry import formatter

    r = request
    for given, flag in ((r.urdf, "--urdf"), (r.srdf, "--srdf"), (r.config, "--config")):
        if given is not None and not given.is_file():
            raise ArmtoolError(f"{flag}: no such file", str(given))
    selected = parse_selectors(r.select, "--select") if r.select is not None else None
    ignored = parse_selectors(r.ignore, "--ignore") if r.ignore is not None else []
    cfg = load_config(r.config)
    if selected is not None:
        cfg.select = selected
    cfg.ignore += ignored
    if r.fail_on is not None:
        cfg.fail_on = r.fail_on
    stdin = sys.stdin.buffer.read() if any(str(p) == "-" for p in r.paths) else None
    options = LintOptions(
        xacro_args=dict(r.xacro_args),
        package_paths=list(r.package_paths),
        urdf=r.urdf,
        srdf=r.srdf,
        config=cfg,
        stdin=stdin,
        moveit_config=r.moveit_config,
    )
    result = lint_paths(list(r.paths), options)
    findings = result.findings
    if r.diff or r.fix:
        from armtool.lint.fix import fixed_texts, safe_edits, unified_diff, write_atomic

        pairs = safe_edits(findings)

    if r.diff:
        changes = fixed_texts(pairs)
        for path, (old, new, _) in sorted(changes.items()):
            write_stdout(unified_diff(path, old, new, display_path(path)))
        count = sum(len(applied) for _, _, applied in changes.values())
        stderr().print(f"{count} fix(es) in {len(changes)} file(s) would be applied; nothing written.")
        return ExitCode.FINDINGS if changes and not r.exit_zero else ExitCode.OK

    if r.fix and pairs:
        changes = fixed_texts(pairs)
        fixed: set[int] = set()
        for path, (_old, new, applied) in changes.items():
            write_atomic(path, new)
            fixed.update(id(f) for f in applied)
        findings = [f for f in findings if id(f) not in fixed]
        stderr().print(f"Fixed {len(fixed)} problem(s) in {len(changes)} file(s).")

    fmt = r.output_format
    if fmt is None:
        fmt = OutputFormat.GITHUB if os.environ.get("GITHUB_ACTIONS") == "true" else OutputFormat.TEXT
    report = LintReport(
        findings,
        len(result.files),
        fixable=sum(1 for f in findings if f.edit is not None and not r.fix),
        checked=result.checked,
    )
    write_stdout(formatter(fmt).render(report, color=sys.stdout.isatty() and "NO_COLOR" not in os.environ))
    failing = any(f.severity.rank >= cfg.fail_on.rank for f in findings)
    return ExitCode.FINDINGS if failing and not r.exit_zero else ExitCode.OK


def run_plain(args: list[str]) -> int | None:
    """Run `armtool lint ARGS` if every argument is a path and return the exit code, else None
    (an option, --help or no path: the Typer command reads those).

    Ends as Typer's standalone mode would: 130 on Ctrl-C, 1 on a closed stdout pipe (`armtool lint
    ... | head`); ArmtoolError and other exceptions propagate to armtool.cli.main.
    """
    if not args or any(arg.startswith("-") for arg in args):
        return None
    try:
        return run(LintRequest([Path(arg) for arg in args]))
    except KeyboardInterrupt:
        return 130
    except OSError as exc:
        import errno

        if exc.errno != errno.EPIPE:
            raise
        devnull = os.open(os.devnull, os.O_WRONLY)  # nothing more reaches the closed pipe at exit
        os.dup2(devnull, sys.stdout.fileno())
        return 1
