"""xacro inputs: findings point into the .xacro sources (call site, macro body), never a temp file."""

from __future__ import annotations

from pathlib import Path

from armtool.lint.engine import LintOptions, lint_paths

MACROS = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="seg" params="name parent mass rpy">
    <link name="${name}">
      <inertial>
        <mass value="${mass}"/>
        <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
      </inertial>
    </link>
    <joint name="${name}_joint" type="revolute">
      <parent link="${parent}"/>
      <child link="${name}"/>
      <origin xyz="0 0 0.1" rpy="${rpy}"/>
      <axis xyz="0 0 1"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/>
    </joint>
  </xacro:macro>
</robot>
"""

MAIN = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="macros.xacro"/>
  <xacro:arg name="prefix" default=""/>
  <link name="$(arg prefix)base"/>
  <xacro:seg name="$(arg prefix)l1" parent="$(arg prefix)base" mass="1" rpy="0 0 0"/>
  <xacro:seg name="$(arg prefix)l2" parent="$(arg prefix)l1" mass="0" rpy="0 0 90"/>
  <joint name="tool" type="fixed">
    <parent link="$(arg prefix)l2"/>
    <child link="tool0"/>
    <origin rpy="0 0 -7"/>
  </joint>
  <link name="tool0"/>
</robot>
"""


def write(tmp_path: Path) -> Path:
    (tmp_path / "macros.xacro").write_text(MACROS)
    main = tmp_path / "arm.urdf.xacro"
    main.write_text(MAIN)
    return main


def test_findings_point_at_call_site_and_name_the_macro_body(tmp_path: Path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.chdir(tmp_path)
    main = write(tmp_path)
    found = lint_paths([main], LintOptions()).findings
    by_code = {(f.code, f.path, f.line) for f in found}
    assert ("U403", "arm.urdf.xacro", 7) in by_code  # mass="0" passed at the call site
    assert ("U301", "arm.urdf.xacro", 7) in by_code  # rpy="0 0 90" passed at the call site
    assert ("U301", "arm.urdf.xacro", 11) in by_code  # literal in the main file
    rpy_call = next(f for f in found if f.code == "U301" and f.line == 7)
    assert "macros.xacro:13" in rpy_call.message
    assert all(not f.path.startswith("/tmp/tmp") for f in found)


def test_safe_fix_only_for_literal_values(tmp_path: Path) -> None:
    main = write(tmp_path)
    found = lint_paths([main], LintOptions()).findings
    literal = next(f for f in found if f.code == "U301" and f.line == 11)
    from_macro = next(f for f in found if f.code == "U301" and f.line == 7)
    assert literal.edit is not None and literal.edit.path == main.resolve()
    assert from_macro.edit is None


def test_xacro_args_are_passed(tmp_path: Path) -> None:
    main = write(tmp_path)
    found = lint_paths([main], LintOptions(xacro_args={"prefix": "left_"})).findings
    assert any("left_l2" in f.message for f in found)


def test_expansion_failure_is_x001_with_xacro_message(tmp_path: Path) -> None:
    main = tmp_path / "bad.urdf.xacro"
    main.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="${undefined_thing}"/></robot>'
    )
    (f,) = lint_paths([main], LintOptions()).findings
    assert f.code == "X001" and "undefined_thing" in f.message


def test_find_package_resolves_through_package_path(tmp_path: Path) -> None:
    pkg = tmp_path / "pkgs" / "arm_description"
    pkg.mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>arm_description</name></package>")
    (pkg / "macros.xacro").write_text(MACROS)
    main = tmp_path / "robot.urdf.xacro"
    main.write_text(MAIN.replace('filename="macros.xacro"', 'filename="$(find arm_description)/macros.xacro"'))
    (f,) = [f for f in lint_paths([main], LintOptions()).findings if f.code == "X001"]
    assert "arm_description" in f.message and f.hint is not None and "--package-path" in f.hint
    found = lint_paths([main], LintOptions(package_paths=[tmp_path / "pkgs"])).findings
    assert "X001" not in {f.code for f in found}


def test_a_missing_package_suggests_the_closest_package_name_around_the_file(tmp_path: Path) -> None:
    (tmp_path / "ws" / ".git").mkdir(parents=True)
    for name in ("foo_description2", "arm_moveit_config"):
        (tmp_path / "ws" / name).mkdir()
        (tmp_path / "ws" / name / "package.xml").write_text(f"<package><name>{name}</name></package>")
    (tmp_path / "ws" / "foo_description2" / "macros.xacro").write_text(MACROS)
    main = tmp_path / "ws" / "arm_moveit_config" / "robot.urdf.xacro"
    main.write_text(MAIN.replace('filename="macros.xacro"', 'filename="$(find foo_description)/macros.xacro"'))
    (f,) = [f for f in lint_paths([main], LintOptions()).findings if f.code == "X001"]
    assert (
        "package 'foo_description' not found for $(find foo_description) "
        f"(did you mean 'foo_description2', in {tmp_path / 'ws' / 'foo_description2'}?)"
    ) in f.message
    assert f.hint is not None and f.hint.startswith("write $(find foo_description2) if that is the package meant")
    main.write_text(MAIN.replace('filename="macros.xacro"', 'filename="$(find gripper_support)/macros.xacro"'))
    (g,) = [f for f in lint_paths([main], LintOptions()).findings if f.code == "X001"]
    assert "did you mean" not in g.message and g.hint is not None and g.hint.startswith("pass --package-path")


def test_a_missing_package_is_suggested_from_its_own_repository_first(tmp_path: Path) -> None:
    """Issue 27 item 7: two repositories side by side (no .git: a corpus, a download folder); the
    close name in the file's own repository wins over a closer one in the unrelated repository."""
    for repo, name in (("sawyer_robot", "sawyer_tools_description"), ("khi_robot", "intera_tool_description")):
        (tmp_path / "src" / repo / name).mkdir(parents=True)
        (tmp_path / "src" / repo / name / "package.xml").write_text(f"<package><name>{name}</name></package>")
    own = tmp_path / "src" / "sawyer_robot" / "sawyer_description"
    own.mkdir()
    (own / "package.xml").write_text("<package><name>sawyer_description</name></package>")
    main = own / "robot.urdf.xacro"
    main.write_text(MAIN.replace('filename="macros.xacro"', 'filename="$(find intera_tools_description)/m.xacro"'))
    (f,) = [f for f in lint_paths([main], LintOptions()).findings if f.code == "X001"]
    where = tmp_path / "src" / "sawyer_robot" / "sawyer_tools_description"
    assert f"(did you mean 'sawyer_tools_description', in {where}?)" in f.message


def test_package_uri_in_include_fails_as_in_xacro_and_says_why(tmp_path: Path) -> None:
    # xacro's get_include_files joins a filename that is not absolute to the including file's
    # directory; it has no package:// scheme (hector_description/robots/quadrotor_base.xacro).
    pkg = tmp_path / "arm_description"
    pkg.mkdir()
    (pkg / "package.xml").write_text("<package><name>arm_description</name></package>")
    (pkg / "macros.xacro").write_text(MACROS)
    main = tmp_path / "robot.urdf.xacro"
    main.write_text(MAIN.replace('filename="macros.xacro"', 'filename="package://arm_description/macros.xacro"'))
    (f,) = [f for f in lint_paths([main], LintOptions(package_paths=[tmp_path])).findings if f.code == "X001"]
    assert f.hint == "xacro does not resolve package:// in <xacro:include filename>: write $(find PKG)/path"


def test_macro_library_alone_is_quiet(tmp_path: Path) -> None:
    lib = tmp_path / "macros.xacro"
    lib.write_text(MACROS)
    assert lint_paths([lib], LintOptions()).findings == []
