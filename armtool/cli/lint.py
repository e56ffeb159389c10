"""`armtool lint`'s Typer command: options in, a LintRequest to armtool.cli.lint_run, its exit code out."""

from __future__ import annotations

from pathlib import Path

import typer

from armtool.cli.options import MoveItConfig, PackagePaths, XacroArgs, parse_xacro_args
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
    from armtool.cli.lint_run import LintRequest, run

    if not paths and moveit_config is None:
        raise typer.BadParameter("give files or directories to lint, or --moveit-config DIR", param_hint="PATHS")
    request = LintRequest(
        list(paths or []),
        output_format=output_format,
        fail_on=fail_on,
        exit_zero=exit_zero,
        fix=fix,
        diff=diff,
        select=select,
        ignore=ignore,
        xacro_args=parse_xacro_args(xacro_arg),
        package_paths=list(package_path or ()),
        moveit_config=moveit_config,
        urdf=urdf,
        srdf=srdf,
        config=config,
    )
    raise typer.Exit(run(request))
