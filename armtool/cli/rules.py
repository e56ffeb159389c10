"""`armtool rules [CODE]`: the rule list, or one rule's documentation."""

from __future__ import annotations

import typer

from armtool.console import write_stdout
from armtool.errors import ArmtoolError


def rules(
    code: str | None = typer.Argument(None, help="A rule code (U301) or name (rpy-out-of-range)."),
) -> None:
    from armtool.lint.registry import RULES, find_rule
    from armtool.suggest import did_you_mean

    if code is None:
        lines = [
            f"{r.code}  {r.name:<32} {r.severity.value:<7} {'fix ' if r.fix_safety.value == 'safe' else '    '}{r.summary()}"
            for r in RULES
        ]
        write_stdout("\n".join(lines))
        return
    rule = find_rule(code)
    if rule is None:
        raise ArmtoolError(
            f"no rule '{code}'{did_you_mean(code.upper(), [r.code for r in RULES] + [r.name for r in RULES])}",
            hint="run `armtool rules` for the list",
        )
    header = f"{rule.code} {rule.name} (default severity: {rule.severity.value}; fix: {rule.fix_safety.value})"
    write_stdout(f"{header}\n\n{rule.documentation()}")
