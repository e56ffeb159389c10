from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class MoveItConfigFileNotFound(Rule):
    """
    What it does:
    Says that `armtool lint --moveit-config PKG` could not find the package's URDF or SRDF as
    its launch files find them (MoveItConfigsBuilder: the `.setup_assistant`'s entries, else
    `config/<robot>.urdf.xacro` / `config/<robot>.urdf` and `config/<robot>.srdf`; armtool also
    takes the only SRDF or SRDF xacro of config/), so that file was not checked, nor were the
    others against it. Reported on the package's `.setup_assistant` or `package.xml`.

    Why is this bad?
    Nothing may be wrong with the files that were checked; but "no problems" would cover only
    them. A package without `.setup_assistant` (written by hand, or the file not committed) is
    the usual cause.

    Example:
    armtool lint --moveit-config arm_moveit_config   (no .setup_assistant; srdf/arm.srdf.xacro)

    Use instead:
    armtool lint --moveit-config arm_moveit_config --urdf ../arm_description/urdf/arm.urdf.xacro \\
        --srdf arm_moveit_config/srdf/arm.srdf.xacro
    """

    code, name, severity, target = "M102", "moveit-config-file-not-found", Severity.WARNING, Target.SETUP_ASSISTANT

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
