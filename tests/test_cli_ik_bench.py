"""`armtool ik-bench`: formats, plot, MoveIt group/timeout, and clear errors."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

from typer.testing import CliRunner

from armtool.cli import app
from tests.ik.robots import ARMS, PLANAR_2R, erd

runner = CliRunner()


def test_json_output_on_ur5(tmp_path: Path) -> None:
    urdf = erd(ARMS["ur5"][0])
    result = runner.invoke(app, ["ik-bench", str(urdf), "--samples", "20", "--solvers", "lm", "--format", "json",
                                 "--plot", str(tmp_path / "bench.png")])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert doc["schema_version"] == 1 and doc["config"]["samples"] == 20
    modes = {(s["solver"], s["mode"]) for s in doc["solvers"]}
    assert modes == {("lm", "single"), ("lm", "batch")}
    assert (tmp_path / "bench.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_csv_and_no_batch(tmp_path: Path) -> None:
    urdf = tmp_path / "planar.urdf"
    urdf.write_text(PLANAR_2R)
    result = runner.invoke(app, ["ik-bench", str(urdf), "--samples", "10", "--solvers", "lm", "--no-batch", "--format", "csv"])
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(io.StringIO(result.stdout)))
    assert [r["solver"] for r in rows] == ["lm"]


def test_group_from_srdf_and_timeout_from_kinematics_yaml(tmp_path: Path) -> None:
    urdf = tmp_path / "planar.urdf"
    urdf.write_text(PLANAR_2R)
    srdf = tmp_path / "planar.srdf"
    srdf.write_text('<robot name="planar"><group name="arm"><chain base_link="base" tip_link="l2"/></group></robot>')
    kin = tmp_path / "kinematics.yaml"
    kin.write_text("arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n  kinematics_solver_timeout: 0.02\n")
    result = runner.invoke(app, ["ik-bench", str(urdf), "--group", "arm", "--srdf", str(srdf), "--kinematics-yaml", str(kin),
                                 "--samples", "5", "--solvers", "lm", "--format", "json"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert (doc["base"], doc["tip"], doc["config"]["timeout_s"]) == ("base", "l2", 0.02)


def test_bad_input_is_exit_2(tmp_path: Path) -> None:
    import subprocess
    import sys

    urdf = tmp_path / "planar.urdf"
    urdf.write_text(PLANAR_2R)

    def run(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-m", "armtool", "ik-bench", str(urdf), *args], capture_output=True, text=True, timeout=120)

    for args, needle in [
        (["--tip", "tol"], "did you mean 'tool'"),
        (["--solvers", "nope"], "unknown solver 'nope'"),
        (["--timeout", "0"], "--timeout must be > 0"),
        (["--group", "arm"], "--group needs --srdf"),
    ]:
        result = run(*args)
        assert result.returncode == 2, (args, result.stderr)
        assert needle in result.stderr and "Traceback" not in result.stderr
