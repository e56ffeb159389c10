from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext


class ChainTipNotBelowBase(Rule):
    """
    What it does:
    Reports a group <chain> whose tip_link is not a descendant of its base_link in the URDF
    tree (both links exist), including a chain whose tip is its base.

    Why is this bad?
    KDL, TRAC-IK and the other chain solvers need a serial chain going down the tree from
    base to tip. A reversed chain (tip above base) gives a group with the wrong joints: MoveIt
    adds the joint above the tip as well. A chain from a link to itself adds no joints, and
    MoveIt drops the group. These are errors.

    A sideways chain (tip on another branch) is a warning: MoveIt's RobotModel builds the group
    on purpose, up from the base to the links' common ancestor and down to the tip (a chain
    "from one end-effector to another"), so the group loads and plans; but it is not a serial
    chain, and the chain IK plugins (KDL, TRAC-IK) refuse to initialise for it.

    Example:
    <chain base_link="tool0" tip_link="base_link"/>

    Use instead:
    <chain base_link="base_link" tip_link="tool0"/>
    """

    code, name, severity, target = "S104", "chain-tip-not-below-base", Severity.ERROR, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        urdf = ctx.urdf
        if urdf is None:
            return
        for group in ctx.elements("group"):
            for el in group:
                if local_tag(el) != "chain":
                    continue
                base, tip = el.get("base_link"), el.get("tip_link")
                if base is None or tip is None or base not in urdf.link_names or tip not in urdf.link_names:
                    continue
                owner = f"group '{group.get('name')}'"
                if base == tip:
                    yield ctx.finding(
                        self,
                        el,
                        f"{owner}: chain base_link and tip_link are both '{tip}': the chain has no joints",
                        attr="tip_link",
                        hint="set tip_link to the tool or flange link below the base",
                    )
                    continue
                if ctx.chain_links(base, tip) is not None:
                    continue
                up = urdf.ancestors(tip)
                message = f"{owner}: chain tip_link '{tip}' is not below base_link '{base}' in {urdf.path.name}"
                base_line = [base, *urdf.ancestors(base)]
                common = next((link for link in up if link in base_line), None)
                if tip in base_line:
                    hint = f'swap them: base_link="{tip}" tip_link="{base}"'
                elif common is not None:
                    message += (
                        f"; MoveIt builds the group up to '{common}' and down again, which is not a serial "
                        "chain: chain IK plugins (KDL, TRAC-IK) reject it"
                    )
                    hint = f'start the chain where the branches meet: base_link="{common}"'
                    yield ctx.finding(self, el, message, attr="tip_link", hint=hint).with_severity(Severity.WARNING)
                    continue
                elif up:
                    hint = f"'{base}' is in another tree; base_link must be above '{tip}', e.g. '{up[-1]}'"
                else:
                    hint = f"'{tip}' is a root link; choose a tip_link below '{base}'"
                yield ctx.finding(self, el, message, attr="tip_link", hint=hint)
