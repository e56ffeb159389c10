from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class InvalidYaml(Rule):
    """
    What it does:
    Reports a kinematics.yaml that is not valid YAML, or whose top level is not a mapping of
    group names to settings (a list, a number, a string), or that is nested too deeply to
    read. Reported by the loader.

    Why is this bad?
    MoveIt reads no solver settings and falls back to defaults (or fails to launch),
    usually without naming the file. A ROS parameter file is a mapping at its top level
    (roslaunch refuses a list without `param=`; ROS 2 parameters are named), so a list
    gives MoveIt no group and no IK solver.

    Example:
    arm:
      kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin
     kinematics_solver_timeout: 0.005

    Use instead:
    arm:
      kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin
      kinematics_solver_timeout: 0.005
    """

    code, name, severity, target = "K001", "invalid-yaml", Severity.ERROR, Target.KINEMATICS

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
