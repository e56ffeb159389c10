from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class SrdfNotFound(Rule):
    """
    What it does:
    Reports a MoveIt kinematics.yaml whose SRDF was not found (`--srdf`, the `srdf` table of
    the configuration, the SRDF named by `.setup_assistant`, the only SRDF or SRDF xacro beside
    it or in the package's `srdf/`; of several, one that defines all its groups, which each
    check then holds against, or any when they all define the same groups: an SRDF and its
    exported copy), so its group names could not be checked; it says why.

    Why is this bad?
    A group name that the SRDF lacks means MoveIt never uses these solver settings.

    Example:
    armtool lint config/kinematics.yaml   (two .srdf files in config/, neither with its groups)

    Use instead:
    armtool lint --srdf config/arm.srdf config/kinematics.yaml
    """

    code, name, severity, target = "K002", "srdf-not-found", Severity.WARNING, Target.KINEMATICS

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
