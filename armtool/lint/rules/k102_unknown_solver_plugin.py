from __future__ import annotations

import re
from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.kinematics_context import KinematicsContext
from armtool.lint.rule import Rule, Target
from armtool.suggest import closest, levenshtein, nearest_within

# pluginlib lookup names of the IK plugins in MoveIt (moveit_kinematics/*_plugin_description.xml)
# and in the ecosystem (trac_ik, pick_ik, bio_ik, moveit_opw_kinematics_plugin, ur_kinematics).
KNOWN_PLUGINS = (
    "kdl_kinematics_plugin/KDLKinematicsPlugin",
    "lma_kinematics_plugin/LMAKinematicsPlugin",
    "srv_kinematics_plugin/SrvKinematicsPlugin",
    "cached_ik_kinematics_plugin/CachedKDLKinematicsPlugin",
    "cached_ik_kinematics_plugin/CachedSrvKinematicsPlugin",
    "cached_ik_kinematics_plugin/CachedTRACKinematicsPlugin",
    "cached_ik_kinematics_plugin/CachedUR3KinematicsPlugin",
    "cached_ik_kinematics_plugin/CachedUR5KinematicsPlugin",
    "cached_ik_kinematics_plugin/CachedUR10KinematicsPlugin",
    "planar_kinematics_plugin/PlanarKinematicsPlugin",
    "planar_kinematics_plugin::PlanarKinematicsPlugin",
    "trac_ik_kinematics_plugin/TRAC_IKKinematicsPlugin",
    "pick_ik/PickIkPlugin",
    "bio_ik/BioIKKinematicsPlugin",
    "moveit_opw_kinematics_plugin/MoveItOPWKinematicsPlugin",
    "opw_kinematics_plugin/OPWKinematicsPlugin",
    "ur_kinematics/UR3KinematicsPlugin",
    "ur_kinematics/UR5KinematicsPlugin",
    "ur_kinematics/UR10KinematicsPlugin",
)
# A generated IKFast plugin may have any package name (`<robot>_<group>_ikfast_plugin`, `prbt_manipulator`).
IKFAST = re.compile(r"[A-Za-z_][\w:]*(/|::)IKFastKinematicsPlugin")
# pluginlib's lookup name `package/Class`, or a class type `namespace::Class`: any plugin a workspace declares.
PLUGINLIB_NAME = re.compile(r"[A-Za-z_]\w*(/|::)[A-Za-z_]\w*(::[A-Za-z_]\w*)*")
_KNOWN_PACKAGES = {k.replace("::", "/").split("/")[0] for k in KNOWN_PLUGINS}
MAX_TYPO_EDITS = 3


def near_miss(value: str) -> str | None:
    """The known plugin `value` was probably meant to be: a few edits (case ignored) away, or a
    class that the named MoveIt package does not export. None for a name that is just different."""
    best = nearest_within(value, KNOWN_PLUGINS, MAX_TYPO_EDITS, levenshtein, fold=str.lower)
    if best is not None:
        return best
    package = value.replace("::", "/").split("/")[0]
    if package in _KNOWN_PACKAGES:
        own = [k for k in KNOWN_PLUGINS if k.replace("::", "/").split("/")[0] == package]
        return closest(value, own) or own[0]
    return None


class UnknownSolverPlugin(Rule):
    """
    What it does:
    Reports a kinematics_solver that is a near miss of a known IK plugin (KDL, LMA, the service
    plugin, cached IK, planar, TRAC-IK, pick_ik, bio_ik, OPW, ur_kinematics): a few letters off,
    or a class the named package does not export; and a value that is no pluginlib name at all.
    Any other `package/Class` passes (a plugin declared in the workspace), and so does every
    IKFast plugin (`<anything>/IKFastKinematicsPlugin`).

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
            match = near_miss(text) if isinstance(value, str) else None
            if match is None and isinstance(value, str) and PLUGINLIB_NAME.fullmatch(value):
                continue  # a plugin of its own (pluginlib finds it in the workspace); nothing to compare with
            yield ctx.finding_at(
                self,
                item.line,
                item.column,
                f"group '{group.name}': kinematics_solver '{text}' is not a known IK plugin"
                + (f" (did you mean '{match}'?)" if match else ""),
                hint=f"kinematics_solver: {match}"
                if match
                else "use pluginlib's package/Class name, e.g. kdl_kinematics_plugin/KDLKinematicsPlugin; for a custom "
                "plugin, silence this line with `# armtool: ignore[K102]`",
            )
