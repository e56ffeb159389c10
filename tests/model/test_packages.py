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


def _count_scandir(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Every directory the resolver lists, in order (os.scandir is how it walks a tree)."""
    import os

    import armtool.model.packages as packages

    listed: list[str] = []
    real = os.scandir

    def counting(path: str | Path) -> object:
        listed.append(str(path))
        return real(path)

    monkeypatch.setattr(packages.os, "scandir", counting)
    return listed


def _installed_example_robot_data(tmp_path: Path) -> Path:
    """example-robot-data as its wheel installs it: share/example-robot-data, whose package.xml
    names another package, among many other installed packages in site-packages."""
    site = tmp_path / "venv" / "lib" / "python3.11" / "site-packages"
    share = site / "cmeel.prefix" / "share"
    erd = make_package(share / "example-robot-data", "example_robot_descriptions")
    (erd / "robots" / "panda_description" / "urdf").mkdir(parents=True)
    for i in range(40):
        (site / f"module_{i}" / "sub" / "deeper").mkdir(parents=True)
        (share / f"other_{i}" / "cmake").mkdir(parents=True)
    return erd


def test_an_installed_package_is_found_by_its_enclosing_share_directory_without_a_scan(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    erd = _installed_example_robot_data(tmp_path)
    listed = _count_scandir(monkeypatch)
    urdf_dir = erd / "robots" / "panda_description" / "urdf"
    assert PackageResolver().find("example-robot-data", near=urdf_dir) == erd
    assert listed == []  # the cheap lookup: no directory of site-packages was listed


def test_a_scan_never_walks_site_packages_or_an_install_space(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    erd = _installed_example_robot_data(tmp_path)
    repo = tmp_path / "repo"
    (repo / ".git").mkdir(parents=True)
    config = make_package(repo / "src" / "arm_moveit_config", "arm_moveit_config")
    make_package(repo / "install" / "share" / "arm_description", "arm_description")
    (repo / "src" / "tools" / ".venv" / "lib" / "python3.11" / "site-packages" / "x").mkdir(parents=True)
    colcon_install = repo / "src" / "ws_install"
    make_package(colcon_install / "share" / "hidden_description", "hidden_description")
    (colcon_install / "local_setup.bash").write_text("")
    listed = _count_scandir(monkeypatch)
    resolver = PackageResolver()
    assert resolver.find("missing_description", near=config) is None
    assert resolver.find("missing_too", near=erd / "robots" / "panda_description" / "urdf") is None
    assert not [p for p in listed if "site-packages" in p or "install" in Path(p).parts or "share" in Path(p).parts]
    assert str(colcon_install) in listed and str(colcon_install / "share") not in listed


def test_a_workspace_is_scanned_at_most_once_per_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    ws = tmp_path / "ws" / "src"
    packages = [make_package(ws / group / f"pkg_{group}_{i}", f"pkg_{group}_{i}") for group in "abc" for i in range(5)]
    for pkg in packages:
        (pkg / "urdf").mkdir()
    listed = _count_scandir(monkeypatch)
    resolver = PackageResolver()
    for pkg in packages:  # one file per package, each naming a package that exists and one that does not
        assert resolver.find("pkg_c_4", near=pkg / "urdf") == ws / "c" / "pkg_c_4"
        assert resolver.find("no_such_package", near=pkg / "urdf") is None
    assert len(listed) == len(set(listed))  # no directory listed twice
    assert str(ws) in listed


def test_known_names_include_the_workspace_and_the_installed_share(tmp_path: Path) -> None:
    erd = _installed_example_robot_data(tmp_path)
    assert "other_3" in PackageResolver().known_names(erd / "robots" / "panda_description" / "urdf")
    ws = tmp_path / "ws"
    (ws / ".git").mkdir(parents=True)
    make_package(ws / "foo_description2", "foo_description2")
    config = make_package(ws / "foo_moveit_config", "foo_moveit_config")
    assert {"foo_description2", "foo_moveit_config"} <= set(PackageResolver().known_names(config))


def test_package_root_looks_at_levels_directories_when_capped(tmp_path: Path) -> None:
    from armtool.model.packages import package_root

    pkg = make_package(tmp_path / "pkg", "pkg")
    deep = pkg / "a" / "b"
    deep.mkdir(parents=True)
    assert package_root(deep) == pkg
    assert package_root(deep, 3) == pkg  # b, a, pkg
    assert package_root(deep, 2) is None
