"""`armtool tree URDF|XACRO`: the kinematic tree as text (check_urdf), Graphviz dot (urdf_to_graphviz) or Mermaid."""

from __future__ import annotations

from enum import Enum
from pathlib import Path

import typer

from armtool.cli.options import MoveItConfig, PackagePaths, RobotConfig, XacroArgs
from armtool.errors import ArmtoolError

HELP = (
    "Print a URDF's kinematic tree (links, joints, types, axes, position, velocity and effort limits), "
    "or write it as a dot/Mermaid graph."
)


class TreeFormat(str, Enum):
    TEXT = "text"
    DOT = "dot"
    MERMAID = "mermaid"


def tree(
    urdf: Path | None = typer.Argument(
        None, help="URDF or xacro of the robot (default: the --moveit-config package's)."
    ),
    output_format: TreeFormat = typer.Option(
        TreeFormat.TEXT, "--format", help="text (like check_urdf), dot (Graphviz, like urdf_to_graphviz) or mermaid."
    ),
    output: Path | None = typer.Option(None, "--output", "-o", help="Write to this file instead of stdout."),
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: RobotConfig = None,
    moveit_config: MoveItConfig = None,
) -> None:
    from armtool.cli.options import RobotOptions
    from armtool.console import write_stdout
    from armtool.fileio import check_output_paths
    from armtool.model.load import load_robot_xml
    from armtool.model.tree import read_tree, render_dot, render_mermaid, render_text

    robot = RobotOptions(xacro_arg, package_path, config)
    package_args: dict[str, str] = {}
    if moveit_config is not None:
        pkg, urdf = robot.moveit_package(moveit_config, urdf, "the URDF argument")
        package_args = pkg.urdf_xacro_args
    if urdf is None:
        raise ArmtoolError("no robot given", hint="pass the URDF (or xacro), or --moveit-config DIR")
    check_output_paths({"--output": output}, inputs=[urdf])  # `-o arm.urdf` must not overwrite the robot
    model = read_tree(load_robot_xml(urdf, robot.xacro_args(urdf, package_args), robot.package_paths))
    render = {TreeFormat.TEXT: render_text, TreeFormat.DOT: render_dot, TreeFormat.MERMAID: render_mermaid}[
        output_format
    ]
    text = render(model) + "\n"
    if output is None:
        write_stdout(text)
        return
    from rich.markup import escape

    from armtool.console import stderr
    from armtool.fileio import write_atomic

    write_atomic(output, text)
    stderr().print(
        f"wrote {escape(str(output))}"
        + (f" (render: dot -Tpng {escape(str(output))} -o tree.png)" if output_format is TreeFormat.DOT else "")
    )
