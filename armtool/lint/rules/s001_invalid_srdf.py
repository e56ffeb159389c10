from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class InvalidSrdf(Rule):
    """
    What it does:
    Reports an SRDF that is not well-formed XML or whose root element is not <robot>.
    Reported by the loader.

    Why is this bad?
    MoveIt's setup fails with "Unable to parse SRDF" and the move_group node does not start.

    Example:
    <robot name="arm"><group name="arm"><chain base_link="base" tip_link="tool0"></robot>

    Use instead:
    <robot name="arm"><group name="arm"><chain base_link="base" tip_link="tool0"/></group></robot>
    """

    code, name, severity, target = "S001", "invalid-srdf", Severity.ERROR, Target.SRDF

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
