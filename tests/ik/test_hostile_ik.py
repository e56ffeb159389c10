"""Hostile input for ik-bench, tree and the chain model (issue 14): every finding in their scope as a
plain regression test, then property-based runs over ik-bench's numeric options and over mutated
URDF, SRDF and kinematics.yaml files.

The CLI runs in-process (CliRunner); an exception other than ArmtoolError or SystemExit is what
`armtool.cli.main` would report as "internal error", so it fails the test. Chains are tiny and
runs short (--samples 5, dls), so the file takes well under a minute.
"""

from __future__ import annotations

import json
import os
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from armtool.cli import app
from armtool.errors import ArmtoolError
from tests.ik.robots import PLANAR_2R

FIXTURE = Path(__file__).resolve().parents[2] / "fixtures" / "robots" / "clean_arm"
URDF = FIXTURE / "urdf" / "clean_arm.urdf"
SRDF = FIXTURE / "config" / "clean_arm.srdf"
runner = CliRunner()
HYPO = settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
QUICK = ["--samples", "5", "--solvers", "dls", "--no-batch"]


def run(*args: str) -> tuple[int, str, str]:
    """Exit code, stdout, error text, as `armtool.cli.main` would give them; any other exception
    fails the test, and so does a RuntimeWarning (numpy overflow, division by zero)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = runner.invoke(app, list(args))
    leaked = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    assert not leaked, (args, leaked)
    exc = result.exception
    if isinstance(exc, ArmtoolError):
        return 2, result.stdout, str(exc)
    if exc is not None and not isinstance(exc, SystemExit):
        raise exc
    return result.exit_code, result.stdout, result.stderr


def planar(tmp_path: Path, text: str = PLANAR_2R, name: str = "planar.urdf") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


# ---------------------------------------------------------------- 5. internal errors


def test_one_joint_chain_has_a_6x1_jacobian() -> None:
    from armtool.model.chain import load_chain

    chain = load_chain(URDF, "base_link", "link1")
    _T, J = chain.fk_jacobian(chain.mid())
    assert J.shape == (6, 1) and chain.jacobian(chain.mid()).shape == (6, 1)
    assert np.allclose(J[:, 0], [0, 0, 0, 0, 0, 1])


ONE_JOINT_SOLVERS = ["dls", "kdl-nr-jl", "kdl-lma", "trac", "lm"]


@pytest.mark.parametrize("solver", ONE_JOINT_SOLVERS)
@pytest.mark.parametrize("base, tip", [("base_link", "link1"), ("gripper_base", "left_finger")])
def test_one_joint_chain_is_benchmarked(solver: str, base: str, tip: str) -> None:
    code, out, err = run(
        "ik-bench",
        str(URDF),
        "--base",
        base,
        "--tip",
        tip,
        "--samples",
        "5",
        "--solvers",
        solver,
        "--timeout",
        "0.05",
        "--format",
        "json",
    )
    assert code == 0, err
    doc = json.loads(out)
    assert len(doc["joints"]) == 1 and doc["solvers"][0]["solver"] == solver


def test_gripper_group_of_the_bundled_fixture_is_a_clear_error() -> None:
    code, _, err = run("ik-bench", str(URDF), "--group", "gripper", "--srdf", str(SRDF), *QUICK)
    assert code == 2 and "not a serial chain" in err


@pytest.mark.parametrize("seed", ["-1", "-123456789", str(2**70)])
def test_any_integer_is_a_seed(tmp_path: Path, seed: str) -> None:
    code, out, err = run("ik-bench", str(planar(tmp_path)), *QUICK, "--seed", seed, "--format", "json")
    assert code == 0, err
    assert json.loads(out)["config"]["rng_seed"] >= 0


def test_huge_axis_is_normalised_without_overflow(tmp_path: Path) -> None:
    from armtool.model.chain import load_chain

    path = planar(tmp_path, PLANAR_2R.replace('<axis xyz="0 0 1"/>', '<axis xyz="1e200 1e200 0"/>', 1))
    chain = load_chain(path)
    assert np.allclose(chain.joints[0].axis, [2**-0.5, 2**-0.5, 0])
    code, out, err = run("ik-bench", str(path), *QUICK, "--format", "json")
    assert code == 0, err
    assert json.loads(out)["solvers"][0]["success_rate"] > 0


LOOP = """<robot name="loop">
  <link name="r"/><link name="a"/><link name="b"/>
  <joint name="ja" type="revolute"><parent link="b"/><child link="a"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="jb" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"""


def test_loop_and_same_base_tip_say_what_is_wrong(tmp_path: Path) -> None:
    code, _, err = run("ik-bench", str(planar(tmp_path, LOOP, "loop.urdf")), *QUICK)
    assert code == 2 and "kinematic loop" in err and "a, b" in err and "between 'r' and 'r'" not in err
    code, _, err = run("ik-bench", str(URDF), "--base", "link2", "--tip", "link2", *QUICK)
    assert code == 2 and "base and tip are the same link 'link2'" in err


def test_same_base_and_tip_from_the_api() -> None:
    """calibrate relays chain_from_xml's message for --base/--flange: it must say what is wrong."""
    from armtool.model.chain import load_chain

    with pytest.raises(ArmtoolError, match="base and tip are the same link 'tool0'"):
        load_chain(URDF, "tool0", "tool0")


def test_several_roots_pick_the_one_with_the_arm(tmp_path: Path) -> None:
    from lxml import etree

    from armtool.model.chain import default_base_tip

    text = PLANAR_2R.replace('<link name="base"/>', '<link name="marker"/><link name="base"/>')
    assert default_base_tip(etree.fromstring(text)) == ("base", "tool")


@pytest.mark.parametrize(
    "edit, what",
    [
        (('<origin xyz="0.5 0 0"/>', '<origin xyz="1e200 0 0"/>'), "joint 'j2' <origin xyz>"),
        (('lower="-3" upper="3"', 'lower="-1e308" upper="1e308"'), "joint 'j1' <limit lower>"),
        (('<origin xyz="0.5 0 0"/>', '<origin xyz="0 nan 0.1"/>'), "joint 'j2' <origin xyz>: bad numbers '0 nan 0.1'"),
    ],
)
def test_numbers_no_robot_has_are_refused_naming_the_joint(tmp_path: Path, edit: tuple[str, str], what: str) -> None:
    code, _, err = run("ik-bench", str(planar(tmp_path, PLANAR_2R.replace(*edit, 1))), *QUICK)
    assert code == 2 and what in err, err


# ---------------------------------------------------------------- 4. memory and time; one validation layer


@pytest.mark.parametrize(
    "args, flag",
    [
        (["--timeout", "inf"], "--timeout"),
        (["--timeout", "nan"], "--timeout"),
        (["--timeout", "-1"], "--timeout"),
        (["--timeout", "1e9"], "--timeout"),
        (["--tolerance", "nan"], "--tolerance"),
        (["--tolerance", "0"], "--tolerance"),
        (["--tolerance", "inf"], "--tolerance"),
        (["--samples", "0"], "--samples"),
        (["--samples", "1000000000"], "--samples"),
        (["--seed", "1.5"], "--seed"),
    ],
)
def test_bad_numbers_are_refused_naming_the_flag(tmp_path: Path, args: list[str], flag: str) -> None:
    start = time.monotonic()
    code, _, err = run("ik-bench", str(planar(tmp_path)), "--solvers", "dls", *args)
    assert code == 2 and flag in err, err
    assert time.monotonic() - start < 5


@pytest.mark.parametrize("value", [".inf", ".nan", "-1", "0", "1e9", "'fast'", "true"])
def test_kinematics_yaml_timeout_is_finite_and_bounded(tmp_path: Path, value: str) -> None:
    urdf = planar(tmp_path)
    srdf = tmp_path / "planar.srdf"
    srdf.write_text('<robot name="planar"><group name="arm"><chain base_link="base" tip_link="l2"/></group></robot>')
    kin = tmp_path / "kinematics.yaml"
    kin.write_text(
        f"arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n  kinematics_solver_timeout: {value}\n"
    )
    start = time.monotonic()
    code, _, err = run(
        "ik-bench", str(urdf), "--group", "arm", "--srdf", str(srdf), "--kinematics-yaml", str(kin), *QUICK
    )
    assert code == 2 and "kinematics_solver_timeout" in err and f"{kin}:3" in err, err
    assert time.monotonic() - start < 5


@pytest.mark.parametrize(
    "text, what",
    [
        ("- arm\n- other\n", "not a mapping of group names"),
        ("arm: 5\n", "not a mapping of settings"),
        ("other:\n  kinematics_solver_timeout: 0.01\n", "group 'arm' is not in kinematics.yaml"),
        ("arm: [\n", "not valid YAML"),
    ],
)
def test_kinematics_yaml_without_the_group_is_not_silently_ignored(tmp_path: Path, text: str, what: str) -> None:
    from armtool.ik.group import group_settings

    kin = tmp_path / "kinematics.yaml"
    kin.write_text(text)
    with pytest.raises(ArmtoolError, match=what):
        group_settings(kin, "arm")


def test_solver_api_refuses_an_endless_timeout() -> None:
    from armtool.ik.registry import make_solver
    from armtool.model.chain import load_chain

    chain = load_chain(URDF, "base_link", "tool0")
    for bad in (float("inf"), float("nan")):
        with pytest.raises(ArmtoolError, match="finite"):
            make_solver("dls", chain, timeout=bad)
        with pytest.raises(ArmtoolError, match="finite"):
            make_solver("dls", chain, tolerance=bad)


# ---------------------------------------------------------------- 7. silent no-ops


@pytest.mark.parametrize(
    "args, flag",
    [
        (["--solvers", ","], "--solvers"),
        (["--solvers", ""], "--solvers"),
        (["--solvers", "dls", "--peers", ","], "--peers"),
        (["--solvers", "dls", "--peers", " "], "--peers"),
        (["--solvers", "dls,dls"], "--solvers"),
    ],
)
def test_empty_solver_lists_are_refused(tmp_path: Path, args: list[str], flag: str) -> None:
    code, out, err = run("ik-bench", str(planar(tmp_path)), "--samples", "5", *args)
    assert code == 2 and flag in err and out == "", err


# ---------------------------------------------------------------- 6. late failures; files


def test_plot_is_checked_before_the_work(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import armtool.ik.bench as bench

    def never(*_: Any, **__: Any) -> None:
        raise AssertionError("the benchmark ran before --plot was checked")

    monkeypatch.setattr(bench, "run_bench", never)
    urdf = planar(tmp_path)
    code, _, err = run("ik-bench", str(urdf), *QUICK, "--plot", str(tmp_path / "no" / "dir" / "ik.png"))
    assert code == 2 and "does not exist" in err and "--plot" in err, err
    code, _, err = run("ik-bench", str(urdf), *QUICK, "--plot", str(urdf))
    assert code == 2 and "is also an input" in err
    code, _, err = run("ik-bench", str(urdf), *QUICK, "--plot", str(tmp_path))
    assert code == 2 and "is a directory" in err
    code, _, err = run("ik-bench", str(urdf), *QUICK, "--plot", str(tmp_path / "ik.jpg"))
    assert code == 2 and "--plot names a file with '.jpg'" in err and "PNG, SVG or PDF" in err, err


@pytest.mark.skipif(os.geteuid() == 0 if hasattr(os, "geteuid") else True, reason="root may write anywhere")
def test_plot_into_a_read_only_directory_is_checked_before_the_work(tmp_path: Path) -> None:
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        code, _, err = run("ik-bench", str(planar(tmp_path)), *QUICK, "--plot", str(locked / "ik.png"))
        assert code == 2 and "not writable" in err
    finally:
        locked.chmod(0o700)


def test_tree_output_never_overwrites_its_input(tmp_path: Path) -> None:
    urdf = planar(tmp_path)
    code, _, err = run("tree", str(urdf), "-o", str(urdf))
    assert code == 2 and "is also an input" in err
    assert urdf.read_text() == PLANAR_2R
    code, _, err = run("tree", str(urdf), "-o", str(tmp_path / "missing" / "tree.txt"))
    assert code == 2 and "does not exist" in err


# ---------------------------------------------------------------- 8. output contamination


class _LoudPeer:
    """A stand-in for TRAC-IK's C++: writes to file descriptor 1 itself, past sys.stdout."""

    def __new__(cls, chain: Any, root: Any, *, timeout: float, tolerance: float) -> Any:
        from armtool.ik.solvers.dls import DampedLeastSquares

        class Loud(DampedLeastSquares):
            name = "loud"

            def solve(self, target: Any, seed: Any) -> Any:
                os.write(1, b"WARNING:NLOpt_IK from os.write\n")
                try:  # and through C stdio's buffer, as printf/std::cout do
                    import ctypes

                    ctypes.CDLL(None).printf(b"WARNING:NLOpt_IK from printf\n")
                except (OSError, AttributeError, TypeError):
                    pass
                return super().solve(target, seed)

        os.write(1, b"WARNING:NLOpt_IK while building\n")
        return Loud(chain, timeout=timeout, tolerance=tolerance)


def test_native_prints_of_peers_never_reach_stdout(
    tmp_path: Path, capfd: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import armtool.ik.peers as peers

    monkeypatch.setitem(peers.PEERS, "loud", (f"{__name__}:_LoudPeer", "os", "nothing to install"))
    code, out, err = run(
        "ik-bench",
        str(URDF),
        "--base",
        "base_link",
        "--tip",
        "link1",
        "--samples",
        "5",
        "--solvers",
        "dls",
        "--no-batch",
        "--peers",
        "loud",
        "--format",
        "json",
    )
    assert code == 0, err
    assert [r["solver"] for r in json.loads(out)["solvers"]] == ["dls", "loud"]
    captured = capfd.readouterr()
    assert "WARNING" not in captured.out, captured.out
    assert "from os.write" in captured.err and "while building" in captured.err


def test_stdout_redirect_restores_fd_1(capfd: pytest.CaptureFixture[str]) -> None:
    from armtool.ik.peers import native_stdout_to_stderr

    with native_stdout_to_stderr():
        os.write(1, b"inside\n")
    os.write(1, b"after\n")
    captured = capfd.readouterr()
    assert captured.out == "after\n" and captured.err == "inside\n"


# ---------------------------------------------------------------- property-based

NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(10**30), 10**30),
    st.sampled_from(["nan", "inf", "-inf", "1e308", "1e-300", "0", "-0", "abc", ""]),
)
# Valid timeouts stay short here: a 10 s budget on a failing solver would only make the run slow.
TIMEOUTS = st.one_of(st.floats(1e-4, 0.02), st.sampled_from(["nan", "inf", "-inf", "0", "-1", "1e308", "11", "x"]))


def ok_codes(code: int, out: str, err: str, fmt: str = "json") -> None:
    assert code in (0, 1, 2), err
    assert "Traceback" not in err and "internal error" not in err
    if code == 0 and fmt == "json":
        json.loads(out)


@HYPO
@given(
    samples=st.one_of(st.integers(-5, 8), st.sampled_from([0, 10**6, 10**12])),
    seed=st.integers(-(10**20), 10**20),
    timeout=TIMEOUTS,
    tolerance=NUMBERS,
)
def test_numeric_options(
    tmp_path_factory: pytest.TempPathFactory, samples: int, seed: int, timeout: Any, tolerance: Any
) -> None:
    urdf = planar(tmp_path_factory.mktemp("opts"))
    start = time.monotonic()
    code, out, err = run(
        "ik-bench",
        str(urdf),
        "--solvers",
        "dls",
        "--no-batch",
        "--samples",
        str(samples),
        "--seed",
        str(seed),
        "--timeout",
        str(timeout),
        "--tolerance",
        str(tolerance),
        "--format",
        "json",
    )
    ok_codes(code, out, err)
    assert urdf.read_text() == PLANAR_2R and time.monotonic() - start < 20


HOSTILE = st.sampled_from(
    ["nan", "inf", "-inf", "1e308", "-1e308", "1e200", "0", "-0", "5e-324", "1e-300", "", "x", "1 2"]
)
SLOTS = [  # (attribute text in PLANAR_2R, how many numbers it holds)
    ('xyz="0 0 0.1"', 3),
    ('xyz="0.5 0 0"', 3),
    ('xyz="0.3 0 0"', 3),
    ('rpy="0 0 0"', 3),
    ('<axis xyz="0 0 1"/><limit lower="-3"', 3),
    ('lower="-3"', 1),
    ('upper="3"', 1),
]


@HYPO
@given(slot=st.integers(0, len(SLOTS) - 1), values=st.lists(HOSTILE, min_size=1, max_size=3), which=st.integers(0, 1))
def test_mutated_urdf_numbers(
    tmp_path_factory: pytest.TempPathFactory, slot: int, values: list[str], which: int
) -> None:
    attr, n = SLOTS[slot]
    name, _, rest = attr.partition('="')
    numbers = rest.split('"')[0].split()
    numbers[: len(values)] = values[:n]
    replaced = f'{name}="{" ".join(numbers)}"' + rest[rest.index('"') + 1 :]
    text = PLANAR_2R.replace(attr, "\0", which + 1).replace("\0", attr, which).replace("\0", replaced)
    urdf = planar(tmp_path_factory.mktemp("urdf"), text)
    start = time.monotonic()
    code, out, err = run("ik-bench", str(urdf), *QUICK, "--format", "json")
    ok_codes(code, out, err)
    assert urdf.read_text() == text and time.monotonic() - start < 20


@HYPO
@given(flips=st.lists(st.tuples(st.integers(0, len(PLANAR_2R) - 1), st.integers(0, 255)), min_size=1, max_size=4))
def test_byte_flipped_urdf(tmp_path_factory: pytest.TempPathFactory, flips: list[tuple[int, int]]) -> None:
    data = bytearray(PLANAR_2R.encode())
    for at, value in flips:
        data[at] = value
    path = tmp_path_factory.mktemp("flip") / "planar.urdf"
    path.write_bytes(bytes(data))
    start = time.monotonic()
    for command in (["ik-bench", str(path), *QUICK, "--format", "json"], ["tree", str(path)]):
        code, out, err = run(*command)
        ok_codes(code, out, err, fmt=command[-1])
    assert path.read_bytes() == bytes(data) and time.monotonic() - start < 20


SRDF_TEXT = '<robot name="planar"><group name="arm"><chain base_link="base" tip_link="tool"/></group></robot>'
KIN_TEXT = "arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n  kinematics_solver_timeout: 0.005\n"
YAML_VALUES = st.sampled_from(
    [
        ".inf",
        "-.inf",
        ".nan",
        "0",
        "-1",
        "1e400",
        "'x'",
        "[1, 2]",
        "{a: 1}",
        "null",
        "true",
        "0.01",
        "*x",
        "&x 1",
        "!!binary AAAA",
        "9" * 400,
    ]
)


@HYPO
@given(
    srdf_edit=st.sampled_from(
        [
            ("tool", "tol"),
            ("base", "tool"),
            ('"arm"', '"ram"'),
            ("<chain", '<joint name="j1"/><chain'),
            ("chain", 'link name="l2"/><x'),
            ("</robot>", ""),
            ("arm", "arm\x00"),
            ("", ""),
        ]
    ),
    key=st.sampled_from(["kinematics_solver_timeout", "position_only_ik", "arm"]),
    value=YAML_VALUES,
)
def test_mutated_srdf_and_kinematics_yaml(
    tmp_path_factory: pytest.TempPathFactory, srdf_edit: tuple[str, str], key: str, value: str
) -> None:
    folder = tmp_path_factory.mktemp("group")
    urdf = planar(folder)
    srdf_text = SRDF_TEXT.replace(*srdf_edit, 1) if srdf_edit[0] else SRDF_TEXT
    kin_text = (KIN_TEXT + f"  {key}: {value}\n") if key != "arm" else f"arm: {value}\n"
    srdf = folder / "planar.srdf"
    srdf.write_text(srdf_text)
    kin = folder / "kinematics.yaml"
    kin.write_text(kin_text)
    start = time.monotonic()
    code, out, err = run(
        "ik-bench",
        str(urdf),
        "--group",
        "arm",
        "--srdf",
        str(srdf),
        "--kinematics-yaml",
        str(kin),
        *QUICK,
        "--format",
        "json",
    )
    ok_codes(code, out, err)
    assert srdf.read_text() == srdf_text and kin.read_text() == kin_text and time.monotonic() - start < 20
