from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.numbers import owner, parse_floats
from armtool.lint.rule import Rule, Target


def _has_count(raw: str, count: int) -> bool:
    values = parse_floats(raw)
    return values is not None and len(values) == count


class MalformedNumber(Rule):
    """
    What it does:
    Reports a numeric attribute that is not a number, or has the wrong count of numbers
    (xyz and rpy take three).

    Why is this bad?
    urdfdom rejects the file; lenient parsers read a prefix or zeros, so the model
    silently differs from the text.

    Example:
    <origin xyz="0 0.1" rpy="0 0 1,57"/>

    Use instead:
    <origin xyz="0 0 0.1" rpy="0 0 1.57"/>
    """

    code, name, severity, target = "U305", "malformed-number", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        if ctx.numbers_plain():
            return  # every numeric text in the file is well formed: no element needs a look
        texts = ctx.numeric_texts()
        if all(_has_count(raw, count) for count in texts for raw in texts[count]):
            return  # some is not plain (1_000, inf) but each has the right count of numbers
        for el, attr, raw, count, values in ctx.numeric_values():
            if values is None:
                problem = "is not a number" if count == 1 else "contains something that is not a number"
            elif len(values) != count:
                problem = f"has {len(values)} values, expected {count}"
            else:
                continue
            yield ctx.finding(
                self,
                el,
                f'{owner(el)}<{local_tag(el)} {attr}="{raw}"> {problem}',
                attr=attr,
                hint=f"write {count} decimal number{'s' if count > 1 else ''} separated by spaces",
            )
