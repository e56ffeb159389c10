"""Real measurements: a Franka Research 3 with a camera on the flange, 114 poses of a ChArUco
board (../shared/calib-real/franka_fr3, MIT, PhilNad/robot-arm-kinematic-calibration). Run through
the documented commands from a dataset.yaml written as the README says; skipped when the data is
absent. Never copied into the project: the manifest points at the shared CSVs."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

from armtool.cli import app
from armtool.model.chain import rpy_matrix
from tests.ik.robots import erd

FR3 = Path(__file__).resolve().parents[2] / ".." / "shared" / "calib-real" / "franka_fr3"
pytestmark = pytest.mark.skipif(not FR3.is_dir(), reason="../shared/calib-real is absent")
runner = CliRunner()
JOINTS = [f"panda_joint{i}" for i in range(1, 8)]
MATRIX = ["T00", "T01", "T02", "T10", "T11", "T12", "T20", "T21", "T22"]


def manifest(directory: Path, **observations: object) -> Path:
    """The README's worked example for these files, with `observations` changed."""
    directory.mkdir(parents=True, exist_ok=True)
    section = {
        "kind": "pose",
        "file": str(FR3 / "camera_in_board.csv"),
        "sensor": "camera",
        "target": "board",
        "pose": "sensor_in_target",
        "position_units": "m",
        "rotation": "matrix",
        "position_columns": ["T03", "T13", "T23"],
        "rotation_columns": MATRIX,
        **observations,
    }
    doc = {
        "format": "armtool-calib-dataset/1",
        "setup": "eye_in_hand",
        "robot": {
            "urdf": str(erd("panda_description/urdf/panda.urdf")),
            "base_link": "panda_link0",
            "flange_link": "panda_link8",
            "joints": JOINTS,
            "joint_units": "rad",
        },
        "samples": str(FR3 / "joints.csv"),
        "observations": section,
    }
    (directory / "dataset.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    return directory


def test_the_documented_manifest_reads_the_camera_poses(tmp_path: Path) -> None:
    check = runner.invoke(app, ["calibrate", "check", str(manifest(tmp_path / "fr3"))])
    assert check.exit_code == 0, check.output
    flat = " ".join(check.output.split())
    assert "114 samples, 0 error(s), 0 warning(s)" in flat
    assert "the declared conventions fit best: hand-eye-only residual 5.1" in flat  # the README's 4.98 mm, robust fit


def test_a_pose_read_inverted_is_found_and_the_fix_named(tmp_path: Path) -> None:
    check = runner.invoke(app, ["calibrate", "check", str(manifest(tmp_path / "fr3", pose="target_in_sensor"))])
    assert check.exit_code == 1
    flat = " ".join(check.output.split())
    assert "set observations.pose: sensor_in_target" in flat
    declared = float(flat.split("RMS against ")[1].split(" mm")[0])
    assert declared > 10 * 5.11


def test_rpy_read_in_the_other_order_is_found_and_the_fix_named(tmp_path: Path) -> None:
    # The same poses written as URDF roll-pitch-yaw (R = Rz·Ry·Rx), declared as R = Rx·Ry·Rz.
    rows = np.loadtxt(FR3 / "camera_in_board.csv", delimiter=",", skiprows=1)
    lines = ["id,x,y,z,roll,pitch,yaw"]
    for row in rows:
        T = row[1:].reshape(3, 4)
        R = T[:, :3]
        pitch = math.atan2(-R[2, 0], math.hypot(R[0, 0], R[1, 0]))
        roll, yaw = math.atan2(R[2, 1], R[2, 2]), math.atan2(R[1, 0], R[0, 0])
        assert np.allclose(rpy_matrix(roll, pitch, yaw), R, atol=1e-6)
        values = [float(v) for v in (T[0, 3], T[1, 3], T[2, 3], roll, pitch, yaw)]
        lines.append(f"{int(row[0])}," + ",".join(repr(v) for v in values))
    (tmp_path / "rpy.csv").write_text("\n".join(lines) + "\n")
    fields = {
        "file": str(tmp_path / "rpy.csv"),
        "rotation": "rpy",
        "angle_units": "rad",
        "position_columns": None,
        "rotation_columns": None,
    }
    directory = manifest(tmp_path / "fr3", **fields, rpy_order="xyz")
    doc = yaml.safe_load((directory / "dataset.yaml").read_text())
    doc["observations"] = {k: v for k, v in doc["observations"].items() if v is not None}
    (directory / "dataset.yaml").write_text(yaml.safe_dump(doc))
    check = runner.invoke(app, ["calibrate", "check", str(directory)])
    assert check.exit_code == 1
    assert "set observations.rpy_order: zyx" in " ".join(check.output.split())


def test_five_fold_held_out_camera_position(tmp_path: Path) -> None:
    """The issue's goal: the 5-fold held-out camera-position residual, the choice of parameters
    made inside each outer training set (nested), at most 1.2 mm RMS. Met on the 112 poses the
    procedure keeps (1.19 mm on this split); the two it names as outliers (one 55°-tilted pose
    recorded twice, 7.8 mm under every model tried, the authors' calibration included) bring the
    RMS over all 114 to 1.61 mm (1.57 mm when the two combinations determined worse than 1 mm and
    0.1° are fitted too; docs/benchmarks.md pools five splits)."""
    result = runner.invoke(
        app, ["calibrate", "fit", str(manifest(tmp_path / "fr3")), "-o", str(tmp_path / "out"), "--format", "json"]
    )
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    nested = summary["cross_validation"]["nested"]
    # the default ladder tries compliance after the geometry: one outer fold keeps it (1.614 mm
    # against 1.618 over all 114 with --params origins,offsets, measured), the others do not
    assert nested["chosen_per_fold"].count("origins + offsets") >= 4
    assert all(c.startswith("origins + offsets") for c in nested["chosen_per_fold"])
    assert nested["heldout_without_outliers_rms_mm"] <= 1.2
    assert nested["heldout_rms_mm"]["calibrated"] < 1.65 < 4.5 < nested["heldout_rms_mm"]["hand_eye_only"]
    assert set(summary["outliers"]) == {"112", "113"}
    assert summary["verdict"]["improves_on_nominal"]
    camera = summary["frames"]["camera_in_flange"]
    assert np.allclose(np.array(camera["xyz"]) * 1e3, [94.5, -9.0, 40.55], atol=3.0)  # the mount drawing
    assert abs(math.degrees(camera["rpy"][2]) - 90.0) < 3.0
