from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.rule import Rule, Target


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
        texts = ctx.numeric_texts()
        if all(values is not None and len(values) == count for count in texts for values in texts[count].values()):
            return  # every numeric text in the file is well formed: no element needs a look
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
                f"<{local_tag(el)} {attr}=\"{raw}\"> {problem}",
                attr=attr,
                hint=f"write {count} decimal number{'s' if count > 1 else ''} separated by spaces",
            )
