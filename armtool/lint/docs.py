"""docs/rules.md, written from the rule registry: the page each SARIF `helpUri` points at.

The rules' docstrings are the one source (as `armtool rules CODE` prints them); the page is
regenerated with `python -m armtool.lint.docs > docs/rules.md`, and a test keeps it in step.
"""

from __future__ import annotations

from armtool.lint.rule import Rule

_CODE_SECTIONS = ("Example:", "Use instead:")


def _section_markdown(heading: str, body: list[str]) -> list[str]:
    text = "\n".join(body).strip("\n")
    if not text:
        return []
    if heading in _CODE_SECTIONS:
        return [f"**{heading[:-1]}**", "", "```", text, "```", ""]
    return [f"**{heading.removesuffix(':')}**", "", _prose(text), ""]


def _prose(text: str) -> str:
    """Markdown renderers take `<origin ...>` for HTML and drop it: escape it, and the table's `|`."""
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def rule_markdown(rule: type[Rule]) -> str:
    """One rule's section: an anchor named by its lower-case code, then its docstring's sections."""
    lines = [
        f'<a id="{rule.code.lower()}"></a>',
        "",
        f"## {rule.code} `{rule.name}`",
        "",
        f"Default severity: {rule.severity.value}. Fix: {rule.fix_safety.value}.",
        "",
    ]
    heading, body = "", list[str]()
    for line in rule.documentation().splitlines():
        stripped = line.strip()
        if stripped.endswith((":", "?")) and stripped[:1].isupper() and not line.startswith(" ") and len(stripped) < 30:
            lines += (
                _section_markdown(heading, body) if heading else ([_prose("\n".join(body)), ""] if any(body) else [])
            )
            heading, body = stripped, []
        else:
            body.append(line)
    lines += _section_markdown(heading, body) if heading else [_prose("\n".join(body))]
    return "\n".join(lines).rstrip() + "\n"


def rules_markdown() -> str:
    from armtool.lint.registry import RULES

    head = [
        "# armtool lint rules",
        "",
        "Written from the rules' docstrings by `python -m armtool.lint.docs > docs/rules.md`;",
        "`armtool rules CODE` prints the same text. Letters: U URDF, X xacro, S SRDF, K kinematics.yaml,",
        "L joint_limits.yaml, P pilz_cartesian_limits.yaml, C controllers files, M a MoveIt config package's "
        ".setup_assistant.",
        "",
        "| code | name | severity | fix | what it does |",
        "|---|---|---|---|---|",
    ]
    for rule in RULES:
        summary = _prose(rule.summary()).replace("|", "\\|")
        head.append(
            f"| [{rule.code}](#{rule.code.lower()}) | `{rule.name}` | {rule.severity.value} | "
            f"{rule.fix_safety.value} | {summary} |"
        )
    return "\n".join(head) + "\n\n" + "\n".join(rule_markdown(r) for r in RULES)


if __name__ == "__main__":
    import sys

    sys.stdout.write(rules_markdown())
