"""docs/rules.md is the page SARIF's helpUri points at: it must exist and match the rules' docstrings."""

from __future__ import annotations

import re
from pathlib import Path

from armtool.lint.docs import rule_markdown, rules_markdown
from armtool.lint.registry import RULES, find_rule
from armtool.output.sarif import lint_tool

PAGE = Path(__file__).resolve().parents[2] / "docs" / "rules.md"


def test_page_is_up_to_date() -> None:
    assert PAGE.read_text(encoding="utf-8") == rules_markdown(), (
        "docs/rules.md is stale: run `python -m armtool.lint.docs > docs/rules.md`"
    )


def test_every_sarif_help_uri_has_its_anchor_on_the_page() -> None:
    anchors = set(re.findall(r'<a id="([a-z0-9]+)"></a>', PAGE.read_text(encoding="utf-8")))
    tool = lint_tool()
    assert len(tool.rules) == len(RULES)
    for rule in tool.rules:
        page, fragment = rule.help_uri.split("#")
        assert page.endswith("/docs/rules.md")
        assert fragment in anchors, rule.code


def test_example_is_a_code_block_and_markup_in_prose_is_escaped() -> None:
    rule = find_rule("U301")
    assert rule is not None
    text = rule_markdown(rule)
    assert '**Example**\n\n```\n<origin xyz="0 0 0.1" rpy="0 0 90"/>\n```' in text
    assert "Reports an &lt;origin" in text  # in prose, a bare <origin> would be dropped as HTML
    assert "**Why is this bad?**" in text
