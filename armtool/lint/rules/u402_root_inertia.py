from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class RootInertia(Rule):
    """
    What it does:
    Reports an <inertial> on the root link.

    Why is this bad?
    KDL (robot_state_publisher, KDL-based controllers and solvers) ignores the inertia of
    the root link and warns at every start; the mass is lost for dynamics there. Harmless
    for tools that read it (Pinocchio, Gazebo), hence info.

    Example:
    <link name="base_link"><inertial>...</inertial></link>   (root)

    Use instead:
    <link name="base_footprint"/>
    <joint name="base_joint" type="fixed"><parent link="base_footprint"/><child link="base_link"/></joint>
    """

    code, name, severity, target = "U402", "root-inertia", Severity.INFO, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        roots = ctx.root_links()
        if len(roots) != 1:
            return
        link = ctx.link(roots[0])
        if link is None:
            return
        inertial = link.find("inertial")
        if inertial is not None:
            yield ctx.finding(
                self,
                inertial,
                f"root link '{roots[0]}' has an <inertial>, which KDL ignores",
                hint="add a massless root link above it with a fixed joint if KDL users need this mass",
            )
