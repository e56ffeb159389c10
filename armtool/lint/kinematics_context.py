"""What kinematics.yaml rules see: each group's settings with line numbers, and the SRDF."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from armtool.lint.context import FileContext
from armtool.lint.locate import Locator
from armtool.lint.rule import Target
from armtool.lint.srdf_context import SrdfContext


@dataclass(frozen=True)
class YamlValue:
    value: Any
    line: int
    column: int


@dataclass
class GroupSettings:
    name: str
    line: int
    column: int
    settings: dict[str, YamlValue] = field(default_factory=dict)
    not_a_mapping: str | None = None  # what stands where the settings belong ("5", "a list", "nothing")
    written: str = ""  # the key as written, when launch substitutions made `name` of it ($(arg arm_id)_arm)


class NotAMapping(Exception):
    """The file's top level (inside ROS 2's wrappers) is not a mapping of groups."""

    def __init__(self, what: str, line: int, column: int) -> None:
        super().__init__(what)
        self.what, self.line, self.column = what, line, column


class KinematicsContext(FileContext):
    target = Target.KINEMATICS

    def __init__(self, path: Path, groups: list[GroupSettings], srdf: SrdfContext | None) -> None:
        super().__init__(path, Locator(path))
        self.groups = groups
        self.srdf = srdf
        self.variant_groups: set[str] = set()  # groups of the SRDF xacro's other argument values


def _plain(node: Any) -> Any:
    """A setting's value. Settings are scalars; lists and maps are not expanded (YAML aliases
    could make a 1 kB file expand to billions of values)."""
    import yaml

    if isinstance(node, yaml.ScalarNode):
        return yaml.safe_load(yaml.serialize(node))
    if isinstance(node, yaml.SequenceNode):
        return "<list>"
    if isinstance(node, yaml.MappingNode):
        return "<mapping>"
    return None


def read_groups(text: str, known: dict[str, str] | None = None) -> list[GroupSettings]:
    """Groups from a MoveIt kinematics.yaml in any layout `armtool.moveit.params` reads (ROS 1
    `arm: {...}`; ROS 2 `/**` or a node name, `ros__parameters`, `robot_description_kinematics`).
    A key's launch substitutions are replaced by the `known` values (armtool.moveit.substitutions).
    Raises yaml.YAMLError, and NotAMapping when the settings are a list or a scalar (an empty
    file has no groups)."""
    from armtool.moveit.params import parse

    return groups_of(parse(text), known)


def groups_of(root: Any, known: dict[str, str] | None = None) -> list[GroupSettings]:
    """read_groups() of a document already parsed (`armtool.moveit.params.parse`)."""
    import yaml

    from armtool.moveit.params import moveit_section, name_ref, shape

    node = moveit_section(root, "robot_description_kinematics").mapping
    if node is None:
        return []
    if not isinstance(node, yaml.MappingNode):
        if shape(node) == "nothing":
            return []
        raise NotAMapping(shape(node), node.start_mark.line + 1, node.start_mark.column + 1)
    groups = []
    for key, value in node.value:
        written = str(key.value)
        resolved = name_ref(written, known).resolved if "$(" in written else written
        group = GroupSettings(resolved or written, key.start_mark.line + 1, key.start_mark.column + 1)
        if resolved is not None and resolved != written:
            group.written = written
        if not isinstance(value, yaml.MappingNode):
            group.not_a_mapping = shape(value)
        else:
            for skey, sval in value.value:
                group.settings[str(skey.value)] = YamlValue(
                    _plain(sval), sval.start_mark.line + 1, sval.start_mark.column + 1
                )
        groups.append(group)
    return groups


def is_moveit_kinematics(groups: list[GroupSettings]) -> bool:
    """A MoveIt kinematics.yaml sets a solver per group (`kinematics_solver*` keys); files merely
    named so (UR's default_kinematics.yaml calibration, Franka's kinematic parameters) do not:
    theirs are mappings of mappings, or of numbers (`a1: 0.025`). A file of entries without
    settings (`arm: 5`) is MoveIt's only if its SRDF has such a group (see `names_srdf_groups`)."""
    return any(key.startswith("kinematics_solver") for group in groups for key in group.settings)


def may_be_unusable_moveit(groups: list[GroupSettings]) -> bool:
    """Entries, none with settings: MoveIt's kinematics.yaml with every group broken (`arm: 5`), or
    another tool's parameters (`a1: 0.025`). The SRDF beside it decides."""
    return bool(groups) and all(group.not_a_mapping is not None for group in groups)


def as_number(value: object) -> float | None:
    """A YAML value as a finite float, or None (strings, booleans, lists, NaN and infinities are not numbers)."""
    import math

    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    number = float(value)
    return number if math.isfinite(number) else None


def not_positive(ctx: KinematicsContext, key: str) -> list[tuple[GroupSettings, YamlValue, str]]:
    """(group, setting, "is 0" / "is 'x', not a number") for each group whose `key` is not a positive number."""
    out = []
    for group in ctx.groups:
        item = group.settings.get(key)
        if item is None:
            continue
        number = as_number(item.value)
        if number is None or number <= 0:
            out.append((group, item, f"is {item.value!r}, not a number" if number is None else f"is {item.value}"))
    return out
