from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class UnknownPackage(Rule):
    """
    What it does:
    Reports a `package://pkg/...` mesh whose package cannot be found in --package-path,
    ROS_PACKAGE_PATH, AMENT_PREFIX_PATH or the directories around the file. Reported once
    per package.

    Why is this bad?
    Without the package its meshes cannot be checked here, and on a machine where the
    package is not installed RViz and Gazebo show nothing.

    Example:
    <mesh filename="package://my_robot_meshes/base.stl"/>

    Use instead:
    Run `armtool lint --package-path ../my_robot_meshes robot.urdf`, or install the
    package and source its workspace.
    """

    code, name, severity, target = "U502", "unknown-package", Severity.WARNING, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        reported: set[str] = set()
        for mesh, uri, _path, missing in ctx.meshes():
            if not missing or missing in reported:
                continue
            reported.add(missing)
            yield ctx.finding(
                self,
                mesh,
                f"cannot find package '{missing}' for '{uri}'",
                attr="filename",
                hint=f"pass --package-path DIR (the directory holding {missing}/package.xml) or set ROS_PACKAGE_PATH",
            )
