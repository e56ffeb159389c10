"""armtool.moveit.params: one reader for MoveIt's YAML layouts, ROS 2 parameter types, launch substitutions."""

from __future__ import annotations

from pathlib import Path

import pytest

from armtool.moveit.params import (
    as_scalar,
    child,
    items,
    moveit_section,
    name_ref,
    parse,
    ros_version,
    scalar_kind,
)

FLAT = "joint_limits:\n  j1: {max_velocity: 1.0}\n"
ROS2 = (
    "/**:\n  ros__parameters:\n    robot_description_planning:\n      joint_limits:\n        j1: {max_velocity: 1.0}\n"
)
NODE = "move_group:\n  ros__parameters:\n    joint_limits:\n      j1: {max_velocity: 1.0}\n"
NAMESPACED = "robot_description_planning:\n  joint_limits:\n    j1: {max_velocity: 1.0}\n"


@pytest.mark.parametrize(("text", "ros2"), [(FLAT, False), (ROS2, True), (NODE, True), (NAMESPACED, False)])
def test_every_layout_gives_the_same_settings(text: str, ros2: bool) -> None:
    section = moveit_section(parse(text), "robot_description_planning")
    assert section.ros2_params is ros2
    limits = child(section.mapping, "joint_limits")
    assert [k for k, _, _ in items(limits)] == ["j1"]


@pytest.mark.parametrize(
    ("text", "kind"),
    [
        ("1", "int"),
        ("-3", "int"),
        ("0x1F", "int"),
        ("1.0", "double"),
        ("1e3", "double"),  # a double for rcl's strtod (PyYAML would say string)
        (".5", "double"),
        (".inf", "double"),
        ("true", "bool"),
        ("yes", "bool"),
        ("abc", "string"),
        ("1_000", "string"),  # strtoll stops at the underscore: not a whole integer
    ],
)
def test_scalars_are_typed_as_ros2_types_them(text: str, kind: str) -> None:
    assert scalar_kind(text, quoted=False) == kind


def test_quoted_and_tagged_scalars_are_strings() -> None:
    root = parse('a: "1.0"\nb: !!str 5\nc: 5\nd:\n')
    kinds = {k: as_scalar(v).kind for k, _, v in items(root)}  # type: ignore[union-attr]
    assert kinds == {"a": "string", "b": "string", "c": "int", "d": "null"}


def test_scalar_offsets_point_at_the_value() -> None:
    text = "x:\n  max_velocity: 12\n"
    scalar = as_scalar(child(child(parse(text), "x"), "max_velocity"))
    assert scalar is not None
    assert (scalar.line, scalar.column) == (2, 17)
    assert text[scalar.start : scalar.end] == "12"
    assert scalar.number() == 12.0


def test_known_substitution_is_replaced() -> None:
    ref = name_ref("$(var tf_prefix)joint_1", {"tf_prefix": "left_"})
    assert ref.resolved == "left_joint_1"
    assert ref.matches(["left_joint_1", "joint_1"]) == ["left_joint_1"]
    assert ref.note() == ""


def test_unknown_substitution_matches_the_rest_of_the_name_and_says_so() -> None:
    ref = name_ref("$(arg prefix)joint_1")
    assert ref.resolved is None and ref.unknown == ("prefix",)
    assert ref.matches(["joint_1", "left_joint_1", "joint_10"]) == ["joint_1", "left_joint_1"]
    assert "matched by the rest of the name" in ref.note()


def test_ros_version_from_package_xml(tmp_path: Path) -> None:
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "package.xml").write_text("<package><buildtool_depend>ament_cmake</buildtool_depend></package>")
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "package.xml").write_text("<package><buildtool_depend>catkin</buildtool_depend></package>")
    (tmp_path / "a" / "config").mkdir()
    assert ros_version(tmp_path / "a" / "config") == 2
    assert ros_version(tmp_path / "b") == 1
    assert ros_version(tmp_path) is None


def test_ros_version_looks_at_six_directories(tmp_path: Path) -> None:
    """A file's own directory and the five above it (a package.xml further up is another tree's)."""
    (tmp_path / "package.xml").write_text("<package><buildtool_depend>ament_cmake</buildtool_depend></package>")
    five_below = tmp_path / "a" / "b" / "c" / "d" / "e"
    (five_below / "f").mkdir(parents=True)
    for directory in (five_below, five_below / "f"):
        (directory / "joint_limits.yaml").write_text("{}\n")
    assert ros_version(five_below / "joint_limits.yaml") == 2  # e, d, c, b, a, then tmp_path: the sixth
    assert ros_version(five_below) == 2
    assert ros_version(five_below / "f" / "joint_limits.yaml") is None  # tmp_path would be the seventh
    assert ros_version(five_below / "f") is None


@pytest.mark.parametrize(
    ("text", "double"),
    [("1", "1.0"), ("-5", "-5.0"), ("+7", "+7.0"), ("0", "0.0"), ("010", "8.0"), ("-010", "-8.0"), ("0x10", "16.0")],
)
def test_an_integer_in_double_form_reads_octal_as_strtoll_does(text: str, double: str) -> None:
    """The fix of L102/P103 (`1` -> `1.0`) keeps the number rcl reads: `010` is octal 8."""
    from armtool.lint.moveit_context import as_double

    scalar = as_scalar(child(parse(f"v: {text}\n"), "v"))
    assert scalar is not None and scalar.kind == "int"
    assert as_double(scalar) == double
