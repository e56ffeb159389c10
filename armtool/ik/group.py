"""MoveIt names for chains: an SRDF group → (base, tip); kinematics.yaml → the group's timeout."""

from __future__ import annotations

from pathlib import Path

from armtool.errors import ArmtoolError
from armtool.lint.suggest import did_you_mean
from armtool.model.xmlsource import XmlSyntaxProblem, parse_xml


def group_chain(srdf: Path, group: str, joint_links: dict[str, tuple[str, str]]) -> tuple[str, str]:
    """(base link, tip link) of an SRDF group given as a <chain>, or as an ordered list of joints."""
    try:
        root = parse_xml(srdf.read_bytes())
    except (OSError, XmlSyntaxProblem) as exc:
        raise ArmtoolError(f"cannot read SRDF: {exc}", str(srdf), f"run `armtool lint {srdf}`") from None
    groups = {el.get("name"): el for el in root.findall("group")}
    el = groups.get(group)
    if el is None:
        names = [g for g in groups if g]
        raise ArmtoolError(f"group '{group}' not in {srdf.name}{did_you_mean(group, names)}", str(srdf), "groups: " + ", ".join(names))
    chain = el.find("chain")
    if chain is not None and chain.get("base_link") and chain.get("tip_link"):
        return chain.get("base_link", ""), chain.get("tip_link", "")
    joints = [j.get("name", "") for j in el.findall("joint")]
    known = [j for j in joints if j in joint_links]
    if known:
        return joint_links[known[0]][0], joint_links[known[-1]][1]
    raise ArmtoolError(f"group '{group}' has no chain or joints armtool can use", str(srdf), "pass --base and --tip")


def group_timeout(kinematics_yaml: Path, group: str) -> float | None:
    """The group's kinematics_solver_timeout in seconds, or None when not set."""
    import yaml

    from armtool.lint.kinematics_context import read_groups

    try:
        groups = read_groups(kinematics_yaml.read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as exc:
        raise ArmtoolError(f"cannot read kinematics.yaml: {exc}", str(kinematics_yaml)) from None
    for g in groups:
        if g.name == group and "kinematics_solver_timeout" in g.settings:
            value = g.settings["kinematics_solver_timeout"].value
            if not isinstance(value, (int, float)) or value <= 0:
                raise ArmtoolError(f"kinematics_solver_timeout of '{group}' is {value!r}", f"{kinematics_yaml}:{g.settings['kinematics_solver_timeout'].line}", "a positive number of seconds")
            return float(value)
    return None
