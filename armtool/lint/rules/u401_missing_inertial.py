from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


def carries_mass(ctx: UrdfContext, link_name: str) -> bool:
    """True if the link, or a link welded to it by fixed joints, has an <inertial>."""
    stack, seen = [link_name], set()
    while stack:
        name = stack.pop()
        if name in seen:
            continue
        seen.add(name)
        el = ctx.link(name)
        if el is not None and ctx.inertial_of(el) is not None:
            return True
        stack.extend(j.child for j in ctx.joints_by_parent.get(name, ()) if j.type == "fixed" and j.child)
    return False


class MissingInertial(Rule):
    """
    What it does:
    Reports a link moved by a non-fixed joint that has no <inertial>, neither itself nor
    on a link welded to it by fixed joints. A link without geometry between two moving
    joints (a virtual link composing two axes) is reported at info level.

    Why is this bad?
    Gazebo drops links without inertia (and the joints to them); dynamics libraries
    (Pinocchio RNEA, MoveIt's gravity compensation) compute wrong torques. Kinematics is
    not affected: KDL builds its tree without inertials.

    Example:
    <link name="forearm"><visual>...</visual><collision>...</collision></link>

    Use instead:
    <link name="forearm"><inertial><mass value="1.2"/><inertia ixx="0.01" ixy="0" ixz="0"
    iyy="0.01" iyz="0" izz="0.002"/></inertial>...</link>
    """

    code, name, severity, target = "U401", "missing-inertial", Severity.WARNING, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        from armtool.lint import kinematics_only

        if kinematics_only.has_no_inertials(ctx):
            yield ctx.finding(self, ctx.root, kinematics_only.description(ctx)).with_severity(Severity.INFO)
            return
        for link, name in ctx.link_name.items():
            if name is None or not ctx.is_moved(name) or carries_mass(ctx, name):
                continue
            has_geometry = link.find("visual") is not None or link.find("collision") is not None
            virtual = not has_geometry and any(j.moves for j in ctx.joints_by_parent.get(name, ()))
            finding = ctx.finding(
                self,
                link,
                f"link '{name}' is moved by a joint but has no <inertial>"
                + (" (a virtual link between two joints?)" if virtual else ""),
                attr="name",
                hint="add <inertial> with its mass and inertia (from CAD), or silence it with <!-- armtool: ignore[U401] -->",
            )
            if virtual:
                finding = finding.with_severity(Severity.INFO)
            yield finding
