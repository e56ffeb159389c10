from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class UrdfNotFound(Rule):
    """
    What it does:
    Reports an SRDF whose URDF was not found or could not be loaded, so names and limits
    could not be checked, and says why (not found, or the xacro error that stopped it).
    armtool looks for `--urdf`, the `urdf` table of the configuration, the URDF named by
    MoveIt's `.setup_assistant` (package, relative path, xacro arguments), then a .urdf/.xacro
    named like the SRDF (or its robot) in its directory, its parent and the parent's
    subdirectories (the `config/` + `urdf/` layout), `<robot>.urdf.xacro` and `.urdf` first.
    A file that defines no links (`<robot>.ros2_control.xacro`) is never taken.

    Why is this bad?
    Most SRDF mistakes are names that do not match the URDF; without it they stay hidden.

    Example:
    armtool lint moveit_config/config/arm.srdf   (URDF lives in another package)

    Use instead:
    armtool lint --urdf ../arm_description/urdf/arm.urdf.xacro moveit_config/config/arm.srdf
    """

    code, name, severity, target = "S002", "urdf-not-found", Severity.WARNING, Target.SRDF

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
