"""Package lookup as ROS does it: by the <name> in package.xml, from --package-path (relative to the
working directory), and in the tree around the file."""

from __future__ import annotations

from pathlib import Path

import pytest

from armtool.model.packages import PackageResolver


def make_package(directory: Path, name: str) -> Path:
    directory.mkdir(parents=True)
    (directory / "package.xml").write_text(f"<package format='3'><name>{name}</name></package>")
    return directory


def test_package_is_found_by_its_package_xml_name_not_its_directory(tmp_path: Path) -> None:
    pkg = make_package(tmp_path / "ws" / "moveit_resources" / "panda_description", "moveit_resources_panda_description")
    resolver = PackageResolver([tmp_path / "ws"])
    assert resolver.find("moveit_resources_panda_description") == pkg
    assert resolver.find("panda_description") is None  # ROS would not find it by its folder either


def test_packages_deep_below_a_package_path_are_found(tmp_path: Path) -> None:
    # moveit2/moveit_planners/test_configs/prbt_pg70_support: four levels below the workspace root
    pkg = make_package(
        tmp_path / "moveit2" / "moveit_planners" / "test_configs" / "prbt_pg70_support",
        "moveit_resources_prbt_pg70_support",
    )
    assert PackageResolver([tmp_path]).find("moveit_resources_prbt_pg70_support") == pkg


def test_relative_package_path_is_taken_from_the_working_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pkg = make_package(tmp_path / "xarm_ros2" / "xarm_description", "xarm_description")
    elsewhere = tmp_path / "robots" / "urdf"
    elsewhere.mkdir(parents=True)
    monkeypatch.chdir(tmp_path)
    found = PackageResolver([Path("xarm_ros2")]).find("xarm_description", near=elsewhere)
    assert found is not None and found.is_absolute() and found.resolve() == pkg.resolve()


def test_relative_ros_package_path_is_taken_from_the_working_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pkg = make_package(tmp_path / "src" / "arm_description", "arm_description")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("ROS_PACKAGE_PATH", "src")
    found = PackageResolver().find("arm_description")
    assert found is not None and found.is_absolute() and found.resolve() == pkg.resolve()


def test_sibling_package_is_found_from_the_tree_around_the_file(tmp_path: Path) -> None:
    # a MoveIt config includes $(find ...) of a package of the same repository, no --package-path;
    # the folder is not the package's name (moveit_resources/panda_description)
    description = make_package(tmp_path / "repo" / "panda_description", "moveit_resources_panda_description")
    config = make_package(tmp_path / "repo" / "panda_moveit_config", "moveit_resources_panda_moveit_config")
    (config / "config").mkdir()
    assert PackageResolver().find("moveit_resources_panda_description", near=config / "config") == description
