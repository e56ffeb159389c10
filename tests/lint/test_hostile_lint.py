"""Issue 14 for `armtool lint`, `rules`, `expand` and the xacro loader: one regression test per
finding (silent no-ops, hangs, memory, internal errors, messages), then property-based runs over
mutated URDF, SRDF, kinematics.yaml and pyproject.toml files through the CLI in-process.

tests/lint/test_hostile_input.py holds the older hostile cases (entities, big files, symlink loops).
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

import armtool.model.xacro_source as xacro_source
from armtool.cli import app
from armtool.errors import ArmtoolError
from armtool.lint import engine
from armtool.lint.engine import LintOptions, lint_paths
from armtool.lint.finding import Finding
from tests.lint.test_hostile_input import no_traceback, robot_urdf, run_cli

REPO = Path(__file__).resolve().parents[2]
CLEAN = REPO / "fixtures" / "robots" / "clean_arm"
XACRO_NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def invoke(*args: str, cwd: Path | None = None) -> tuple[int, str, str]:
    """`armtool ARGS` in-process: (exit code, stdout, stderr). An ArmtoolError is exit 2, as
    `armtool.cli.main` makes it; any other exception fails the test."""
    old = Path.cwd()
    if cwd is not None:
        os.chdir(cwd)
    try:
        result = CliRunner().invoke(app, list(args))
    finally:
        os.chdir(old)
    exc = result.exception
    if isinstance(exc, ArmtoolError):
        return 2, result.stdout, str(exc)
    assert exc is None or isinstance(exc, SystemExit), repr(exc)
    return result.exit_code, result.stdout, result.stderr


def lint(path: Path, **options: object) -> list[Finding]:
    return lint_paths([path], LintOptions(**options)).findings  # type: ignore[arg-type]


@pytest.fixture
def arm(tmp_path: Path) -> Path:
    """A copy of the clean fixture package (URDF, SRDF, kinematics.yaml)."""
    shutil.copytree(CLEAN, tmp_path / "clean_arm")
    return tmp_path / "clean_arm"


# ---- 7. silent no-ops: a selection that checks nothing ---------------------------------------------


@pytest.mark.parametrize("select", ["U999", ",", "", " , ", "rpy-out-of-rang"])
def test_select_that_names_no_rule_is_exit_2(select: str, arm: Path) -> None:
    code, out, err = invoke("lint", "--select", select, str(arm / "urdf" / "clean_arm.urdf"))
    assert code == 2 and "All checks passed" not in out
    assert "--select" in err


def test_unknown_select_suggests_the_closest_rule(arm: Path) -> None:
    code, _, err = invoke("lint", "--select", "rpy-out-of-rang", str(arm / "urdf" / "clean_arm.urdf"))
    assert code == 2 and "did you mean 'rpy-out-of-range'" in err


def test_unknown_ignore_is_exit_2(arm: Path) -> None:
    code, _, err = invoke("lint", "--ignore", "U99", str(arm / "urdf" / "clean_arm.urdf"))
    assert code == 2 and "U99" in err


def test_known_selectors_still_work(arm: Path) -> None:
    code, out, _ = invoke("lint", "--select", "U3,S101,rpy-out-of-range", "--ignore", "U5", str(arm / "urdf"))
    assert code == 0 and "All checks passed" in out


def test_empty_select_in_config_is_exit_2(arm: Path) -> None:
    (arm / "pyproject.toml").write_text("[tool.armtool.lint]\nselect = []\n")
    code, out, err = invoke("lint", "urdf/clean_arm.urdf", cwd=arm)
    assert code == 2 and "'select' is empty" in err and out == ""


def _moveit_config(arm: Path, kinematics: str) -> Path:
    path = arm / "config" / "kinematics.yaml"
    path.write_text(kinematics)
    return path


def test_kinematics_yaml_that_is_a_list_is_k001(arm: Path) -> None:
    path = _moveit_config(arm, "- arm\n- kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n")
    (f,) = lint(path)
    assert (f.code, f.line) == ("K001", 1) and "a list" in f.message


@pytest.mark.parametrize("value, shown", [("5", "'5'"), ("[1, 2]", "a list"), ("", "has no settings")])
def test_group_that_is_not_a_mapping_is_k106(value: str, shown: str, arm: Path) -> None:
    path = _moveit_config(arm, f"# the arm\narm: {value}\n")
    (f,) = lint(path)
    assert (f.code, f.line) == ("K106", 2) and "'arm'" in f.message and shown in f.message
    mixed = _moveit_config(
        arm, f"arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\ngripper: {value}\n"
    )
    assert [(g.code, g.line) for g in lint(mixed)] == [("K106", 3)]


def test_other_tools_kinematics_yaml_still_passes(tmp_path: Path, arm: Path) -> None:
    # Franka-style parameters and a DH table: no SRDF group of those names, so not MoveIt's.
    assert lint(_moveit_config(arm, "a1: 0.025\nc1: 0.4\n")) == []
    (tmp_path / "dh_kinematics.yaml").write_text("- {a: 0, d: 0.1}\n- {a: 0.4, d: 0}\n")
    assert lint(tmp_path / "dh_kinematics.yaml") == []


# ---- 4. memory and time ------------------------------------------------------------------------------


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_fifo_in_a_linted_directory_is_skipped(arm: Path) -> None:
    os.mkfifo(arm / "urdf" / "evil.urdf")
    proc = run_cli("lint", str(arm / "urdf"), timeout=60)  # a hang fails through TimeoutExpired
    assert proc.returncode == 0 and "evil.urdf" not in proc.stdout, proc.stdout + proc.stderr
    no_traceback(proc)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_fifo_named_on_the_command_line_is_exit_2(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "evil.urdf")
    proc = run_cli("lint", str(tmp_path / "evil.urdf"), timeout=60)
    assert proc.returncode == 2 and "not a regular file" in proc.stderr
    no_traceback(proc)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_fifo_named_package_xml_does_not_block_package_lookup(arm: Path, tmp_path: Path) -> None:
    other = tmp_path / "ws" / "ghost"
    other.mkdir(parents=True)
    os.mkfifo(other / "package.xml")
    proc = run_cli("lint", "--package-path", str(tmp_path / "ws"), str(arm / "urdf" / "clean_arm.urdf"), timeout=60)
    assert proc.returncode in (0, 1)
    no_traceback(proc)


def _xacro(tmp_path: Path, body: str, name: str = "arm.urdf.xacro") -> Path:
    path = tmp_path / name
    path.write_text(f'<?xml version="1.0"?>\n<robot name="arm" {XACRO_NS}>\n  <link name="base"/>\n{body}\n</robot>\n')
    return path


def test_xacro_including_dev_zero_is_x001_at_the_include(tmp_path: Path) -> None:
    path = _xacro(tmp_path, '  <xacro:include filename="/dev/zero"/>')
    (f,) = lint(path)
    assert (f.code, f.line) == ("X001", 4) and "not a regular file" in f.message


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_xacro_including_a_fifo_is_x001(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "parts.xacro")
    (f,) = lint(_xacro(tmp_path, '  <xacro:include filename="parts.xacro"/>'))
    assert f.code == "X001" and "not a regular file" in f.message


def test_xacro_include_over_the_size_limit_is_x001(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(xacro_source, "MAX_INCLUDE_BYTES", 1000)
    (tmp_path / "parts.xacro").write_text(f"<robot {XACRO_NS}><!-- {'x' * 2000} --></robot>\n")
    (f,) = lint(_xacro(tmp_path, '  <xacro:include filename="parts.xacro"/>'))
    assert f.code == "X001" and "limit" in f.message


def test_expanded_document_over_the_limit_is_x001(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(xacro_source, "MAX_EXPANDED_CHARS", 5000)
    (f,) = lint(_xacro(tmp_path, "  <link name=\"${'x' * 10000}\"/>"))
    assert f.code == "X001" and "expanded document" in f.message


@pytest.mark.skipif(not hasattr(os, "fork"), reason="the time bound needs fork")
def test_endless_xacro_expression_is_x001_within_the_time_bound(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(xacro_source, "TIMEOUT_S", 2.0)
    start = time.monotonic()
    # An endless loop of small steps, which the expression bounds (armtool/model/xacro_eval.py) let
    # through: the time bound stops it.
    endless = "python.sum(x * y for x in python.range(10**7) for y in python.range(10**7))"
    (f,) = lint(_xacro(tmp_path, f'  <link name="${{{endless}}}"/>'))
    assert f.code == "X001" and "did not finish within 2 s" in f.message
    assert time.monotonic() - start < 20


def test_huge_power_in_a_xacro_is_x001_at_once_without_the_time_bound(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # In-process expansion (as where fork is not possible): nothing could stop a C-level 9**387420489.
    monkeypatch.setattr(xacro_source, "_can_fork", lambda: False)
    start = time.monotonic()
    (f,) = lint(_xacro(tmp_path, '  <link name="${str(9**9**9)}"/>'))
    assert f.code == "X001" and "9 ** 387420489 would have about 1.23e+09 bits" in f.message
    assert time.monotonic() - start < 10


@pytest.mark.skipif(not hasattr(os, "fork") or not Path("/proc/self/statm").exists(), reason="needs fork and /proc")
def test_xacro_expression_filling_memory_is_x001(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(xacro_source, "MEMORY_HEADROOM_BYTES", 512 * 1024**2)
    (f,) = lint(_xacro(tmp_path, "  <link name=\"${'x'.ljust(4 * 1024**3)}\"/>"))
    assert f.code == "X001" and ("MemoryError" in f.message or "memory" in f.message)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="the bound needs fork")
def test_xacro_child_that_dies_is_said_as_it_died_not_as_out_of_memory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import signal

    def die(*_: object) -> None:
        os.kill(os.getpid(), signal.SIGKILL)

    monkeypatch.setattr(xacro_source, "_expand_text", die)  # the forked child runs this and is killed
    (f,) = lint(_xacro(tmp_path, '  <link name="a"/>'))
    assert f.code == "X001" and "killed by signal 9" in f.message and "memory" not in f.message


def test_expand_command_reports_the_bound_as_exit_2(tmp_path: Path) -> None:
    path = _xacro(tmp_path, '  <xacro:include filename="/dev/zero"/>')
    code, out, err = invoke("expand", str(path))
    assert code == 2 and "not a regular file" in err and out == ""


# ---- 5. internal errors ---------------------------------------------------------------------------------


def test_deeply_nested_kinematics_yaml_is_k001(arm: Path) -> None:
    path = _moveit_config(arm, "arm: " + "[" * 5000 + "]" * 5000 + "\n")
    (f,) = lint(path)
    assert f.code == "K001" and "nested too deeply" in f.message


def _many(tmp_path: Path, n: int = 20) -> list[Path]:
    paths = []
    for i in range(n):
        path = tmp_path / f"r{i:02d}.urdf"
        path.write_text(robot_urdf(2))
        paths.append(path)
    return paths


def test_one_file_too_deep_in_a_parallel_run_is_that_files_finding(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    paths = _many(tmp_path)
    original = engine.Linter.lint_file

    def lint_file(self: engine.Linter, path: Path) -> list[Finding]:
        if path.name == "r07.urdf":
            raise RecursionError("maximum recursion depth exceeded")
        return original(self, path)

    monkeypatch.setattr(engine.Linter, "lint_file", lint_file)
    monkeypatch.setattr(engine, "_cpus", lambda: 2)  # forked workers even on one core
    found = lint_paths(paths, LintOptions()).findings
    assert [(Path(f.path).name, f.code) for f in found] == [("r07.urdf", "U001")]
    assert "nested too deeply" in found[0].message


def test_unexpected_crash_in_a_parallel_run_names_the_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    paths = _many(tmp_path)
    original = engine.Linter.lint_file

    def lint_file(self: engine.Linter, path: Path) -> list[Finding]:
        if path.name == "r11.urdf":
            raise KeyError("boom")
        return original(self, path)

    monkeypatch.setattr(engine.Linter, "lint_file", lint_file)
    monkeypatch.setattr(engine, "_cpus", lambda: 2)
    with pytest.raises(RuntimeError, match=r"r11\.urdf: KeyError"):
        lint_paths(paths, LintOptions())


def test_non_utf8_pyproject_is_exit_2_with_the_line(arm: Path) -> None:
    (arm / "pyproject.toml").write_bytes(b'[tool.armtool.lint]\nselect = ["\xff"]\n')
    code, _, err = invoke("lint", "urdf/clean_arm.urdf", cwd=arm)
    assert code == 2 and "not UTF-8" in err and "pyproject.toml:2" in err


@pytest.mark.parametrize(
    "toml, says",
    [
        (
            'tool = "armtool"\n',
            "[tool] must be a table, not a string (/pyproject.toml:1)",
        ),  # PEP 518: [tool] is a table
        ("[tool]\narmtool = 1\n", "[tool.armtool] must be a table, not a number (/pyproject.toml:2)"),
        ("[tool.armtool]\nlint = 3\n", "[tool.armtool.lint] must be a table, not a number (/pyproject.toml:2)"),
    ],
)
def test_pyproject_with_armtool_not_a_table(toml: str, says: str, arm: Path) -> None:
    (arm / "pyproject.toml").write_text(toml)
    code, _, err = invoke("lint", "urdf/clean_arm.urdf", cwd=arm)
    assert code == 2, err
    message, where = says.split(" (")
    assert message in err and f"{where}" in err and "internal error" not in err


def test_huge_axis_is_reported_with_a_finite_fix(tmp_path: Path) -> None:
    path = tmp_path / "robot.urdf"
    path.write_text(robot_urdf(1).replace('<axis xyz="0 0 1"/>', '<axis xyz="1e200 1e200 0"/>'))
    (f,) = lint(path)
    assert f.code == "U303" and f.edit is not None and "0.7071067812 0.7071067812 0" in f.edit.replacement


def test_fix_of_a_non_utf8_file_leaves_it_unchanged(tmp_path: Path) -> None:
    path = tmp_path / "robot.urdf"
    text = (
        robot_urdf(1)
        .replace('rpy="0 0 0"', 'rpy="0 0 7"')
        .replace('<robot name="arm">', '<robot name="arm"><!-- caf\xe9 -->')
    )
    path.write_bytes(
        text.replace('<?xml version="1.0"?>', '<?xml version="1.0" encoding="ISO-8859-1"?>').encode("latin-1")
    )
    before = path.read_bytes()
    code, out, _err = invoke("lint", "--fix", str(path))
    assert code == 0 and "U301" in out and path.read_bytes() == before


def test_fix_that_cannot_write_is_exit_2_naming_the_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "robot.urdf"
    path.write_text(robot_urdf(1).replace('rpy="0 0 0"', 'rpy="0 0 7"'))
    before = path.read_bytes()

    def refuse(src: object, dst: object) -> None:
        raise PermissionError(13, "Permission denied", str(dst))

    monkeypatch.setattr(os, "replace", refuse)  # as for a read-only file or directory (root ignores chmod)
    code, _, err = invoke("lint", "--fix", str(path))
    assert code == 2 and "cannot write" in err and "robot.urdf" in err
    assert path.read_bytes() == before
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]


# ---- 9. messages ------------------------------------------------------------------------------------


def test_non_finite_and_malformed_numbers_name_the_joint(tmp_path: Path) -> None:
    path = tmp_path / "robot.urdf"
    path.write_text(
        robot_urdf(2)
        .replace('<axis xyz="0 0 1"/>', '<axis xyz="0 nan 0.1"/>', 1)
        .replace('<mass value="1"/>', '<mass value="one"/>', 1)
    )
    by_code = {f.code: f.message for f in lint(path)}
    assert by_code["U304"].startswith("joint 'j1': <axis xyz=\"0 nan 0.1\">")
    assert by_code["U305"].startswith("link 'l1': <mass value=\"one\">")


def test_xacro_error_is_at_its_line_not_line_1(tmp_path: Path) -> None:
    path = _xacro(tmp_path, '\n\n  <link name="${undefined_property}"/>')
    (f,) = lint(path)
    assert (f.code, f.line) == ("X001", 6) and "undefined_property" in f.message
    (tmp_path / "parts.xacro").write_text(f'<robot {XACRO_NS}>\n\n  <link name="${{nowhere}}"/>\n</robot>\n')
    (g,) = lint(_xacro(tmp_path, '\n  <xacro:include filename="parts.xacro"/>', name="top.urdf.xacro"))
    assert (g.code, g.line) == ("X001", 5) and "parts.xacro:3" in g.message


# ---- property-based: mutated inputs through the CLI ---------------------------------------------------

SRDF = (CLEAN / "config" / "clean_arm.srdf").read_bytes()
KINEMATICS = (CLEAN / "config" / "kinematics.yaml").read_bytes()
URDF = (CLEAN / "urdf" / "clean_arm.urdf").read_bytes()
HOSTILE_BITS = [
    b"nan",
    b"inf",
    b"-1e400",
    b"1e308",
    b"9" * 400,
    b"\x00",
    b"\xff\xfe",
    b"<",
    b"&",
    b"]]>",
    b"<a>" * 300,
    b"[" * 3000,
    b"{" * 3000,
    b"- " * 2000,
    b"&x;",
    b"${9**9}",
    b"\n\t",
    b"\xe9",
]


@st.composite
def mutated(draw: st.DrawFn, base: bytes) -> bytes:
    data = bytearray(base)
    for _ in range(draw(st.integers(1, 4))):
        op = draw(st.sampled_from(["flip", "insert", "replace", "truncate"]))
        at = draw(st.integers(0, len(data)))
        if op == "flip" and data:
            i = min(at, len(data) - 1)
            data[i] ^= 1 << draw(st.integers(0, 7))
        elif op == "truncate":
            del data[at:]
        else:
            blob = draw(st.one_of(st.sampled_from(HOSTILE_BITS), st.binary(min_size=1, max_size=16)))
            data[at : at + (len(blob) if op == "replace" else 0)] = blob
    return bytes(data)


def _digest(root: Path) -> dict[str, str]:
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(root.rglob("*"))
        if p.is_file()
    }


def _check_cli(root: Path, *args: str) -> None:
    """The CLI's contract on any input: exit 0/1/2, no crash, inputs unchanged, JSON on stdout, bounded time."""
    before = _digest(root)
    start = time.monotonic()
    code, out, err = invoke("lint", "--format", "json", *args, cwd=root)
    assert time.monotonic() - start < 30
    assert code in (0, 1, 2), (code, err)
    assert "Traceback" not in out + err and "internal error" not in out + err
    if code in (0, 1):
        assert isinstance(json.loads(out)["findings"], list)
    else:
        assert out == ""
    assert _digest(root) == before


def _package(tmp: Path, name: str, data: bytes) -> Path:
    root = tmp / f"case-{hashlib.sha256(data).hexdigest()[:12]}-{time.monotonic_ns()}"
    shutil.copytree(CLEAN, root)
    (root / name).write_bytes(data)
    return root


SETTINGS = settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture]
)


@SETTINGS
@given(data=mutated(URDF))
def test_mutated_urdf(data: bytes, tmp_path: Path) -> None:
    root = _package(tmp_path, "urdf/clean_arm.urdf", data)
    _check_cli(root, "urdf/clean_arm.urdf")


@SETTINGS
@given(data=mutated(SRDF))
def test_mutated_srdf(data: bytes, tmp_path: Path) -> None:
    root = _package(tmp_path, "config/clean_arm.srdf", data)
    _check_cli(root, "config/clean_arm.srdf")


@SETTINGS
@given(
    data=st.one_of(
        mutated(KINEMATICS),
        st.sampled_from(
            [b"- a\n- b\n", b"arm: 5\n", b"7\n", b"arm: .nan\n", b"arm:\n  kinematics_solver_timeout: .inf\n"]
        ),
    )
)
def test_mutated_kinematics_yaml(data: bytes, tmp_path: Path) -> None:
    root = _package(tmp_path, "config/kinematics.yaml", data)
    _check_cli(root, "config/kinematics.yaml")


PYPROJECT = b'[tool.armtool.lint]\nselect = ["U", "S1"]\nignore = ["U502"]\nfail-on = "warning"\n[tool.armtool.lint.severity]\nU301 = "info"\n'
TOML_VALUES = st.sampled_from(
    ["[]", '""', '","', '"U999"', "3", "nan", "inf", "{}", '"armtool"', "[[]]", '"\\u0000"', "true"]
)


@st.composite
def pyprojects(draw: st.DrawFn) -> bytes:
    if draw(st.booleans()):
        return draw(mutated(PYPROJECT))
    key = draw(
        st.sampled_from(
            [
                "select",
                "ignore",
                "fail-on",
                "per-file-ignores",
                "severity",
                "package-paths",
                "xacro-args",
                "urdf",
                "srdf",
                "unknown",
            ]
        )
    )
    section = draw(st.sampled_from(["[tool.armtool.lint]", "[tool.armtool]", "[tool]", ""]))
    return f"{section}\n{key} = {draw(TOML_VALUES)}\n".encode()


@SETTINGS
@given(data=pyprojects())
def test_mutated_pyproject(data: bytes, tmp_path: Path) -> None:
    root = _package(tmp_path, "pyproject.toml", data)
    _check_cli(root, "urdf/clean_arm.urdf", "config/kinematics.yaml")


def test_deeply_nested_pyproject_is_a_message(tmp_path: Path) -> None:
    """Found by test_mutated_pyproject: tomllib raises RecursionError on deep nesting."""
    root = _package(tmp_path, "pyproject.toml", b"[tool.armtool.lint]\nselect = " + b"[" * 5000 + b"\n")
    _check_cli(root, "urdf/clean_arm.urdf", "config/kinematics.yaml")
    code, _out, err = invoke("lint", "--config", str(root / "pyproject.toml"), str(root / "urdf" / "clean_arm.urdf"))
    assert code == 2 and "nested too deeply" in err


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_expand_of_a_fifo_says_what_it_is(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "arm.urdf.xacro")
    code, out, err = invoke("expand", str(tmp_path / "arm.urdf.xacro"))
    assert code == 2 and "not a regular file" in err and out == ""


@SETTINGS
@given(code=st.one_of(st.text(max_size=40), st.sampled_from(["", "[bold]", "u30", "U" + "9" * 50, "ALL", "\x00"])))
def test_rules_with_any_argument_is_exit_0_or_2(code: str) -> None:
    if code.startswith("-") or "\x00" in code:
        code = "x" + code.replace("\x00", "")  # an option or a NUL is not an argument a shell can pass
    exit_code, out, err = invoke("rules", code)
    assert exit_code in (0, 2) and "Traceback" not in out + err and "internal error" not in err


@pytest.mark.parametrize(
    ("name", "code"),
    [
        ("arm.urdf", "U001"),
        ("arm.urdf.xacro", "X001"),
        ("arm.srdf", "S001"),
        ("kinematics.yaml", "K001"),
        ("joint_limits.yaml", "L001"),
        ("pilz_cartesian_limits.yaml", "P001"),
        ("ros2_controllers.yaml", "C001"),
    ],
)
def test_a_file_too_deep_to_check_is_its_kinds_loader_finding(
    name: str, code: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def too_deep(self: engine.Linter, path: Path) -> list[Finding]:
        raise RecursionError("maximum recursion depth exceeded")

    monkeypatch.setattr(engine.Linter, "lint_file", too_deep)
    path = tmp_path / name
    path.write_text("x\n")
    (found,) = lint_paths([path], LintOptions()).findings
    assert (found.code, found.message) == (code, "file is nested too deeply for armtool to check")
