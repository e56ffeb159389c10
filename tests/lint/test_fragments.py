"""Include-only xacro fragments (armtool.lint.fragments, X003, issue 27 item 4): a file another
file of the package includes, which does not stand alone, is checked through its includer, never
as a robot with untrue U101/U103 errors."""

from __future__ import annotations

from pathlib import Path

from armtool.lint.engine import LintOptions, lint_paths
from armtool.lint.finding import Finding
from tests.lint.helpers import LINK, revolute

XACRO = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
FRAGMENT = f"""<robot {XACRO}>
  {LINK.format(name="hand")}
  {revolute("wrist_to_hand", "wrist", "hand", limit='lower="-1" upper="1" effort="10" velocity="0"')}
</robot>
"""
ROBOT = f"""<robot name="arm" {XACRO}>
  <xacro:arg name="with_hand" default="true"/>
  {LINK.format(name="base")}
  {LINK.format(name="wrist")}
  {revolute("j1", "base", "wrist")}
  <xacro:if value="$(arg with_hand)">
    <xacro:include filename="$(find arm_description)/urdf/hand.urdf.xacro"/>
  </xacro:if>
</robot>
"""


def _package(tmp_path: Path) -> Path:
    pkg = tmp_path / "arm_description"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>arm_description</name></package>")
    (pkg / "urdf" / "hand.urdf.xacro").write_text(FRAGMENT)
    (pkg / "urdf" / "arm.urdf.xacro").write_text(ROBOT)
    return pkg


def _lint(paths: list[Path], tmp_path: Path, **options: object) -> list[tuple[str, str, int]]:
    found: list[Finding] = lint_paths(paths, LintOptions(package_paths=[tmp_path], **options)).findings  # type: ignore[arg-type]
    return [(Path(f.path).name, f.code, f.line) for f in found if f.code != "U402"]


def test_a_fragment_linted_with_its_includer_is_checked_through_it(tmp_path: Path) -> None:
    pkg = _package(tmp_path)
    # the fragment's defect (velocity 0) once, from the includer's expansion; no U101/U103
    assert _lint([pkg], tmp_path) == [("hand.urdf.xacro", "X003", 1), ("hand.urdf.xacro", "U203", 3)]


def test_a_fragment_linted_alone_is_checked_through_its_includer(tmp_path: Path) -> None:
    pkg = _package(tmp_path)
    found = lint_paths([pkg / "urdf" / "hand.urdf.xacro"], LintOptions(package_paths=[tmp_path])).findings
    assert [(f.code, f.line) for f in found] == [("X003", 1), ("U203", 3)]
    assert "included by" in found[0].message and "arm.urdf.xacro" in found[0].message


def test_a_fragment_its_includer_leaves_out_is_said_to_be_unchecked(tmp_path: Path) -> None:
    pkg = _package(tmp_path)
    found = lint_paths(
        [pkg / "urdf" / "hand.urdf.xacro"], LintOptions(package_paths=[tmp_path], xacro_args={"with_hand": "false"})
    ).findings
    assert [(f.code, f.severity.value) for f in found] == [("X003", "info")]
    assert "not checked" in found[0].message


def test_a_file_nothing_includes_keeps_its_findings(tmp_path: Path) -> None:
    pkg = _package(tmp_path)
    (pkg / "urdf" / "arm.urdf.xacro").unlink()
    assert {"U101", "U203"} <= {c for _, c, _ in _lint([pkg / "urdf" / "hand.urdf.xacro"], tmp_path)}


def test_an_srdf_fragment_using_the_includers_argument(tmp_path: Path) -> None:
    """franka_ros's panda_moveit_config/config/arm.xacro: `$(arg arm_id)` that only panda.srdf.xacro declares."""
    config = tmp_path / "cfg_moveit_config" / "config"
    config.mkdir(parents=True)
    (config.parent / "package.xml").write_text("<package><name>cfg_moveit_config</name></package>")
    (config / "arm.xacro").write_text(f'<robot {XACRO}><group name="$(arg arm_id)_arm"/></robot>')
    (config / "robot.srdf.xacro").write_text(
        f'<robot name="r" {XACRO}><xacro:arg name="arm_id" default="r"/>'
        '<xacro:include filename="$(find cfg_moveit_config)/config/arm.xacro"/></robot>'
    )
    codes = {c for _, c, _ in _lint([config], tmp_path)}
    assert "X001" not in codes and "X003" in codes
