from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.kinematics_context import KinematicsContext
from armtool.lint.rule import Rule, Target
from armtool.suggest import closest


class KinematicsUnknownGroup(Rule):
    """
    What it does:
    Reports a group in kinematics.yaml that the SRDF does not define. A key's ROS 1 launch
    substitutions are filled in as the package's launch fills them (`$(arg arm_id)_arm` is
    `panda_arm` where planning_context.launch loads the file with `subst_value="true"` and arm_id
    defaults to panda; without such a launch file, the SRDF xacro's `<xacro:arg>` defaults). A
    group that an SRDF xacro defines with another argument value its sources write down (the
    `panda_manipulator` of `hand:=true`) is not reported: the file serves every variant.

    Why is this bad?
    MoveIt loads solver settings per SRDF group name; a group it does not know is skipped
    without a word, and the real group gets no IK solver at all ("No kinematics solver
    instantiated for group 'arm'") or falls back to defaults.

    Example:
    manipulater:
      kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin

    Use instead:
    manipulator:
      kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin
    """

    code, name, severity, target = "K101", "kinematics-unknown-group", Severity.ERROR, Target.KINEMATICS

    def check(self, ctx: KinematicsContext) -> Iterator[Finding]:
        if ctx.srdf is None:
            return
        known = set(ctx.srdf.groups)
        srdf_name = ctx.srdf.path.name
        for group in ctx.groups:
            if group.name in known or group.name in ctx.variant_groups:
                continue  # a group of this SRDF, or of its xacro with another written-down argument value
            match = closest(group.name, known)
            if match:
                hint = f"rename the key to '{match}'"
            elif known:
                hint = f"groups in {srdf_name}: " + ", ".join(sorted(known))
            else:
                hint = f"{srdf_name} defines no groups; add the group there"
            yield ctx.finding_at(
                self,
                group.line,
                group.column,
                f"group '{group.written or group.name}'{f' ({group.name})' if group.written else ''} "
                f"is not defined in {srdf_name}" + (f" (did you mean '{match}'?)" if match else ""),
                hint=hint,
            )
