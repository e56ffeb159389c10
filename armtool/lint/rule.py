"""A rule: a stable code, a kebab-case name, a default severity, and documentation in its docstring."""

from __future__ import annotations

from collections.abc import Iterator
from enum import Enum
from typing import Any, ClassVar

from armtool.lint.finding import Finding, FixSafety, Severity


class Target(str, Enum):
    """The kind of file a rule checks."""

    URDF = "urdf"
    SRDF = "srdf"
    KINEMATICS = "kinematics"
    JOINT_LIMITS = "joint_limits"
    PILZ = "pilz"
    CONTROLLERS = "controllers"
    SETUP_ASSISTANT = "setup_assistant"


DOC_SECTIONS = ("What it does", "Why is this bad?", "Example", "Use instead")


class Rule:
    """Base class. The docstring is the rule's documentation (shown by `armtool rules CODE` and in SARIF).

    It must contain the sections in DOC_SECTIONS, each as a line ending with a colon.
    """

    code: ClassVar[str]
    name: ClassVar[str]
    severity: ClassVar[Severity]
    target: ClassVar[Target]
    fix_safety: ClassVar[FixSafety] = FixSafety.NONE

    def check(self, ctx: Any) -> Iterator[Finding]:
        raise NotImplementedError

    @classmethod
    def documentation(cls) -> str:
        import inspect

        return inspect.cleandoc(cls.__doc__ or "")

    @classmethod
    def summary(cls) -> str:
        """First sentence of "What it does", for listings and SARIF shortDescription."""
        doc = cls.documentation()
        lines = doc.splitlines()
        for i, line in enumerate(lines):
            if line.strip() == "What it does:":
                body = []
                for nxt in lines[i + 1 :]:
                    if not nxt.strip():
                        break
                    body.append(nxt.strip())
                return " ".join(body)
        return lines[0] if lines else cls.name
