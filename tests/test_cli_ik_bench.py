"""`armtool ik-bench`: formats, plot, MoveIt group/timeout, and clear errors."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from armtool.cli import app
from tests.ik.robots import ARMS, PLANAR_2R, erd

runner = CliRunner()


def test_json_output_on_ur5(tmp_path: Path) -> None:
    urdf = erd(ARMS["ur5"][0])
    result = runner.invoke(
        app,
        [
            "ik-bench",
            str(urdf),
            "--samples",
            "20",
            "--solvers",
            "lm",
            "--format",
            "json",
            "--plot",
            str(tmp_path / "bench.svg"),
        ],
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert doc["schema_version"] == 3 and doc["config"]["samples"] == 20
    assert "the solver's own solve call only" in doc["timing"] and "outside the timed region" in doc["timing"]
    modes = {(s["solver"], s["mode"]) for s in doc["solvers"]}
    assert modes == {("lm", "single"), ("lm", "batch")}
    assert all(isinstance(s["failure_reasons"], dict) for s in doc["solvers"])
    svg = (tmp_path / "bench.svg").read_text()
    assert svg.startswith("<?xml") and "<svg" in svg and svg.rstrip().endswith("</svg>")


def test_csv_and_no_batch(tmp_path: Path) -> None:
    urdf = tmp_path / "planar.urdf"
    urdf.write_text(PLANAR_2R)
    result = runner.invoke(
        app, ["ik-bench", str(urdf), "--samples", "10", "--solvers", "lm", "--no-batch", "--format", "csv"]
    )
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(io.StringIO(result.stdout)))
    assert [r["solver"] for r in rows] == ["lm"]


def test_group_from_srdf_and_timeout_from_kinematics_yaml(tmp_path: Path) -> None:
    urdf = tmp_path / "planar.urdf"
    urdf.write_text(PLANAR_2R)
    srdf = tmp_path / "planar.srdf"
    srdf.write_text('<robot name="planar"><group name="arm"><chain base_link="base" tip_link="l2"/></group></robot>')
    kin = tmp_path / "kinematics.yaml"
    kin.write_text(
        "arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n  kinematics_solver_timeout: 0.02\n"
    )
    result = runner.invoke(
        app,
        [
            "ik-bench",
            str(urdf),
            "--group",
            "arm",
            "--srdf",
            str(srdf),
            "--kinematics-yaml",
            str(kin),
            "--samples",
            "5",
            "--solvers",
            "lm",
            "--format",
            "json",
        ],
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert (doc["base"], doc["tip"], doc["config"]["timeout_s"]) == ("base", "l2", 0.02)


def test_bad_input_is_exit_2(tmp_path: Path) -> None:
    import subprocess
    import sys

    urdf = tmp_path / "planar.urdf"
    urdf.write_text(PLANAR_2R)

    def run(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "armtool", "ik-bench", str(urdf), *args], capture_output=True, text=True, timeout=120
        )

    for args, needle in [
        (["--tip", "tol"], "did you mean 'tool'"),
        (["--solvers", "nope"], "unknown solver 'nope'"),
        (["--timeout", "0"], "--timeout must be > 0"),
        (["--group", "arm"], "--group needs --srdf"),
    ]:
        result = run(*args)
        assert result.returncode == 2, (args, result.stderr)
        assert needle in result.stderr and "Traceback" not in result.stderr


def test_requested_solver_that_does_not_apply_gets_a_row(tmp_path: Path) -> None:
    """`--solvers lm,analytic` on a 2-joint arm: analytic is marked not applicable, lm still runs (exit 0)."""
    urdf = tmp_path / "planar.urdf"
    urdf.write_text(PLANAR_2R)
    result = runner.invoke(
        app, ["ik-bench", str(urdf), "--samples", "10", "--solvers", "lm,analytic", "--no-batch", "--format", "json"]
    )
    assert result.exit_code == 0, result.output
    rows = {r["solver"]: r for r in json.loads(result.stdout)["solvers"]}
    assert rows["lm"]["applicable"] and rows["lm"]["success_rate"] >= 0.8  # wall-clock timeouts on a busy machine
    assert rows["analytic"]["applicable"] is False and rows["analytic"]["success_rate"] is None
    assert "the chain has 2 joints" in rows["analytic"]["reason"] and "gripper" not in rows["analytic"]["reason"]
    assert "analytic not applicable" in result.stderr
    table = runner.invoke(app, ["ik-bench", str(urdf), "--samples", "10", "--solvers", "lm,analytic", "--no-batch"])
    assert table.exit_code == 0 and "n/a" in table.stdout


def test_table_labels_maxima_and_shows_stalled_failures(tmp_path: Path) -> None:
    urdf = tmp_path / "planar.urdf"
    urdf.write_text(PLANAR_2R)
    result = runner.invoke(app, ["ik-bench", str(urdf), "--samples", "10", "--solvers", "lm", "--no-batch"])
    assert result.exit_code == 0, result.output
    assert "max pos err m" in result.stdout and "max rot err rad" in result.stdout
    import re

    assert "failures (stalled)" in result.stdout and re.search(r"│\s+\d+ \(\d+\) │", result.stdout)
    doc = json.loads(
        runner.invoke(
            app, ["ik-bench", str(urdf), "--samples", "10", "--solvers", "lm", "--no-batch", "--format", "json"]
        ).stdout
    )
    assert isinstance(doc["solvers"][0]["stalled_failures"], int)


def test_table_states_its_timing_boundary_and_why_a_row_fails() -> None:
    # A 0 % row with no reason looks like a broken solver: kdl-lma's says that KDL's own test
    # weights rotation by 0.01, and the footer says what the times are.
    urdf = erd(ARMS["ur5"][0])
    result = runner.invoke(
        app, ["ik-bench", str(urdf), "--samples", "8", "--solvers", "kdl-lma", "--no-batch", "--timeout", "0.05"]
    )
    assert result.exit_code == 0, result.output
    text = " ".join(result.stdout.split())
    assert "main failure reason" in result.stdout
    assert "KDL's test weights rotation by 0.01" in text.replace("│ ", "").replace(" │", "")
    assert "Timing: time = the solver's own solve call only" in text


def test_group_from_srdf_xacro_with_xacro_args(tmp_path: Path) -> None:
    """--srdf may be a .srdf.xacro; it gets the same --xacro-arg values as the URDF (issue 10 item 2)."""
    from tests.ik.test_group import ARM

    urdf = tmp_path / "arm.urdf"
    urdf.write_text(ARM)
    srdf = tmp_path / "arm.srdf.xacro"
    srdf.write_text(
        '<robot xmlns:xacro="http://wiki.ros.org/xacro" name="arm"><xacro:arg name="prefix" default=""/>'
        '<xacro:macro name="arm_group" params="p"><group name="${p}arm">'
        '<joint name="tool_frame_joint"/><joint name="j2"/><joint name="j1"/><joint name="j3"/>'
        '<joint name="flange_joint"/></group></xacro:macro><xacro:arm_group p="$(arg prefix)"/></robot>'
    )
    result = runner.invoke(
        app,
        [
            "ik-bench",
            str(urdf),
            "--group",
            "my_arm",
            "--srdf",
            str(srdf),
            "--xacro-arg",
            "prefix:=my_",
            "--samples",
            "5",
            "--solvers",
            "lm",
            "--no-batch",
            "--format",
            "json",
        ],
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert (doc["base"], doc["tip"], doc["joints"]) == ("base", "tool_frame", ["j1", "j2", "j3"])


REALWORLD = Path(__file__).resolve().parents[1] / ".." / "shared" / "realworld"


def test_realworld_gen3_lite_group_joint_order() -> None:
    """Kinova gen3_lite's SRDF lists tool_frame_joint first: the chain is still base_link → tool_frame."""
    import pytest

    urdf = REALWORLD / "ros2_kortex/kortex_description/robots/gen3_lite.urdf"
    srdf = REALWORLD / "ros2_kortex/kortex_moveit_config/kinova_gen3_lite_moveit_config/config/gen3_lite.srdf"
    if not urdf.is_file():
        pytest.skip("the realworld corpus is absent")
    result = runner.invoke(
        app,
        [
            "ik-bench",
            str(urdf),
            "--group",
            "arm",
            "--srdf",
            str(srdf),
            "--samples",
            "20",
            "--solvers",
            "lm",
            "--no-batch",
            "--format",
            "json",
        ],
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert (doc["base"], doc["tip"], doc["joints"]) == ("base_link", "tool_frame", [f"joint_{i}" for i in range(1, 7)])


def test_position_only_ik_from_kinematics_yaml(tmp_path: Path) -> None:
    """position_only_ik: true → targets and checks on position; every numerical solver runs (free virtual wrist)."""
    from tests.ik.test_group import ARM

    urdf = tmp_path / "arm.urdf"
    urdf.write_text(ARM)
    srdf = tmp_path / "arm.srdf"
    srdf.write_text(
        '<robot name="arm"><group name="arm"><chain base_link="base" tip_link="tool_frame"/></group></robot>'
    )
    kin = tmp_path / "kinematics.yaml"
    kin.write_text("arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n  position_only_ik: true\n")
    result = runner.invoke(
        app,
        [
            "ik-bench",
            str(urdf),
            "--group",
            "arm",
            "--srdf",
            str(srdf),
            "--kinematics-yaml",
            str(kin),
            "--samples",
            "20",
            "--solvers",
            "lm,dls,analytic",
            "--no-batch",
            "--format",
            "json",
        ],
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert doc["config"]["position_only"] is True and doc["joints"] == ["j1", "j2", "j3"]
    rows = {r["solver"]: r for r in doc["solvers"]}
    assert rows["lm"]["success_rate"] >= 0.9 and rows["dls"]["applicable"]
    assert rows["analytic"]["applicable"] is False and "position-only" in rows["analytic"]["reason"]
    assert "position only (position_only_ik" in result.stderr
    # Without position_only_ik the 3-joint arm cannot reach the same targets' orientations from the mid seed as often:
    kin.write_text("arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n")
    full = json.loads(
        runner.invoke(
            app,
            [
                "ik-bench",
                str(urdf),
                "--group",
                "arm",
                "--srdf",
                str(srdf),
                "--kinematics-yaml",
                str(kin),
                "--samples",
                "20",
                "--solvers",
                "lm",
                "--no-batch",
                "--format",
                "json",
            ],
        ).stdout
    )
    assert full["config"]["position_only"] is False


def test_missing_peer_hint_keeps_its_brackets(tmp_path: Path, monkeypatch: object) -> None:
    """The install hint "pip install 'armtool[peers]'" printed through rich must keep '[peers]' (issue 10 item 19)."""
    import armtool.ik.peers as peers

    entry = peers.PEERS["ikpy"]
    monkeypatch.setitem(peers.PEERS, "ikpy", (entry[0], "no_such_module_for_armtool_test", entry[2]))  # type: ignore[attr-defined]
    urdf = tmp_path / "planar.urdf"
    urdf.write_text(PLANAR_2R)
    result = runner.invoke(
        app,
        [
            "ik-bench",
            str(urdf),
            "--samples",
            "5",
            "--solvers",
            "lm",
            "--no-batch",
            "--peers",
            "ikpy",
            "--format",
            "json",
        ],
    )
    assert result.exit_code == 0, result.output
    assert "pip install 'armtool[peers]'" in result.stderr


MOVEIT_PACKAGE = Path(__file__).resolve().parents[1] / "fixtures" / "robots" / "clean_arm_moveit_config"


def test_moveit_config_gives_robot_group_timeout_and_solver() -> None:
    """--moveit-config: the URDF .setup_assistant names, the only kinematics.yaml group (a ROS 2
    parameter file), its timeout, and MoveIt's solver (KDL) first among armtool's."""
    result = runner.invoke(
        app, ["ik-bench", "--moveit-config", str(MOVEIT_PACKAGE), "--samples", "10", "--format", "json", "--no-batch"]
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert (doc["base"], doc["tip"]) == ("base_link", "tool0")
    assert doc["config"]["timeout_s"] == 0.01
    assert doc["solvers"][0]["solver"] == "kdl-nr-jl"
    assert (
        "MoveIt's solver kdl_kinematics_plugin/KDLKinematicsPlugin (armtool's kdl-nr-jl stands for it)" in result.stderr
    )


def test_closed_form_peers_count_solutions_and_say_why_they_cannot_take_an_arm(tmp_path: Path) -> None:
    """--peers eaik,ik-geo: on UR5 both solve every target with the same solution sets (JSON and CSV);
    on a general 6R arm EAIK's row says it has no decomposition, and the others still run."""
    import pytest

    pytest.importorskip("eaik")
    pytest.importorskip("ik_geo")
    urdf = erd(ARMS["ur5"][0])
    base = ["ik-bench", str(urdf), "--samples", "10", "--solvers", "lm", "--peers", "eaik,ik-geo"]
    result = runner.invoke(app, [*base, "--format", "json"])
    assert result.exit_code == 0, result.output
    rows = {(r["solver"], r["mode"]): r for r in json.loads(result.stdout)["solvers"]}
    assert set(rows) == {("lm", "single"), ("lm", "batch"), ("eaik", "single"), ("eaik", "batch"), ("ik-geo", "single")}
    for key in [("eaik", "single"), ("eaik", "batch"), ("ik-geo", "single")]:
        row = rows[key]
        assert row["success_rate"] == 1.0 and row["distinct_solutions"] >= 4, row
        assert row["missing_solutions"] == 0 and row["targets_missing_solutions"] == 0
    assert rows[("eaik", "single")]["distinct_solutions"] == rows[("ik-geo", "single")]["distinct_solutions"]
    assert rows[("ik-geo", "single")]["method"] == "three_parallel_two_intersecting (closed form)"
    assert rows[("lm", "single")]["distinct_solutions"] is None and rows[("lm", "single")]["missing_solutions"] is None
    table = runner.invoke(app, [*base, "--no-batch"])
    assert (
        table.exit_code == 0 and "missing" in table.stdout and "Methods: eaik: 6R-THREE_INNER_PARALLEL" in table.stdout
    )
    csv_rows = list(csv.DictReader(io.StringIO(runner.invoke(app, [*base, "--no-batch", "--format", "csv"]).stdout)))
    assert {r["solver"]: r["missing_solutions"] for r in csv_rows} == {"lm": "", "eaik": "0", "ik-geo": "0"}

    from tests.ik.robots import GENERAL_6R

    general = tmp_path / "general6r.urdf"
    general.write_text(GENERAL_6R)
    result = runner.invoke(
        app, ["ik-bench", str(general), "--samples", "3", "--solvers", "lm", "--peers", "eaik", "--format", "json"]
    )
    assert result.exit_code == 0, result.output
    rows = {r["solver"]: r for r in json.loads(result.stdout)["solvers"]}
    assert rows["eaik"]["applicable"] is False and "no subproblem decomposition" in rows["eaik"]["reason"]
    assert rows["lm"]["applicable"] and "eaik not applicable" in result.stderr


class _PanickyPeer:
    """A stand-in for IK-Geo's Rust: every other solve, its panic hook writes on file descriptor 2
    itself (past sys.stderr, in the middle of the progress bar); the answer is still dls's."""

    def __new__(cls, chain: object, root: object, *, timeout: float, tolerance: float) -> object:
        import os

        from armtool.ik.solvers.dls import DampedLeastSquares

        class Panicky(DampedLeastSquares):
            name = "panicky"
            prints_natively = True
            calls = 0

            def call(self, prepared):  # type: ignore[no-untyped-def]
                self.calls += 1
                if self.calls % 2:
                    os.write(2, b"thread '<unnamed>' panicked at src/fake.rs:1:2:\nfrom os.write\n")
                return super().call(prepared)

        return Panicky(chain, timeout=timeout, tolerance=tolerance)  # type: ignore[arg-type]


def test_native_stderr_of_a_peer_is_one_note_after_the_run(
    tmp_path: Path, capfd: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """What a peer's native code writes on fd 2 during its solves never reaches stderr as it is:
    ik-bench says once, after the run, how many lines and panics it held back, and the first line."""
    import armtool.ik.peers as peers

    monkeypatch.setitem(peers.PEERS, "panicky", (f"{__name__}:_PanickyPeer", "os", "nothing to install"))
    urdf = tmp_path / "planar.urdf"
    urdf.write_text(PLANAR_2R)
    args = ["ik-bench", str(urdf), "--samples", "10", "--solvers", "dls", "--no-batch", "--peers", "panicky"]
    result = runner.invoke(app, [*args, "--format", "json"])
    assert result.exit_code == 0, result.output
    assert [r["solver"] for r in json.loads(result.stdout)["solvers"]] == ["dls", "panicky"]
    raw = capfd.readouterr()
    assert "from os.write" not in raw.err and "panicked" not in raw.err, raw.err
    # 9 warm-up solves, 10 timed, 10 repeated (BenchConfig.repeat covers them all): every other one panics
    notes = [line for line in result.stderr.splitlines() if line.startswith("note:")]
    assert notes == [
        "note: panicky printed 30 lines on stderr during its solves (not shown; 15 Rust panics: 5 on timed"
        " targets, among its row's failures, 10 in untimed warm-up or repeat solves); the first: thread"
        " '<unnamed>' panicked at src/fake.rs:1:2:"
    ], result.stderr
    table = runner.invoke(app, args)
    assert table.exit_code == 0 and table.stderr.count("note: panicky printed") == 1, table.stderr


def test_xarm6_ik_geo_panics_stay_out_of_stderr(capfd: pytest.CaptureFixture[str]) -> None:
    """xarm_ros2's xArm6 (IK-Geo's two_parallel 1-D search): some targets end in a Rust panic inside
    IK-Geo; its panic hook's text is held back and summed up in one note."""
    pytest.importorskip("ik_geo")
    urdf = REALWORLD / "xarm_ros2/xarm_description/urdf/xarm_device.urdf.xacro"
    if not urdf.is_file():
        pytest.skip("the realworld corpus is absent")
    result = runner.invoke(
        app,
        [
            "ik-bench",
            str(urdf),
            "--xacro-arg",
            "dof:=6",
            "--package-path",
            str(REALWORLD),
            "--base",
            "link_base",
            "--tip",
            "link6",
            "--samples",
            "10",
            "--solvers",
            "dls",
            "--peers",
            "ik-geo",
            "--format",
            "json",
        ],
    )
    assert result.exit_code == 0, result.output
    raw = capfd.readouterr()
    assert "panicked" not in raw.err and "unwrap" not in raw.err, raw.err[:2000]
    rows = {r["solver"]: r for r in json.loads(result.stdout)["solvers"]}
    timed = sum(n for why, n in rows["ik-geo"]["failure_reasons"].items() if "PanicException" in why)
    assert timed >= 1, rows["ik-geo"]["failure_reasons"]
    notes = [line for line in result.stderr.splitlines() if line.startswith("note: ik-geo printed")]
    assert len(notes) == 1, result.stderr
    assert f"{timed} on {'a timed target' if timed == 1 else 'timed targets'}, among its row's failures" in notes[0]
    assert "the first: thread '<unnamed>' panicked at" in notes[0]
