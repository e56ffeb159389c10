from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class SrdfNotFound(Rule):
    """
    What it does:
    Reports a kinematics.yaml whose SRDF was not found (`--srdf`, or the only .srdf in the
    same directory), so its group names could not be checked.

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
