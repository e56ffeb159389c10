from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.numbers import parse_floats
from armtool.lint.rule import Rule, Target


class NonPositiveReduction(Rule):
    """
    What it does:
    Reports a transmission <mechanicalReduction> that is zero or not a number (error),
    and a negative one (info: ros_control accepts it to reverse the motor direction).

    Why is this bad?
    The transmission maps actuator to joint by multiplying or dividing by the reduction:
    0 gives a joint that never moves or a division by zero in ros_control. (A reversed
    motor is usually handled by the joint axis, not a negative ratio.)

    Example:
    <mechanicalReduction>0</mechanicalReduction>

    Use instead:
    <mechanicalReduction>100</mechanicalReduction>
    """

    code, name, severity, target = "U504", "non-positive-reduction", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for trans in ctx.transmissions:
            for red in trans.iter("mechanicalReduction"):
                values = parse_floats(red.text)
                if values and len(values) == 1 and values[0] < 0:
                    yield ctx.finding(
                        self,
                        red,
                        f"transmission '{trans.get('name')}': mechanicalReduction {values[0]:g} is negative "
                        "(reverses the motor direction)",
                        hint="if the motor turns the wrong way on purpose, keep it; else use a positive ratio",
                    ).with_severity(Severity.INFO)
                    continue
                if values and len(values) == 1 and values[0] > 0:
                    continue
                yield ctx.finding(
                    self,
                    red,
                    f"transmission '{trans.get('name')}': mechanicalReduction '{(red.text or '').strip()}' is not a positive number",
                    hint="write the gear ratio, e.g. 100 for a 100:1 gearbox",
                )
