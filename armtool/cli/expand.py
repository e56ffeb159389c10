"""`armtool expand FILE.xacro`: the document armtool checks, as armtool's own xacro expansion made it.

Users see what `lint` saw: the same xacro arguments, package lookup (package.xml names,
--package-path, ROS variables, the tree around the file) and per-file settings from the config.
"""

from __future__ import annotations

from pathlib import Path

import typer

from armtool.cli.options import PackagePaths, RobotConfig, XacroArgs
from armtool.errors import ArmtoolError

HELP = "Print a xacro file expanded as armtool expands it for lint and ik-bench (URDF or SRDF xacro)."


def expand(
    path: Path = typer.Argument(..., help="A .xacro file (URDF or SRDF)."),
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: RobotConfig = None,
) -> None:
    from lxml import etree

    from armtool.cli.options import RobotOptions
    from armtool.console import write_stdout
    from armtool.model.packages import PackageResolver
    from armtool.model.xacro_source import XacroFailure
    from armtool.model.xacro_source import expand as run_xacro

    if not path.is_file():
        what = "not a regular file (a FIFO, socket or device)" if path.exists() else "no such file"
        raise ArmtoolError(what, str(path), "check the path to the .xacro file")
    robot = RobotOptions(xacro_arg, package_path, config)
    args = robot.xacro_args(path)
    resolver = PackageResolver(robot.package_paths)
    try:
        expansion = run_xacro(path, args, resolver)
    except XacroFailure as exc:
        from armtool.lint.locate import display_path

        raise ArmtoolError(f"xacro failed: {exc.message}", f"{display_path(exc.path)}:{exc.line}", exc.hint) from None
    etree.indent(expansion.root, space="  ")  # one element per line, as `xacro` prints it
    text = etree.tostring(expansion.root, encoding="unicode")
    write_stdout('<?xml version="1.0"?>\n' + text)
