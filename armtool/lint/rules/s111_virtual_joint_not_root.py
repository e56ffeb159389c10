from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext


class VirtualJointNotRoot(Rule):
    """
    What it does:
    Reports a `<virtual_joint>` whose `child_link` is not the root link of the URDF.

    Graded by what MoveIt then does. Its child is a link that fixed joints attach to the URDF's
    root, and the virtual joint is fixed (a URDF that already has `world` -> `base_link`, as
    Gazebo wants): MoveIt skips it, and the URDF's fixed joints hold the robot as it would; info
    (moveit2 stopped warning about that very setup, "Silent warning about virtual_joint in Gazebo
    setups"). A planar or floating virtual joint there, or a child that a moving joint carries:
    error.

    Why is this bad?
    A virtual joint attaches the robot's root to the world. MoveIt builds it only for the root
    link (RobotModel::buildRoot): any other child link and MoveIt skips it ("Skipping virtual
    joint ... because its child frame ... does not match the URDF frame"), so groups naming it
    lose it and a mobile base does not move.

    Example:
    <virtual_joint name="world_joint" type="fixed" parent_frame="world" child_link="link1"/>

    Use instead:
    <virtual_joint name="world_joint" type="fixed" parent_frame="world" child_link="base_link"/>
    """

    code, name, severity, target = "S111", "virtual-joint-not-root", Severity.ERROR, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        if ctx.urdf is None:
            return
        roots = ctx.urdf.root_links()
        if len(roots) != 1:
            return  # several roots or a loop: U103 reports the URDF
        root = roots[0]
        for el in ctx.elements("virtual_joint"):
            child = el.get("child_link")
            if child is None or child == root or child not in ctx.urdf.link_names:
                continue  # an unknown link is S102's
            fixed_to_root = root in ctx.urdf.ancestors(child) and not any(
                ctx.urdf.is_moved(link) for link in [child, *ctx.urdf.ancestors(child)]
            )
            harmless = fixed_to_root and (el.get("type") or "").strip().lower() == "fixed"
            finding = ctx.finding(
                self,
                el,
                f"virtual_joint '{el.get('name')}': child_link '{child}' is not the URDF's root link '{root}'; MoveIt skips it"
                + (
                    f" (harmless: fixed joints attach '{child}' to '{root}' as this fixed virtual joint would)"
                    if harmless
                    else ""
                ),
                attr="child_link",
                hint=f'child_link="{root}"' + (", or remove it" if harmless else ""),
            )
            yield finding.with_severity(Severity.INFO) if harmless else finding
