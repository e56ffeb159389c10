"""MoveIt names for chains: an SRDF group → (base, tip) the way MoveIt builds it; kinematics.yaml → its settings.

MoveIt (RobotModel::addJointModelGroup, JointModelGroup, KinematicsPluginLoader) treats a group as
a *set* of joints: the joints of its <chain>s (tip up to base), its <joint>s, the parent joint of
each <link>, and every joint of its subgroups. It sorts them in depth-first tree order; the IK
base frame is the parent link of the first, the tip is the child link of the last. The KDL plugin
only takes a group whose joints form one chain (each joint below the previous one, with nothing
but fixed joints in between). The order the SRDF lists them in means nothing.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from lxml import etree

from armtool.errors import ArmtoolError
from armtool.suggest import did_you_mean

if TYPE_CHECKING:
    from armtool.lint.kinematics_context import GroupSettings as KinematicsGroup


@dataclass(frozen=True)
class GroupChain:
    """What MoveIt would hand its IK plugin for a group: base frame, tip frame and the group's joints in tree order."""

    group: str
    base: str
    tip: str
    joints: tuple[str, ...]  # every joint of the group (fixed ones too), depth-first tree order


@dataclass(frozen=True)
class _Joint:
    name: str
    type: str
    parent: str
    child: str


def _urdf_tree(urdf: etree._Element) -> tuple[dict[str, _Joint], list[str]]:
    """URDF joints by name, and joint names in depth-first order from the root (children in file order)."""
    joints: dict[str, _Joint] = {}
    for el in urdf.findall("joint"):
        parent, child = el.find("parent"), el.find("child")
        if parent is None or child is None:
            continue
        name = el.get("name", "")
        joints[name] = _Joint(name, el.get("type", ""), parent.get("link", ""), child.get("link", ""))
    children: dict[str, list[_Joint]] = {}
    for j in joints.values():
        children.setdefault(j.parent, []).append(j)
    child_links = {j.child for j in joints.values()}
    roots = [el.get("name", "") for el in urdf.findall("link") if el.get("name", "") not in child_links]
    order: list[str] = []
    stack = [j for root in reversed(roots) for j in reversed(children.get(root, []))]
    seen: set[str] = set()
    while stack:
        j = stack.pop()
        if j.name in seen:  # a loop: lint reports it
            continue
        seen.add(j.name)
        order.append(j.name)
        stack.extend(reversed(children.get(j.child, [])))
    return joints, order


def _groups(srdf: etree._Element) -> dict[str, etree._Element]:
    return {el.get("name", ""): el for el in srdf.findall("group") if el.get("name")}


def group_chain(srdf: etree._Element, group: str, urdf: etree._Element, source: str = "SRDF") -> GroupChain:
    """The chain MoveIt's IK plugin gets for `group` of an SRDF (already expanded) on a URDF (already expanded)."""
    groups = _groups(srdf)
    if group not in groups:
        names = sorted(groups)
        raise ArmtoolError(
            f"group '{group}' not in {source}{did_you_mean(group, names)}", source,
            "groups: " + (", ".join(names) if names else "none (is it the right SRDF, and are its xacro arguments given?)"),
        )  # fmt: skip
    joints, order = _urdf_tree(urdf)
    links = {el.get("name", "") for el in urdf.findall("link")}
    by_child = {j.child: j for j in joints.values()}
    virtual = {el.get("name", ""): el for el in srdf.findall("virtual_joint")}
    members: set[str] = set()
    _collect(groups, group, joints, links, by_child, virtual, members, (), source)
    members -= set(virtual)  # a fixed virtual joint: its parent frame coincides with the root link
    if not members:
        raise ArmtoolError(
            f"group '{group}' has no joint of the URDF", source, "pass --base and --tip, or fix the group"
        )
    index = {name: i for i, name in enumerate(order)}
    ordered = sorted(members, key=lambda name: index.get(name, len(index)))
    first, last = joints[ordered[0]], joints[ordered[-1]]
    # One chain: walking up from the last joint reaches every member, and only fixed joints are skipped.
    path: list[str] = []
    cur = last.child
    while cur != first.parent and cur in by_child:
        path.append(by_child[cur].name)
        cur = by_child[cur].parent
    off_path = [name for name in ordered if name not in path]
    skipped = [name for name in path if name not in members and joints[name].type != "fixed"]
    if cur != first.parent or off_path or skipped:
        why = (
            f"joint(s) {', '.join(off_path)} are on another branch"
            if off_path
            else f"moving joint(s) {', '.join(skipped)} between its joints are not in the group"
        )
        raise ArmtoolError(
            f"group '{group}' is not a serial chain ({why}); MoveIt's chain IK plugins (KDL, TRAC-IK) refuse it too",
            source, "pass --base and --tip for the chain to benchmark",
        )  # fmt: skip
    return GroupChain(group, first.parent, last.child, tuple(ordered))


def _collect(
    groups: dict[str, etree._Element], name: str, joints: dict[str, _Joint], links: set[str], by_child: dict[str, _Joint],
    virtual: dict[str, etree._Element], out: set[str], stack: Sequence[str], source: str,
) -> None:  # fmt: skip
    """Add the joints of group `name` to `out`, as MoveIt's addJointModelGroup does."""
    if name in stack:
        raise ArmtoolError(f"groups {' → '.join([*stack, name])} include each other", source, "remove the cycle")
    el = groups.get(name)
    if el is None:
        raise ArmtoolError(
            f"group '{stack[-1]}' names subgroup '{name}', which is not defined{did_you_mean(name, list(groups))}",
            source,
        )
    for chain in el.findall("chain"):
        base, tip = chain.get("base_link", ""), chain.get("tip_link", "")
        for role, link in (("base_link", base), ("tip_link", tip)):
            if link not in links:
                raise ArmtoolError(
                    f"group '{name}': chain {role} '{link}' is not in the URDF{did_you_mean(link, sorted(links))}",
                    source,
                )
        up: list[str] = []
        cur = tip
        while cur != base and cur in by_child:
            up.append(by_child[cur].name)
            cur = by_child[cur].parent
        if cur != base:
            raise ArmtoolError(
                f"group '{name}': chain tip '{tip}' is not below base '{base}' in the URDF",
                source,
                "swap them, or fix the chain",
            )
        out.update(up)
    for j in el.findall("joint"):
        jname = j.get("name", "")
        if jname in joints or jname in virtual:
            if jname in virtual and virtual[jname].get("type", "fixed") != "fixed":
                raise ArmtoolError(
                    f"group '{name}' includes the {virtual[jname].get('type')} virtual joint '{jname}'", source,
                    "a moving base is not a serial chain: pass --base and --tip for the arm",
                )  # fmt: skip
            out.add(jname)
        else:
            raise ArmtoolError(
                f"group '{name}': joint '{jname}' is not in the URDF{did_you_mean(jname, sorted(joints))}", source
            )
    for link in el.findall("link"):
        lname = link.get("name", "")
        if lname not in links:
            raise ArmtoolError(
                f"group '{name}': link '{lname}' is not in the URDF{did_you_mean(lname, sorted(links))}", source
            )
        if lname in by_child:
            out.add(by_child[lname].name)
    for sub in el.findall("group"):
        _collect(groups, sub.get("name", ""), joints, links, by_child, virtual, out, (*stack, name), source)


@dataclass(frozen=True)
class GroupSettings:
    """The settings of one group in kinematics.yaml that ik-bench honours."""

    timeout_s: float | None = None
    position_only: bool = False
    solver_plugin: str | None = None  # kinematics_solver, as written


def kinematics_groups(kinematics_yaml: Path) -> list[str]:
    """The groups a MoveIt kinematics.yaml configures, in file order (any layout)."""
    return [g.name for g in _read_groups(kinematics_yaml)]


def planning_group(kinematics_yaml: Path | None, package: Path) -> str:
    """The group of a MoveIt config package when none is named: the one group its kinematics.yaml
    configures (MoveIt gives an IK solver to those groups only). None or several is an error that
    lists them and says to pass --group (ik-bench and traj cartesian --moveit-config)."""
    configured = kinematics_groups(kinematics_yaml) if kinematics_yaml is not None else []
    if len(configured) != 1:
        raise ArmtoolError(
            f"{len(configured) or 'no'} groups in {kinematics_yaml or 'the package (no kinematics.yaml)'}: "
            "pass --group NAME",
            str(package),
            "groups: " + (", ".join(configured) or "none"),
        )
    return configured[0]


def _read_groups(kinematics_yaml: Path) -> list[KinematicsGroup]:
    """The file's groups, read as `armtool lint` reads them; errors name the file and line."""
    from armtool.lint.kinematics_context import NotAMapping, groups_of
    from armtool.moveit.params import load_document
    from armtool.moveit.substitutions import launch_values

    try:  # `$(arg arm_id)_arm` read as the package's launch fills it in
        return groups_of(load_document(kinematics_yaml, "kinematics.yaml"), launch_values(kinematics_yaml))
    except NotAMapping as exc:
        raise ArmtoolError(
            f"kinematics.yaml is {exc.what}, not a mapping of group names to settings",
            f"{kinematics_yaml}:{exc.line}",
            "write `GROUP:` followed by its settings (kinematics_solver, ...)",
        ) from None


def group_settings(kinematics_yaml: Path, group: str) -> GroupSettings:
    """The group's kinematics_solver_timeout (seconds), position_only_ik and kinematics_solver
    from a MoveIt kinematics.yaml (ROS 1 or ROS 2 layout, read as `armtool lint` reads it).

    The file must hold the group (the user named both): a group it lacks, a group whose value is
    not a mapping, a timeout that is not a finite number of seconds in (0, MAX_TIMEOUT_S]
    (`.inf` would never end a solve) are errors naming the file and line."""
    from armtool.ik import MAX_TIMEOUT_S

    groups = {g.name: g for g in _read_groups(kinematics_yaml)}
    if group not in groups:
        names = sorted(groups)
        raise ArmtoolError(
            f"group '{group}' is not in kinematics.yaml{did_you_mean(group, names)}",
            str(kinematics_yaml),
            "groups: " + (", ".join(names) if names else "none") + "; or leave out --kinematics-yaml",
        )
    g = groups[group]
    if g.not_a_mapping is not None and g.not_a_mapping != "nothing":
        raise ArmtoolError(
            f"group '{group}' in kinematics.yaml is {g.not_a_mapping}, not a mapping of settings",
            f"{kinematics_yaml}:{g.line}",
            "e.g. `kinematics_solver_timeout: 0.005` on the next line, indented",
        )
    timeout = None
    if "kinematics_solver_timeout" in g.settings:
        setting = g.settings["kinematics_solver_timeout"]
        value = setting.value
        where = f"{kinematics_yaml}:{setting.line}"
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ArmtoolError(
                f"kinematics_solver_timeout of '{group}' is {value!r}, not a number",
                where,
                "a number of seconds such as 0.005",
            )
        try:
            seconds = float(value)
        except OverflowError:  # an integer beyond a float's range (YAML integers are unbounded)
            seconds = math.inf
        if not (math.isfinite(seconds) and 0 < seconds <= MAX_TIMEOUT_S):
            raise ArmtoolError(
                f"kinematics_solver_timeout of '{group}' is {value!r}",
                where,
                f"a finite number of seconds > 0 and ≤ {MAX_TIMEOUT_S:g}, such as 0.005",
            )
        timeout = seconds
    position_only = False
    if "position_only_ik" in g.settings:
        flag = g.settings["position_only_ik"].value
        if not isinstance(flag, bool):
            raise ArmtoolError(
                f"position_only_ik of '{group}' is {flag!r}",
                f"{kinematics_yaml}:{g.settings['position_only_ik'].line}",
                "true or false",
            )
        position_only = flag
    plugin = g.settings.get("kinematics_solver")
    return GroupSettings(timeout, position_only, str(plugin.value) if plugin is not None else None)


# MoveIt's IK plugins and the armtool solver that works the same way (None: no counterpart).
def counterpart_solver(plugin: str | None) -> str | None:
    """The built-in solver that stands for a MoveIt kinematics plugin in a benchmark: KDL's
    Newton-Raphson with joint limits, TRAC-IK, or the closed form for an IKFast plugin."""
    if not plugin:
        return None
    lowered = plugin.lower()
    if lowered.startswith("kdl_kinematics_plugin/"):
        return "kdl-nr-jl"
    if lowered.startswith("trac_ik_kinematics_plugin/"):
        return "trac"
    if "ikfast" in lowered:
        return "analytic"
    return None
