"""What SRDF rules see: the SRDF's groups and the URDF they refer to (None when it was not found)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from lxml import etree

from armtool.lint.context import FileContext, UrdfContext
from armtool.lint.finding import Finding
from armtool.lint.locate import Locator, display_path, local_tag
from armtool.lint.rule import Rule, Target

_SRDF_ONLY = frozenset({"S103"})  # rules that compare the SRDF with itself, not with the URDF


class SrdfContext(FileContext):
    target = Target.SRDF

    def __init__(self, path: Path, root: etree._Element, locator: Locator, urdf: UrdfContext | None) -> None:
        super().__init__(path, locator)
        self.root = root
        self.urdf = urdf
        # True when the URDF is the user's or MoveIt's choice (--urdf, the configuration,
        # .setup_assistant), False when armtool picked it among the files beside the SRDF.
        self.urdf_given = False
        self.groups: dict[str, etree._Element] = {}
        for el in root:
            if local_tag(el) == "group" and el.get("name") and el.get("name") not in self.groups:
                self.groups[el.get("name")] = el

    def finding(self, rule: Rule | type[Rule], el: etree._Element, message: str, **kwargs: Any) -> Finding:
        """A finding that says which URDF the SRDF was checked against (it was found, not given)."""
        if self.urdf is not None and rule.code not in _SRDF_ONLY and self.urdf.path.name not in message:
            message = f"{message} (URDF: {display_path(self.urdf.path)})"
        return super().finding(rule, el, message, **kwargs)

    def elements(self, tag: str) -> list[etree._Element]:
        return [el for el in self.root if local_tag(el) == tag]

    def chain_links(self, base: str, tip: str) -> list[str] | None:
        """Links from base to tip along the URDF tree (both included), or None if tip is not below base."""
        if self.urdf is None:
            return None
        if base == tip:
            return [base]
        up = self.urdf.ancestors(tip)
        if base not in up:
            return None
        return list(reversed([tip, *up[: up.index(base) + 1]]))

    def group_links(self, name: str, _seen: frozenset[str] = frozenset()) -> set[str]:
        """Links of a group, as MoveIt builds it: its links, joints' child links, chains, subgroups."""
        group = self.groups.get(name)
        if group is None or self.urdf is None or name in _seen:
            return set()
        urdf = self.urdf
        links: set[str] = set()
        for el in group:
            tag, ref = local_tag(el), el.get("name")
            if tag == "link" and ref:
                links.add(ref)
            elif tag == "joint" and ref:
                joint = urdf.joint(ref)
                if joint is not None and joint.child:
                    links.add(joint.child)
            elif tag == "chain":
                chain = self.chain_links(el.get("base_link", ""), el.get("tip_link", ""))
                if chain:
                    links.update(chain[1:])
            elif tag == "group" and ref:
                links |= self.group_links(ref, _seen | {name})
        return links

    def group_joints(self, name: str, _seen: frozenset[str] = frozenset()) -> list[str]:
        """Joint names of a group in tree order: listed joints, joints along chains, subgroups' joints."""
        group = self.groups.get(name)
        if group is None or self.urdf is None or name in _seen:
            return []
        urdf = self.urdf
        out: dict[str, None] = {}
        for el in group:
            tag, ref = local_tag(el), el.get("name")
            if tag == "joint" and ref and urdf.joint(ref) is not None:
                out[ref] = None
            elif tag == "link" and ref:
                for joint in urdf.joints_by_child.get(ref, ()):
                    if joint.name:
                        out[joint.name] = None
            elif tag == "chain":
                chain = self.chain_links(el.get("base_link", ""), el.get("tip_link", ""))
                for link in (chain or [])[1:]:
                    for joint in urdf.joints_by_child.get(link, ()):
                        if joint.name:
                            out[joint.name] = None
            elif tag == "group" and ref:
                for joint_name in self.group_joints(ref, _seen | {name}):
                    out[joint_name] = None
        return list(out)
