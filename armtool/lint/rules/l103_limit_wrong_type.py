from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import JointLimitsContext
from armtool.lint.rule import Rule, Target
from armtool.moveit.joint_limits import KEY_TYPES

_NUMBER = ("int", "double")


class LimitWrongType(Rule):
    """
    What it does:
    Reports a value in joint_limits.yaml that its reader cannot take as its type: a string
    (`max_velocity: "2.0"`, `max_velocity: 2,0`), a bool, a list or nothing where a number
    belongs, and anything but true/false for a `has_*_limits` flag (`has_velocity_limits: 1`).
    Integers where a double belongs are L102.

    Why is this bad?
    ROS 2 (MoveIt's RobotModelLoader declares the limits as PARAMETER_DOUBLE and the flags as
    PARAMETER_BOOL): move_group stops with InvalidParameterTypeException. ROS 1 (roscpp
    getParam): the value is not read, so the limit silently does not apply ("Specified a
    velocity limit for joint ... but did not set a max velocity").

    Example:
    joint_limits:
      joint1:
        has_velocity_limits: "true"
        max_velocity: "2.0"

    Use instead:
    joint_limits:
      joint1:
        has_velocity_limits: true
        max_velocity: 2.0
    """

    code, name, severity, target = "L103", "limit-wrong-type", Severity.ERROR, Target.JOINT_LIMITS

    def check(self, ctx: JointLimitsContext) -> Iterator[Finding]:
        for entry in ctx.doc.joints:
            where = f"joint '{entry.name.written}'"
            if entry.not_a_mapping is not None and entry.not_a_mapping != "nothing":
                yield ctx.finding_at(
                    self,
                    entry.line,
                    entry.column,
                    f"{where} is {entry.not_a_mapping}, not a mapping of limits",
                    hint="write the joint's settings below it: has_velocity_limits: true, max_velocity: 2.0, ...",
                )
            for key, (shape, line, column) in entry.not_scalar.items():
                if key in KEY_TYPES:
                    yield ctx.finding_at(
                        self, line, column, f"{where}: {key} is {shape}, not a {_word(KEY_TYPES[key])}"
                    )
            for key, value in entry.values.items():
                wanted = KEY_TYPES.get(key)
                if wanted is None:
                    continue
                ok = value.kind == "bool" if wanted == "bool" else value.kind in _NUMBER
                if not ok:
                    yield ctx.finding_at_scalar(
                        self,
                        value,
                        f"{where}: {key} is {_shown(value.text, value.kind)}, not a {_word(wanted)}",
                        hint="true or false" if wanted == "bool" else "a number such as 2.0, without quotes",
                    )
        for key, value in ctx.doc.scaling.items():
            if value.kind not in _NUMBER:
                yield ctx.finding_at_scalar(
                    self, value, f"{key} is {_shown(value.text, value.kind)}, not a number", hint="e.g. 0.1"
                )
        for key, (shape, line, column) in ctx.doc.scaling_not_scalar.items():
            yield ctx.finding_at(self, line, column, f"{key} is {shape}, not a number", hint="e.g. 0.1")


def _word(kind: str) -> str:
    return "true/false flag" if kind == "bool" else "number"


def _shown(text: str, kind: str) -> str:
    if kind == "null":
        return "empty"
    return f"the {kind} {text!r}" if kind in ("string", "bool") else repr(text)
