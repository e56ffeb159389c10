"""--fix edits text in place (comments, layout kept); --diff writes nothing."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from armtool.cli import app

BROKEN = """<?xml version="1.0"?>
<!-- keep this comment -->
<robot name="r">
  <link name="base"/>
  <link name="l1"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <joint name="j1"   type="revolute">
    <parent link="base"/> <child link="l1"/>
    <origin xyz="0 0 0.1"   rpy="0 0 -270"/>  <!-- degrees -->
    <axis xyz="0 0 2"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
"""


def test_diff_shows_fixes_and_writes_nothing(tmp_path: Path) -> None:
    path = tmp_path / "r.urdf"
    path.write_text(BROKEN)
    result = CliRunner().invoke(app, ["lint", "--diff", str(path)])
    assert result.exit_code == 1
    assert '-    <origin xyz="0 0 0.1"   rpy="0 0 -270"/>  <!-- degrees -->' in result.stdout
    assert '+    <axis xyz="0 0 1"/>' in result.stdout
    assert path.read_text() == BROKEN


def test_fix_applies_safe_edits_and_keeps_everything_else(tmp_path: Path) -> None:
    path = tmp_path / "r.urdf"
    path.write_text(BROKEN)
    result = CliRunner().invoke(app, ["lint", "--fix", str(path)])
    assert result.exit_code == 0, result.stdout
    fixed = path.read_text()
    # -270 rad wrapped keeps the same rotation: -270 + 43 * 2π = 0.1769682087 (not the degrees reading).
    assert fixed == BROKEN.replace('rpy="0 0 -270"', 'rpy="0 0 0.1769682087"').replace('xyz="0 0 2"', 'xyz="0 0 1"')
    assert "All checks passed" in result.stdout
    again = CliRunner().invoke(app, ["lint", str(path)])
    assert again.exit_code == 0


def test_fix_keeps_file_mode(tmp_path: Path) -> None:
    path = tmp_path / "r.urdf"
    path.write_text(BROKEN)
    path.chmod(0o640)
    CliRunner().invoke(app, ["lint", "--fix", str(path)])
    assert path.stat().st_mode & 0o777 == 0o640
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]


def _joint(name: str, child: str, axis: str) -> str:
    return (
        f'<joint name="{name}" type="revolute"><parent link="base"/><child link="{child}"/>'
        f'<axis xyz="{axis}"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
    )


LINK = '<link name="{}"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>'


def test_fix_lands_on_its_own_element_when_many_share_a_line(tmp_path: Path) -> None:
    # A generated URDF on one line, two joints with the same non-unit axis: both get fixed (the
    # line-based search found the first <axis> of the line twice).
    one_line = (
        '<robot name="r"><link name="base"/>'
        + LINK.format("l1")
        + LINK.format("l2")
        + _joint("j1", "l1", "0 0 2")
        + _joint("j2", "l2", "0 0 2")
        + "</robot>\n"
    )
    path = tmp_path / "r.urdf"
    path.write_text(one_line)
    result = CliRunner().invoke(app, ["lint", "--fix", str(path)])
    assert path.read_text() == one_line.replace('xyz="0 0 2"', 'xyz="0 0 1"'), result.stdout


def test_fix_never_edits_a_comment(tmp_path: Path) -> None:
    text = (
        '<robot name="r"><link name="base"/>'
        + LINK.format("l1")
        + _joint("j1", "l1", "0 0 2").replace("<axis", '<!-- was: <axis xyz="0 0 2"/> --><axis')
        + "</robot>\n"
    )
    path = tmp_path / "r.urdf"
    path.write_text(text)
    CliRunner().invoke(app, ["lint", "--fix", str(path)])
    assert path.read_text() == text.replace('--><axis xyz="0 0 2"/>', '--><axis xyz="0 0 1"/>')


def test_fix_keeps_crlf_and_single_quotes(tmp_path: Path) -> None:
    text = BROKEN.replace('<axis xyz="0 0 2"/>', "<axis xyz='0 0 2'/>").replace("\n", "\r\n")
    path = tmp_path / "r.urdf"
    path.write_bytes(text.encode())
    CliRunner().invoke(app, ["lint", "--fix", str(path)])
    fixed = path.read_bytes().decode()
    assert fixed == text.replace('rpy="0 0 -270"', 'rpy="0 0 0.1769682087"').replace("'0 0 2'", "'0 0 1'")


def test_fix_in_a_xacro_finds_its_element_among_others_on_the_line(tmp_path: Path) -> None:
    xacro = (
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:property name="m" value="1"/>\n  <link name="base"/>\n  '
        + LINK.format("l1").replace('value="1"', 'value="${m}"')
        + "\n  "
        + LINK.format("l2")
        + "\n  "
        + _joint("j1", "l1", "0 0 1")
        + _joint("j2", "l2", "0 2 0")
        + "\n</robot>\n"
    )
    path = tmp_path / "r.urdf.xacro"
    path.write_text(xacro)
    result = CliRunner().invoke(app, ["lint", "--fix", str(path)])
    assert path.read_text() == xacro.replace('xyz="0 2 0"', 'xyz="0 1 0"'), result.stdout


def test_fix_counts_characters_as_utf8_when_the_declaration_says_otherwise(tmp_path: Path) -> None:
    # A common mislabel: the declaration says ISO-8859-1, the editor saved UTF-8. --fix reads UTF-8,
    # so its offsets must count UTF-8 characters (counting in the declared encoding shifted the edit).
    text = BROKEN.replace('<?xml version="1.0"?>', '<?xml version="1.0" encoding="ISO-8859-1"?>').replace(
        "keep this comment", "Müller, Größe, café"
    )
    path = tmp_path / "r.urdf"
    path.write_bytes(text.encode("utf-8"))
    result = CliRunner().invoke(app, ["lint", "--fix", str(path)])
    assert result.exit_code == 0, result.stdout
    expected = text.replace('rpy="0 0 -270"', 'rpy="0 0 0.1769682087"').replace('xyz="0 0 2"', 'xyz="0 0 1"')
    assert path.read_bytes() == expected.encode("utf-8")


def test_fix_leaves_a_file_that_is_not_utf8_unchanged(tmp_path: Path) -> None:
    text = BROKEN.replace('<?xml version="1.0"?>', '<?xml version="1.0" encoding="ISO-8859-1"?>').replace(
        "keep this comment", "Größe"
    )
    path = tmp_path / "r.urdf"
    path.write_bytes(text.encode("latin-1"))
    result = CliRunner().invoke(app, ["lint", "--fix", str(path)])
    assert result.exit_code == 0  # warnings only
    assert "U303" in result.stdout and "U301" in result.stdout  # reported, not fixed
    assert path.read_bytes() == text.encode("latin-1")
