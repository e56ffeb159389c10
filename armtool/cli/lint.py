"""`armtool lint PATH...`: arguments in, findings out, exit code 0 / 1 / 2."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import typer

from armtool.cli.options import MoveItConfig, PackagePaths, XacroArgs, parse_xacro_args
from armtool.errors import ArmtoolError, ExitCode
from armtool.lint.finding import Severity
from armtool.output.registry import OutputFormat


def lint(
    paths: list[Path] | None = typer.Argument(
        None,
        help="URDF, xacro, SRDF or MoveIt YAML files, or directories to search; - reads a URDF or SRDF from stdin "
        "(none with --moveit-config: the package's files).",
    ),
    output_format: OutputFormat | None = typer.Option(
        None, "--format", help="Output format (default: text; github inside GitHub Actions)."
    ),
    fail_on: Severity | None = typer.Option(
        None, "--fail-on", help="Lowest severity that makes the exit code 1 \\[default: error]."
    ),
    exit_zero: bool = typer.Option(False, "--exit-zero", help="Exit 0 even when problems are found."),
    fix: bool = typer.Option(False, "--fix", help="Apply safe fixes in place (text edits; comments and layout kept)."),
    diff: bool = typer.Option(False, "--diff", help="Show the safe fixes as a unified diff; write nothing."),
    select: str | None = typer.Option(
        None, "--select", help="Comma-separated codes or prefixes to check (e.g. U3,S101)."
    ),
    ignore: str | None = typer.Option(None, "--ignore", help="Comma-separated codes or prefixes to skip."),
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    moveit_config: MoveItConfig = None,
    urdf: Path | None = typer.Option(None, "--urdf", help="URDF (or xacro) that SRDF files describe."),
    srdf: Path | None = typer.Option(None, "--srdf", help="SRDF that kinematics.yaml files refer to."),
    config: Path | None = typer.Option(
        None, "--config", help="pyproject.toml with [tool.armtool.lint] (default: nearest one)."
    ),
) -> None:
    from armtool.console import stderr, write_stdout
    from armtool.lint.config import load_config, parse_selectors
    from armtool.lint.engine import LintOptions, lint_paths
    from armtool.lint.locate import display_path
    from armtool.output.base import LintReport
    from armtool.output.registry import formatter

    for given, flag in ((urdf, "--urdf"), (srdf, "--srdf"), (config, "--config")):
        if given is not None and not given.is_file():
            raise ArmtoolError(f"{flag}: no such file", str(given))
    selected = parse_selectors(select, "--select") if select is not None else None
    ignored = parse_selectors(ignore, "--ignore") if ignore is not None else []
    cfg = load_config(config)
    if selected is not None:
        cfg.select = selected
    cfg.ignore += ignored
    if fail_on is not None:
        cfg.fail_on = fail_on
    paths = list(paths or [])
    if not paths and moveit_config is None:
        raise typer.BadParameter("give files or directories to lint, or --moveit-config DIR", param_hint="PATHS")
    stdin = sys.stdin.buffer.read() if any(str(p) == "-" for p in paths) else None
    options = LintOptions(
        xacro_args=parse_xacro_args(xacro_arg),
        package_paths=list(package_path or ()),
        urdf=urdf,
        srdf=srdf,
        config=cfg,
        stdin=stdin,
        moveit_config=moveit_config,
    )
    result = lint_paths(paths, options)
    findings = result.findings
    if diff or fix:
        from armtool.lint.fix import fixed_texts, safe_edits, unified_diff, write_atomic

        pairs = safe_edits(findings)

    if diff:
        changes = fixed_texts(pairs)
        for path, (old, new, _) in sorted(changes.items()):
            write_stdout(unified_diff(path, old, new, display_path(path)))
        count = sum(len(applied) for _, _, applied in changes.values())
        stderr().print(f"{count} fix(es) in {len(changes)} file(s) would be applied; nothing written.")
        raise typer.Exit(ExitCode.FINDINGS if changes and not exit_zero else ExitCode.OK)

    if fix and pairs:
        changes = fixed_texts(pairs)
        fixed: set[int] = set()
        for path, (_old, new, applied) in changes.items():
            write_atomic(path, new)
            fixed.update(id(f) for f in applied)
        findings = [f for f in findings if id(f) not in fixed]
        stderr().print(f"Fixed {len(fixed)} problem(s) in {len(changes)} file(s).")

    fmt = output_format
    if fmt is None:
        fmt = OutputFormat.GITHUB if os.environ.get("GITHUB_ACTIONS") == "true" else OutputFormat.TEXT
    report = LintReport(findings, len(result.files), fixable=sum(1 for f in findings if f.edit is not None and not fix))
    write_stdout(formatter(fmt).render(report, color=sys.stdout.isatty() and "NO_COLOR" not in os.environ))
    failing = any(f.severity.rank >= cfg.fail_on.rank for f in findings)
    raise typer.Exit(ExitCode.FINDINGS if failing and not exit_zero else ExitCode.OK)


# `armtool lint PATH...` with no option at all is how pre-commit runs it, on every commit. That
# call skips building the Typer command, whose parameter introspection costs ~4% of the run.
# Anything else (an option, --help, no path) goes through Typer. These are the values Typer
# passes for the defaults (tests/lint/test_cli_plain_paths.py compares both ways).
_DEFAULTS: dict[str, object] = {
    "output_format": None,
    "fail_on": None,
    "exit_zero": False,
    "fix": False,
    "diff": False,
    "select": None,
    "ignore": None,
    "xacro_arg": None,
    "package_path": None,
    "moveit_config": None,
    "urdf": None,
    "srdf": None,
    "config": None,
}


def run_plain(args: list[str]) -> int | None:
    """Run `armtool lint ARGS` if every argument is a path and return the exit code, else None.

    Exits as Typer's standalone mode would: typer.Exit's code, 130 on Ctrl-C, 1 on a closed
    stdout pipe (`armtool lint ... | head`); other exceptions propagate to the caller.
    """
    if not args or any(arg.startswith("-") for arg in args):
        return None
    options = {k: list(v) if isinstance(v, tuple) else v for k, v in _DEFAULTS.items()}
    try:
        lint([Path(arg) for arg in args], **options)  # type: ignore[arg-type]
    except typer.Exit as exc:
        return exc.exit_code
    except KeyboardInterrupt:
        return 130
    except OSError as exc:
        import errno

        if exc.errno != errno.EPIPE:
            raise
        devnull = os.open(os.devnull, os.O_WRONLY)  # nothing more reaches the closed pipe at exit
        os.dup2(devnull, sys.stdout.fileno())
        return 1
    return 0
