"""The Typer app of `armtool`: every subcommand, one module each, built on first use (a plain
`armtool lint PATH...` never builds it: see armtool.cli.lint_run)."""

from __future__ import annotations

import sys

import typer

from armtool import __version__
from armtool.cli import lint as lint_cmd

LINT_HELP = "Find silent mistakes in URDF, xacro, SRDF and MoveIt kinematics.yaml files."
_CONTEXT = {"help_option_names": ["-h", "--help"]}


def _version(value: bool) -> None:
    if value:
        typer.echo(f"armtool {__version__}")
        raise typer.Exit()


def _root(
    version: bool = typer.Option(
        False, "--version", callback=_version, is_eager=True, help="Show the version and exit."
    ),
    verbose: int = typer.Option(0, "--verbose", "-v", count=True, help="More log output on stderr (-vv for debug)."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="Only errors on stderr."),
) -> None:
    if verbose or quiet:  # logging costs start-up time; the default (warnings) needs no set-up
        import logging

        level = logging.ERROR if quiet else (logging.INFO, logging.DEBUG)[min(verbose, 2) - 1]
        logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s", stream=sys.stderr)


_ESCAPED: dict[int, object] = {}


def escape_help(app: typer.Typer) -> typer.Typer:
    """Escape rich markup in every help text of `app` and its sub-apps, in place (idempotent).

    Typer renders help with rich markup, so "armtool[peers]" became "armtool" and
    "[default: …]" vanished. armtool's help texts are plain text: escape them all here, once,
    instead of in each command's module.
    """
    import inspect

    from rich.markup import escape

    def fix(obj: object) -> None:
        text = getattr(obj, "help", None)
        if isinstance(text, str) and id(obj) not in _ESCAPED:
            obj.help = escape(text)  # type: ignore[attr-defined]
            _ESCAPED[id(obj)] = obj  # kept alive, so its id is not reused

    def fix_params(callback: object) -> None:
        """The options of a command: typer.Option(...) defaults, and Annotated[..., typer.Option(...)]."""
        import typing

        for param in inspect.signature(callback).parameters.values():  # type: ignore[arg-type]
            fix(param.default)
        try:
            hints = typing.get_type_hints(callback, include_extras=True)
        except Exception:  # a name only imported for type checking: typer resolves what it needs itself
            hints = {}
        for hint in hints.values():
            for meta in getattr(hint, "__metadata__", ()):
                fix(meta)

    def walk(typer_app: typer.Typer) -> None:
        fix(typer_app.info)
        for command in typer_app.registered_commands:
            fix(command)
            if command.callback is not None:
                fix_params(command.callback)
        if typer_app.registered_callback is not None and typer_app.registered_callback.callback is not None:
            fix_params(typer_app.registered_callback.callback)
        for group in typer_app.registered_groups:
            fix(group)
            if group.typer_instance is not None:
                walk(group.typer_instance)

    walk(app)
    return app


def build_app() -> typer.Typer:
    """The full command: every subcommand, one module each."""
    from armtool.cli import ik_bench as ik_bench_cmd
    from armtool.cli import rules as rules_cmd

    full = typer.Typer(
        name="armtool",
        help="Toolkit for people who build and debug robot arms.",
        no_args_is_help=True,
        add_completion=False,
        pretty_exceptions_enable=False,
        context_settings=_CONTEXT,
    )
    full.callback()(_root)
    full.command("lint", help=LINT_HELP)(lint_cmd.lint)
    full.command("lint-urdf", help="Alias of `armtool lint`.")(lint_cmd.lint)
    full.command("rules", help="List the lint rules, or show one rule's documentation.")(rules_cmd.rules)
    from armtool.cli import expand as expand_cmd

    full.command("expand", help=expand_cmd.HELP)(expand_cmd.expand)
    full.command("ik-bench", help="Compare IK solvers on your robot: success, speed, accuracy, repeatability.")(
        ik_bench_cmd.ik_bench
    )
    from armtool.cli import calibrate as calibrate_cmd

    full.add_typer(
        calibrate_cmd.app,
        name="calibrate",
        help=calibrate_cmd.HELP,
    )
    from armtool.cli import servo_lut as servo_lut_cmd

    full.add_typer(servo_lut_cmd.app, name="servo-lut", help=servo_lut_cmd.HELP)
    from armtool.cli import servo_sim as servo_sim_cmd

    full.command("servo-sim", help="Simulate a Dynamixel/Feetech servo bus on a pseudo-terminal (tests, demos).")(
        servo_sim_cmd.servo_sim
    )
    from armtool.cli import tree as tree_cmd

    full.command("tree", help=tree_cmd.HELP)(tree_cmd.tree)
    from armtool.cli import limits as limits_cmd
    from armtool.cli import traj as traj_cmd

    full.add_typer(traj_cmd.app, name="traj", help=traj_cmd.HELP)
    full.command(
        "limits",
        help="Record each joint's real range over a Dynamixel/Feetech bus; write limits YAML, URDF limits, EEPROM.",
    )(limits_cmd.limits)
    return escape_help(add_manual_links(full))


def add_manual_links(app: typer.Typer) -> typer.Typer:
    """End the help of armtool, of every command and of every subcommand with its manual page's URL."""
    from armtool.docs_links import manual_link

    app.info.epilog = manual_link()
    for command in app.registered_commands:
        command.epilog = manual_link(command.name)
    for group in app.registered_groups:
        link = manual_link(group.name)
        group.epilog = link
        if group.typer_instance is not None:
            for command in group.typer_instance.registered_commands:
                command.epilog = link
    return app


def lint_only_app(show_help: bool) -> typer.Typer:
    """`armtool lint` alone: pre-commit runs it on every commit, and importing and building the
    parsers of every other subcommand first would add ~10 ms to each run."""
    single = typer.Typer(add_completion=False, pretty_exceptions_enable=False, context_settings=_CONTEXT)
    from armtool.docs_links import manual_link

    single.command(help=LINT_HELP, epilog=manual_link("lint"))(lint_cmd.lint)
    return escape_help(single) if show_help else single  # rich.markup costs ~20 ms: only when help is shown
