from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext


class RobotNameMismatch(Rule):
    """
    What it does:
    Reports an SRDF whose `<robot name>` differs from the name of the URDF it is paired with by
    the user or by MoveIt (`--urdf`, the configuration's `urdf` table, `.setup_assistant`,
    `--moveit-config`). A URDF armtool picked among the files beside the SRDF may simply be
    another variant, so a different name there is not reported.

    Why is this bad?
    srdfdom compares them when MoveIt loads the pair and logs "Semantic description is not
    specified for the same robot as the URDF". MoveIt carries on, but the mismatch usually means
    the SRDF was written for another robot or another variant of the description (a renamed
    xacro, another arm of the family), and its groups may not fit.

    Example:
    <robot name="panda">         (URDF)
    <robot name="panda_arm">     (SRDF)

    Use instead:
    <robot name="panda">         (SRDF)
    """

    code, name, severity, target = "S110", "robot-name-mismatch", Severity.WARNING, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        if ctx.urdf is None or not ctx.urdf_given:
            return
        mine, theirs = ctx.root.get("name"), ctx.urdf.root.get("name")
        if mine is None or theirs is None or mine == theirs:
            return
        yield ctx.finding(
            self,
            ctx.root,
            f"SRDF robot '{mine}' is not the URDF's robot '{theirs}'",
            attr="name",
            hint=f'name it <robot name="{theirs}">, or check that this SRDF belongs to this URDF',
        )
