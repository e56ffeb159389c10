from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class SrdfNotFound(Rule):
    """
    What it does:
    Reports a MoveIt kinematics.yaml whose SRDF was not found (`--srdf`, the `srdf` table of
    the configuration, the SRDF named by `.setup_assistant`, the only SRDF or SRDF xacro beside
    it or in the package's `srdf/`, or the one of several that defines all its groups), so its
    group names could not be checked; it says why.

    Why is this bad?
    A group name that the SRDF lacks means MoveIt never uses these solver settings.

    Example:
    armtool lint config/kinematics.yaml   (two .srdf files in config/)

    Use instead:
    armtool lint --srdf config/arm.srdf config/kinematics.yaml
    """

    code, name, severity, target = "K002", "srdf-not-found", Severity.WARNING, Target.KINEMATICS

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
