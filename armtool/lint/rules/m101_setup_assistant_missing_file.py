from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class SetupAssistantMissingFile(Rule):
    """
    What it does:
    Reports a MoveIt config package's `.setup_assistant` whose `urdf` (package and
    relative_path) or `srdf` (relative_path) names a file that does not exist, at that line,
    with the file it most likely became (`config/wxai.srdf` renamed `config/wxai.srdf.xacro`).
    Reported by the loader when the package's directory, or `--moveit-config`, is linted.

    Why is this bad?
    MoveIt 2's MoveItConfigsBuilder (moveit_configs_utils) takes the URDF's package and path
    and the SRDF's path from `.setup_assistant` whenever a launch file does not name them
    itself, so those launches fail with a missing file, and the Setup Assistant cannot re-open
    the package to edit it. armtool lint then checks the SRDF the package's layout gives
    (config/<robot>.srdf or .srdf.xacro, the only SRDF of config/); other armtool commands say
    which file they took.

    Example:
    srdf:
      relative_path: config/wxai.srdf      (config/ holds wxai.srdf.xacro)

    Use instead:
    srdf:
      relative_path: config/wxai.srdf.xacro
    """

    code, name, severity, target = "M101", "setup-assistant-missing-file", Severity.WARNING, Target.SETUP_ASSISTANT

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
