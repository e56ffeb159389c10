"""[tool.armtool.lint] in pyproject.toml, --select/--ignore, and inline ignore comments."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from armtool.cli import app
from armtool.errors import ArmtoolError
from armtool.lint.config import load_config
from armtool.lint.engine import LintOptions, lint_paths
from tests.lint.helpers import LINK, revolute, robot

DEGREES = robot(
    '<link name="base"/>\n'
    + LINK.format(name="l1")
    + "\n"
    + revolute(
        "j1", "base", "l1", limit='lower="-1" upper="1" effort="10" velocity="0"', extra='<origin rpy="0 0 90"/>'
    )
)


def lint_with(tmp_path: Path, toml: str, text: str = DEGREES) -> list[tuple[str, str]]:
    (tmp_path / "pyproject.toml").write_text(toml)
    (tmp_path / "urdf").mkdir(exist_ok=True)
    path = tmp_path / "urdf" / "r.urdf"
    path.write_text(text)
    cfg = load_config(tmp_path / "pyproject.toml")
    return [(f.code, f.severity.value) for f in lint_paths([path], LintOptions(config=cfg)).findings]


def test_default_reports_both(tmp_path: Path) -> None:
    assert sorted(lint_with(tmp_path, "")) == [("U203", "error"), ("U301", "warning")]


def test_select_ignore_severity_and_per_file(tmp_path: Path) -> None:
    assert lint_with(tmp_path, '[tool.armtool.lint]\nselect = ["U3"]\n') == [("U301", "warning")]
    assert lint_with(tmp_path, '[tool.armtool.lint]\nignore = ["non-positive-velocity"]\n') == [("U301", "warning")]
    assert sorted(lint_with(tmp_path, '[tool.armtool.lint]\nseverity = { U301 = "error" }\n')) == [
        ("U203", "error"),
        ("U301", "error"),
    ]
    assert lint_with(tmp_path, '[tool.armtool.lint]\nper-file-ignores = { "urdf/*.urdf" = ["U203"] }\n') == [
        ("U301", "warning")
    ]


@pytest.mark.parametrize(
    "toml",
    [
        '[tool.armtool.lint]\nselect = ["Q999"]\n',
        '[tool.armtool.lint]\nselekt = ["U"]\n',
        '[tool.armtool.lint]\nseverity = { U301 = "fatal" }\n',
        "[tool.armtool.lint\n",
    ],
)
def test_bad_config_is_a_clear_error(tmp_path: Path, toml: str) -> None:
    (tmp_path / "pyproject.toml").write_text(toml)
    with pytest.raises(ArmtoolError) as err:
        load_config(tmp_path / "pyproject.toml")
    assert "pyproject.toml" in (err.value.where or "")


def test_inline_ignore_comment_silences_next_element(tmp_path: Path) -> None:
    text = DEGREES.replace("<joint", "<!-- armtool: ignore[U301] -->\n<joint")
    assert lint_with(tmp_path, "", text) == [("U203", "error")]
    everything = DEGREES.replace("<joint", "<!-- armtool: ignore -->\n<joint")
    assert lint_with(tmp_path, "", everything) == []


def test_cli_select_fail_on_and_exit_zero(tmp_path: Path) -> None:
    path = tmp_path / "r.urdf"
    path.write_text(DEGREES)
    runner = CliRunner()
    assert runner.invoke(app, ["lint", str(path)]).exit_code == 1
    assert runner.invoke(app, ["lint", "--select", "U301", str(path)]).exit_code == 0
    assert runner.invoke(app, ["lint", "--select", "U301", "--fail-on", "warning", str(path)]).exit_code == 1
    assert runner.invoke(app, ["lint", "--exit-zero", str(path)]).exit_code == 0


XACRO_ROBOT = """<robot name="$(arg name)" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="name" default=""/>
  <link name="base"/>
</robot>
"""


def test_per_file_xacro_args_package_paths_and_urdf_pairing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "urdf").mkdir()
    (tmp_path / "urdf" / "ur.urdf.xacro").write_text(
        XACRO_ROBOT.replace("<link", '<xacro:include filename="$(find ur_meshes)/m.xacro"/>\n  <link')
    )
    meshes = tmp_path / "vendor" / "ur_meshes"
    meshes.mkdir(parents=True)
    (meshes / "package.xml").write_text("<package><name>ur_meshes</name></package>")
    (meshes / "m.xacro").write_text('<robot xmlns:xacro="http://www.ros.org/wiki/xacro"/>')
    (tmp_path / "srdf").mkdir()
    (tmp_path / "srdf" / "robot.srdf").write_text(
        '<robot name="ur"><group name="g"><link name="base"/></group></robot>'
    )
    toml = """[lint]
package-paths = ["vendor"]
[lint.xacro-args]
"urdf/*.urdf.xacro" = { name = "ur" }
[lint.urdf]
"srdf/robot.srdf" = "urdf/ur.urdf.xacro"
"""
    (tmp_path / "armtool.toml").write_text(toml)
    monkeypatch.chdir(tmp_path)
    assert lint_paths([tmp_path], LintOptions(config=load_config())).findings == []
    (tmp_path / "armtool.toml").write_text("[lint]\n")  # without the settings: X001 and S002
    assert {f.code for f in lint_paths([tmp_path], LintOptions(config=load_config())).findings} == {"X001", "S002"}


def test_pyproject_takes_the_same_keys(tmp_path: Path) -> None:
    (tmp_path / "pyproject.toml").write_text('[tool.armtool.lint]\nxacro-args = { "*.xacro" = ["name:=r"] }\n')
    cfg = load_config(tmp_path / "pyproject.toml")
    assert cfg.xacro_args_for(tmp_path / "a" / "robot.urdf.xacro") == {"name": "r"}


def test_bad_xacro_args_table_is_a_clear_error(tmp_path: Path) -> None:
    (tmp_path / "armtool.toml").write_text('[lint]\nxacro-args = { "*.xacro" = 3 }\n')
    with pytest.raises(ArmtoolError) as err:
        load_config(tmp_path / "armtool.toml")
    assert "armtool.toml" in (err.value.where or "")


PROJECT = '# a project that uses armtool\n[project]\nname = "arm"\n\n[tool.black]\nline-length = 100\n\n'


@pytest.mark.parametrize(
    ("name", "toml", "says", "line"),
    [
        ("pyproject.toml", 'tool.armtool = "lint"\n' + PROJECT, "[tool.armtool] must be a table, not a string", 1),
        ("pyproject.toml", '[tool]\nblack = {}\narmtool = "lint"\n', "[tool.armtool] must be a table, not a string", 3),
        ("pyproject.toml", 'tool = { armtool = ["lint"] }\n', "[tool.armtool] must be a table, not a list", 1),
        ("pyproject.toml", PROJECT + "[[tool.armtool]]\nlint = {}\n", "[tool.armtool] must be a table, not a list", 8),
        ("pyproject.toml", 'tool = "armtool"\n', "[tool] must be a table, not a string", 1),
        ("pyproject.toml", '[tool.armtool]\nlint = "strict"\n', "[tool.armtool.lint] must be a table, not a string", 2),
        ("pyproject.toml", PROJECT + "[[tool.armtool.lint]]\n", "[tool.armtool.lint] must be a table, not a list", 8),
        ("pyproject.toml", '[tool.armtool]\nselect = ["U1"]\n', "unknown key(s) in [tool.armtool]: select", 2),
        ("armtool.toml", 'lint = "strict"\n', "[lint] must be a table, not a string", 1),
        ("armtool.toml", 'select = ["U1"]\n', "unknown key(s) in armtool.toml: select", 1),
        ("armtool.toml", 'tool.armtool = "lint"\n', "armtool.toml holds [tool.armtool]", 1),
        ("armtool.toml", '[tool.armtool.lint]\nselect = ["U1"]\n', "armtool.toml holds [tool.armtool]", 1),
    ],
)
def test_armtool_settings_that_are_not_tables_are_a_config_error_exit_2(
    tmp_path: Path, name: str, toml: str, says: str, line: int
) -> None:
    """`[tool.armtool]` written as a string was refused without its line; armtool's keys one level
    too high (`[tool.armtool]` then `select = ...`) were ignored with exit 0."""
    from tests.lint.test_hostile_lint import invoke

    (tmp_path / name).write_text(toml)
    (tmp_path / "r.urdf").write_text(DEGREES)
    code, _out, err = invoke("lint", "r.urdf", cwd=tmp_path)  # an ArmtoolError: exit 2, as main() makes it
    assert code == 2, err
    assert says in err
    with pytest.raises(ArmtoolError) as info:
        load_config(tmp_path / name)
    assert info.value.where == f"{tmp_path / name}:{line}"


@pytest.mark.parametrize(
    ("toml", "says", "line"),
    [
        (
            'select = "U3"\nxacro-args = ["name:=ur"]\n',
            "'xacro-args' must be a table of glob = { name = value }, not a list",
            2,
        ),
        ('per-file-ignores = ["U401"]\n', "'per-file-ignores' must be a table of glob = [codes], not a list", 1),
        (
            '\nper-file-ignores = { "urdf/*.urdf" = { U401 = true } }\n',
            "'per-file-ignores.urdf/*.urdf' must be a list of rule codes, not a table",
            2,
        ),
        ('select = [["U"]]\n', "'select' must be a list of rule codes, not a list holding a list", 1),
        ("ignore = 401\n", "'ignore' must be a list of rule codes, not a number", 1),
        ('fail-on = ["error"]\n', "'fail-on' must be a severity (a string), not a list", 1),
        ('severity = ["U401"]\n', "'severity' must be a table of code = \"error|warning|info\", not a list", 1),
        ("package-paths = [1]\n", "'package-paths' must be a list of directories (strings)", 1),
        ('urdf = ["urdf/arm.urdf"]\n', "'urdf' must be a table of glob = \"path\", not a list", 1),
        (
            '\n[tool.armtool.lint.srdf]\n"config/*.yaml" = 3\n',
            "'srdf.config/*.yaml' must be a path (a string), not a number",
            3,
        ),
        (
            '\n[tool.armtool.lint.severity]\nU401 = ["error"]\n',
            "'severity.U401' must be a severity (a string), not a list",
            3,
        ),
        ('doc = """\nselect = 3\n"""\n', "unknown key(s) in [tool.armtool.lint]: doc", 1),
    ],
)
def test_a_value_of_the_wrong_shape_is_refused_at_its_line(tmp_path: Path, toml: str, says: str, line: int) -> None:
    """A table where a list belongs, a list where a string belongs: refused with file:line, never read as empty."""
    path = tmp_path / "pyproject.toml"
    path.write_text("[tool.armtool.lint]\n" + toml)
    with pytest.raises(ArmtoolError) as info:
        load_config(path)
    assert says in info.value.what and info.value.where == f"{path}:{line + 1}"


def test_invalid_toml_names_its_line_and_column(tmp_path: Path) -> None:
    path = tmp_path / "pyproject.toml"
    path.write_text('[tool.armtool.lint]\nselect = ["U3"\nignore = []\n')
    with pytest.raises(ArmtoolError) as info:
        load_config(path)
    assert info.value.what.startswith("invalid TOML: ") and info.value.where == f"{path}:3:1"
