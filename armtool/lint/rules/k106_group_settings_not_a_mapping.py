from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.kinematics_context import KinematicsContext
from armtool.lint.rule import Rule, Target


class GroupSettingsNotAMapping(Rule):
    """
    What it does:
    Reports a group in kinematics.yaml whose entry is not a mapping of settings: a number,
    a string, a list, or nothing at all (`arm:` with no settings below it).

    Why is this bad?
    MoveIt looks up `GROUP.kinematics_solver` for each planning group; when the entry is not
    a mapping there is no such parameter, so the group silently gets no IK solver and every
    IK request for it fails later, far from this file.

    Example:
    arm: kdl_kinematics_plugin/KDLKinematicsPlugin

    Use instead:
    arm:
      kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin
      kinematics_solver_timeout: 0.005
    """

    code, name, severity, target = "K106", "group-settings-not-a-mapping", Severity.ERROR, Target.KINEMATICS

    def check(self, ctx: KinematicsContext) -> Iterator[Finding]:
        for group in ctx.groups:
            if group.not_a_mapping is not None:
                what = (
                    "has no settings"
                    if group.not_a_mapping == "nothing"
                    else f"is {group.not_a_mapping}, not a mapping of settings"
                )
                yield ctx.finding_at(
                    self,
                    group.line,
                    group.column,
                    f"group '{group.name}' {what}: MoveIt loads no IK solver for it",
                    hint=f"write '{group.name}:' then indented settings, e.g. kinematics_solver: "
                    "kdl_kinematics_plugin/KDLKinematicsPlugin",
                )
