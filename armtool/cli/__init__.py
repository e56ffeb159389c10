"""The `armtool` command: one Typer app (armtool.cli.typer_app), one module per subcommand, one error path.

Nothing here imports Typer: `armtool lint PATH...`, how pre-commit runs it on every commit, goes
straight to armtool.cli.lint_run, and only anything else builds the parser.
"""

from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING

from armtool.errors import ArmtoolError, ExitCode

if TYPE_CHECKING:
    import typer


def report_error(exc: ArmtoolError) -> None:
    from rich.markup import escape

    from armtool.console import stderr

    where = f" ({escape(exc.where)})" if exc.where else ""
    stderr().print(f"[bold red]error:[/bold red] {escape(exc.what)}{where}")
    if exc.hint:
        stderr().print(f"  [dim]hint:[/dim] {escape(exc.hint)}")


_app: typer.Typer | None = None


def __getattr__(name: str) -> typer.Typer:
    # `from armtool.cli import app` (tests, embedding): built on first use.
    global _app
    if name == "app":
        if _app is None:
            from armtool.cli.typer_app import build_app

            _app = build_app()
        return _app
    raise AttributeError(name)


def main() -> None:
    """Entry point: user errors print what/where/hint and exit 2; tracebacks only with ARMTOOL_DEBUG=1."""
    debug = os.environ.get("ARMTOOL_DEBUG") == "1"
    argv = sys.argv[1:]
    try:
        if argv[:1] in (["lint"], ["lint-urdf"]):
            from armtool.cli.lint_run import run_plain

            code = run_plain(argv[1:])  # only paths: no Typer at all
            if code is not None:
                sys.exit(code)
            from armtool.cli.typer_app import lint_only_app

            wants_help = any(a in ("-h", "--help") for a in argv[1:])
            lint_only_app(wants_help)(args=argv[1:], prog_name=f"armtool {argv[0]}", standalone_mode=True)
        else:
            from armtool.cli.typer_app import build_app

            build_app()(standalone_mode=True)
    except ArmtoolError as exc:
        if debug:
            raise
        report_error(exc)
        sys.exit(ExitCode.ERROR)
    except SystemExit as exc:
        # Typer turns an interrupt into exit code 130; a SIGTERM (the servo guard raises
        # Terminated for it) should end with 143, as shells expect of a terminated process.
        interrupt = getattr(exc.__context__, "__cause__", None)
        if exc.code == 130 and isinstance(interrupt, KeyboardInterrupt):
            sys.exit(getattr(interrupt, "exit_code", 130))
        raise
    except KeyboardInterrupt as exc:  # Ctrl-C: 130; SIGTERM (the servo guard's Terminated): 143
        sys.stderr.write("interrupted\n")
        sys.exit(getattr(exc, "exit_code", 130))
    except Exception as exc:  # a bug in armtool (or a missing extra): say so plainly
        if debug:
            raise
        from armtool.extras import missing_extra_error

        if isinstance(exc, ModuleNotFoundError) and (missing := missing_extra_error(exc)) is not None:
            report_error(missing)  # an optional module a command imported without calling require()
            sys.exit(ExitCode.ERROR)
        sys.stderr.write(
            f"error: internal error: {type(exc).__name__}: {exc}\n"
            "  hint: rerun with ARMTOOL_DEBUG=1 for the traceback, and report it\n"
        )
        sys.exit(ExitCode.ERROR)
