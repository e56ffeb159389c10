"""--moveit-config on ik-bench and traj: one reading of the package (RobotOptions.moveit_package),
so both commands give a URDF passed beside it the package's xacro arguments alike."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from armtool.cli import app
from armtool.cli.options import RobotOptions
from armtool.errors import ArmtoolError

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "fixtures" / "robots" / "clean_arm_moveit_config"
CLEAN_URDF = ROOT / "fixtures" / "robots" / "clean_arm" / "urdf" / "clean_arm.urdf"
runner = CliRunner()


@pytest.fixture
def package_and_xacro(tmp_path: Path) -> tuple[Path, Path]:
    """A copy of the bundled package whose .setup_assistant gives `velocity:=1.5`, and a xacro of
    the arm that needs that argument."""
    pkg = tmp_path / "pkg"
    shutil.copytree(PACKAGE, pkg)
    setup = pkg / ".setup_assistant"
    setup.write_text(setup.read_text().replace('xacro_args: ""', 'xacro_args: "velocity:=1.5"'))
    text = CLEAN_URDF.read_text().replace(
        '<robot name="clean_arm">', '<robot name="clean_arm" xmlns:xacro="http://www.ros.org/wiki/xacro">'
    )
    xacro = tmp_path / "arm.urdf.xacro"
    xacro.write_text(text.replace('velocity="2.0"', 'velocity="$(arg velocity)"', 1))
    return pkg, xacro


def test_the_given_urdf_wins_and_takes_the_package_arguments(package_and_xacro: tuple[Path, Path]) -> None:
    pkg, xacro = package_and_xacro
    options = RobotOptions(None, None)
    found, urdf = options.moveit_package(pkg, xacro, "--urdf URDF")
    assert urdf == xacro and found.urdf != xacro
    assert options.xacro_args(urdf, found.urdf_xacro_args) == {"velocity": "1.5"}
    assert RobotOptions(["velocity:=0.5"], None).xacro_args(urdf, found.urdf_xacro_args) == {"velocity": "0.5"}


def test_no_urdf_anywhere_names_the_commands_option(tmp_path: Path) -> None:
    pkg = tmp_path / "pkg"
    shutil.copytree(PACKAGE, pkg)
    setup = pkg / ".setup_assistant"
    setup.write_text(setup.read_text().replace("package: clean_arm", "package: no_such_description"))
    with pytest.raises(ArmtoolError) as raised:
        RobotOptions(None, None).moveit_package(pkg, None, "--urdf URDF")
    assert "no_such_description" in raised.value.what and raised.value.hint == "pass --urdf URDF too"


def test_ik_bench_and_traj_read_the_package_alike(package_and_xacro: tuple[Path, Path], tmp_path: Path) -> None:
    pkg, xacro = package_and_xacro
    bench = runner.invoke(
        app, ["ik-bench", str(xacro), "--moveit-config", str(pkg), "--samples", "5", "--no-batch", "--format", "json"]
    )
    assert bench.exit_code == 0, bench.output
    path = tmp_path / "path.csv"
    path.write_text(
        "joint1_rad,joint2_rad,joint3_rad,joint4_rad,joint5_rad,joint6_rad\n0,-0.6,1.2,0,0.9,0\n0.2,-0.5,1.2,0,0.9,0\n"
    )
    timed = runner.invoke(
        app,
        ["traj", "time", str(path), "--urdf", str(xacro), "--moveit-config", str(pkg), "-o", str(tmp_path / "t.csv")],
    )
    assert timed.exit_code == 0, timed.output
