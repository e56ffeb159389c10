from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class SrdfForOtherVariant(Rule):
    """
    What it does:
    Reports, once, an SRDF written for another argument set of its URDF's xacro (or for another
    robot). When the SRDF names joints or links the expansion lacks, armtool tries the argument
    values written down for that xacro: the configuration's sets, the `.setup_assistant` of
    sibling MoveIt configs naming the same URDF, the values its sources compare an argument with.
    One that gives every name is named (`--xacro-arg dof:=6`) and the SRDF is checked against it,
    instead of one S101/S102/S108 per name. An SRDF in one of several variant folders (config/6dof/
    beside config/7dof/) is paired with the value its folder's name holds, without a finding; when
    no value explains its names it could not be checked (this finding, with the fix). When most
    names are unknown, it is for another robot. Then names and limits are not checked: names
    missing from a variant it was not written for are never reported. Reported by the loader.

    Why is this bad?
    MoveIt loaded with this pair drops every group, state and collision pair that names what the
    URDF lacks: the planning groups are empty or missing. Usually the launch passes another
    argument (a 6-DOF Kinova launch passes dof:=6), so the fix is the argument, not the SRDF.

    Example:
    armtool lint config/gen3.srdf --urdf robots/gen3.xacro --xacro-arg dof:=7   (the SRDF is 6-DOF)

    Use instead:
    armtool lint config/gen3.srdf --urdf robots/gen3.xacro --xacro-arg dof:=6
    """

    code, name, severity, target = "S003", "srdf-for-other-variant", Severity.WARNING, Target.SRDF

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
