"""The kinematic tree of a URDF as text (like ROS's `check_urdf`), Graphviz dot (like `urdf_to_graphviz`) or Mermaid.

Each moving joint shows its limits, velocity and effort included: `velocity="0"` makes a joint
unplannable (time parameterization divides by it) and `effort="0"` leaves controllers and
simulators unable to move it, so a zero is marked ZERO, and a revolute or prismatic joint without
them (urdfdom rejects a `<limit>` without effort or velocity) says so.

Plain lxml, no numpy: `armtool tree` must start as fast as `armtool lint`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from lxml import etree


@dataclass(frozen=True)
class TreeJoint:
    name: str
    type: str
    parent: str
    child: str
    xyz: str
    rpy: str
    axis: str | None  # None for fixed/floating/planar joints
    lower: str | None
    upper: str | None
    mimic: str | None
    velocity: str | None = None  # <limit velocity>, as written (rad/s or m/s)
    effort: str | None = None  # <limit effort>, as written (N·m or N)
    has_limit: bool = False  # the joint has a <limit> element


@dataclass
class Tree:
    robot: str
    links: list[str]
    joints: list[TreeJoint]
    roots: list[str] = field(default_factory=list)
    children: dict[str, list[TreeJoint]] = field(default_factory=dict)


def _attr(el: etree._Element | None, name: str, default: str) -> str:
    value = el.get(name) if el is not None else None
    return " ".join((value or default).split())


def read_tree(root: etree._Element) -> Tree:
    """Links, joints and parent → child structure of a <robot> element (file order kept)."""
    links = [el.get("name", "") for el in root.findall("link")]
    joints = []
    for el in root.findall("joint"):
        parent, child = el.find("parent"), el.find("child")
        origin, axis, limit, mimic = el.find("origin"), el.find("axis"), el.find("limit"), el.find("mimic")
        kind = el.get("type", "")
        moving = kind in ("revolute", "continuous", "prismatic")
        joints.append(TreeJoint(
            el.get("name", ""), kind,
            parent.get("link", "") if parent is not None else "", child.get("link", "") if child is not None else "",
            _attr(origin, "xyz", "0 0 0"),
            _attr(origin, "rpy", "0 0 0"),
            _attr(axis, "xyz", "1 0 0") if moving else None,
            limit.get("lower") if limit is not None and kind in ("revolute", "prismatic") else None,
            limit.get("upper") if limit is not None and kind in ("revolute", "prismatic") else None,
            mimic.get("joint") if mimic is not None else None,
            limit.get("velocity") if limit is not None and moving else None,
            limit.get("effort") if limit is not None and moving else None,
            limit is not None,
        ))  # fmt: skip
    tree = Tree(root.get("name", ""), links, joints)
    child_links = {j.child for j in joints}
    tree.roots = [name for name in links if name not in child_links]
    for j in joints:
        tree.children.setdefault(j.parent, []).append(j)
    return tree


def _is_zero(value: str) -> bool:
    try:
        return float(value) == 0.0
    except ValueError:
        return False


def _rate(j: TreeJoint, what: str, value: str | None, unit: str) -> str | None:
    """`velocity 2 rad/s`, `velocity 0 rad/s (ZERO)`, or `no velocity` where urdfdom needs one."""
    if value is None:
        needed = j.type in ("revolute", "prismatic") or (j.type == "continuous" and j.has_limit)
        return f"no {what}" if needed else None
    value = " ".join(value.split())
    return f"{what} {value} {unit}" + (" (ZERO)" if _is_zero(value) else "")


def _describe(j: TreeJoint) -> str:
    parts = [j.type]
    if j.axis is not None:
        parts.append(f"axis [{j.axis}]")
    if j.lower is not None or j.upper is not None:
        parts.append(f"limits [{j.lower or '0'}, {j.upper or '0'}]")
    prismatic = j.type == "prismatic"
    for what, value, unit in (
        ("velocity", j.velocity, "m/s" if prismatic else "rad/s"),
        ("effort", j.effort, "N" if prismatic else "N·m"),
    ):
        if j.axis is not None and (shown := _rate(j, what, value, unit)) is not None:
            parts.append(shown)
    if j.mimic:
        parts.append(f"mimics {j.mimic}")
    return ", ".join(parts)


def render_text(tree: Tree) -> str:
    """check_urdf's view: robot name, root, and every link under its parent, with the joint between them."""
    kinds: dict[str, int] = {}
    for j in tree.joints:
        kinds[j.type] = kinds.get(j.type, 0) + 1
    summary = ", ".join(f"{n} {k}" for k, n in sorted(kinds.items()))
    lines = [f"robot name is: {tree.robot}",
             f"{len(tree.links)} links, {len(tree.joints)} joints" + (f" ({summary})" if summary else "")]  # fmt: skip
    if len(tree.roots) != 1:
        lines.append(
            f"warning: {len(tree.roots)} root links ({', '.join(tree.roots) or 'none'}); a URDF has exactly one"
        )
    seen: set[str] = set()

    def walk(link: str, prefix: str) -> None:
        kids = tree.children.get(link, [])
        for i, j in enumerate(kids):
            last = i == len(kids) - 1
            lines.append(f"{prefix}{'└── ' if last else '├── '}{j.child}  ← {j.name} ({_describe(j)})")
            if j.child in seen:
                lines.append(f"{prefix}{'    ' if last else '│   '}(loop: {j.child} appears again)")
                continue
            seen.add(j.child)
            walk(j.child, prefix + ("    " if last else "│   "))

    for root in tree.roots:
        lines.append(f"root link: {root} has {len(tree.children.get(root, []))} child(ren)")
        seen.add(root)
        walk(root, "")
    orphans = [j for j in tree.joints if j.parent not in tree.links or j.child not in tree.links]
    for j in orphans:
        lines.append(
            f"warning: joint {j.name} connects {j.parent or '?'} → {j.child or '?'}, which is not a link of the robot"
        )
    return "\n".join(lines)


def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def render_dot(tree: Tree) -> str:
    """urdf_to_graphviz's graph: links as boxes, joints as ellipses, origins on the edges."""
    out = [f"digraph {_quote(tree.robot or 'robot')} {{", "  node [shape=box];"]
    for link in tree.links:
        out.append(f"  {_quote(link)};")
    out.append("  node [shape=ellipse, color=blue, fontcolor=blue];")
    for j in tree.joints:
        out.append(f"  {_quote('joint:' + j.name)} [label={_quote(j.name + chr(10) + _describe(j))}];")
    for j in tree.joints:
        label = f"xyz: {j.xyz}\\nrpy: {j.rpy}"
        out.append(f'  {_quote(j.parent)} -> {_quote("joint:" + j.name)} [label="{label}"];')
        out.append(f"  {_quote('joint:' + j.name)} -> {_quote(j.child)};")
    out.append("}")
    return "\n".join(out)


def _mermaid_id(name: str, ids: dict[str, str]) -> str:
    if name not in ids:
        ids[name] = f"L{len(ids)}_" + re.sub(r"[^A-Za-z0-9_]", "_", name)
    return ids[name]


def _mermaid_text(text: str) -> str:
    return text.replace('"', "#quot;")


def render_mermaid(tree: Tree) -> str:
    """A Mermaid flowchart (renders in GitHub Markdown): links as boxes, joints on the edges."""
    ids: dict[str, str] = {}
    out = ["graph TD"]
    for link in tree.links:
        out.append(f'  {_mermaid_id(link, ids)}["{_mermaid_text(link)}"]')
    for j in tree.joints:
        label = _mermaid_text(f"{j.name} ({_describe(j)})")
        out.append(f'  {_mermaid_id(j.parent, ids)} -->|"{label}"| {_mermaid_id(j.child, ids)}')
    return "\n".join(out)
