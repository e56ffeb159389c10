from __future__ import annotations

import re
from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.kinematics_context import KinematicsContext
from armtool.lint.rule import Rule, Target
from armtool.lint.suggest import closest

KNOWN_PLUGINS = (
    "kdl_kinematics_plugin/KDLKinematicsPlugin",
    "trac_ik_kinematics_plugin/TRAC_IKKinematicsPlugin",
    "pick_ik/PickIkPlugin",
    "bio_ik/BioIKKinematicsPlugin",
    "cached_ik_kinematics_plugin/CachedKDLKinematicsPlugin",
    "cached_ik_kinematics_plugin/CachedTRACKinematicsPlugin",
    "lma_kinematics_plugin/LMAKinematicsPlugin",
    "srv_kinematics_plugin/SrvKinematicsPlugin",
)
IKFAST = re.compile(r".*_ikfast_plugin/IKFastKinematicsPlugin|.*IKFast.*")


class UnknownSolverPlugin(Rule):
    """
    What it does:
    Reports a kinematics_solver that is not a known MoveIt IK plugin: KDL, TRAC-IK, pick_ik,
    bio_ik, cached IK (KDL/TRAC), LMA, the service plugin, or a generated IKFast plugin
    (`<robot>_<group>_ikfast_plugin/IKFastKinematicsPlugin`).

    Why is this bad?
    pluginlib cannot load the class, so the group has no IK solver: MoveIt logs "Kinematics
    solver could not be instantiated" at start-up and every Cartesian or pose goal fails.
    A typo in the package or class part is the usual cause.

    Example:
    arm:
      kinematics_solver: kdl_kinematics_plugin/KDLKinematicPlugin

    Use instead:
    arm:
      kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin
    """

    code, name, severity, target = "K102", "unknown-solver-plugin", Severity.ERROR, Target.KINEMATICS

    def check(self, ctx: KinematicsContext) -> Iterator[Finding]:
        for group in ctx.groups:
            item = group.settings.get("kinematics_solver")
            if item is None:
                continue
            value = item.value
            if isinstance(value, str) and (value in KNOWN_PLUGINS or IKFAST.fullmatch(value)):
                continue
            text = str(value)
            match = closest(text, KNOWN_PLUGINS) if isinstance(value, str) else None
            if not match and isinstance(value, str) and "/" in value:
                # same class, wrong package (or the reverse): compare the parts separately
                pkg, _, cls = value.partition("/")
                match = next((k for k in KNOWN_PLUGINS if k.split("/")[1] == cls or k.split("/")[0] == pkg), None)
            yield ctx.finding_at(
                self,
                item.line,
                item.column,
                f"group '{group.name}': kinematics_solver '{text}' is not a known IK plugin"
                + (f" (did you mean '{match}'?)" if match else ""),
                hint=f"kinematics_solver: {match}" if match else
                "use package/Class, e.g. kdl_kinematics_plugin/KDLKinematicsPlugin; for a custom plugin, "
                "silence this line with `# armtool: ignore[K102]`",
            )
