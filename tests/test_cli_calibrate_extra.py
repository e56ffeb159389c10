"""`armtool calibrate camera` and `armtool calibrate import-bag` end to end, and their bad input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest
from typer.testing import CliRunner

from armtool.calib.model.camera import load_intrinsics
from armtool.cli import app
from tests.calib.board_images import APRILGRID, TRUE_CAMERA, board_images

ROOT = Path(__file__).resolve().parents[1]
CLEAN_ARM = ROOT / "fixtures" / "robots" / "clean_arm" / "urdf" / "clean_arm.urdf"
runner = CliRunner()


def armtool(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "armtool", *args], capture_output=True, text=True, cwd=ROOT)


@pytest.fixture(scope="module")
def board_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("board")
    for k, img in enumerate(board_images(APRILGRID)):
        cv2.imwrite(str(d / f"{k:02d}.png"), img)
    return d


def test_camera_writes_intrinsics_that_a_dataset_can_use(board_dir: Path, tmp_path: Path) -> None:
    out = tmp_path / "camera.yaml"
    result = runner.invoke(
        app, ["calibrate", "camera", str(board_dir), "--board", APRILGRID, "-o", str(out), "--format", "json"]
    )
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["schema_version"] == 1 and len(summary["images"]) == 16 and all(i["used"] for i in summary["images"])
    assert (
        abs(summary["fx_px"] / 600 - 1) < 0.002
        and abs(summary["cx_px"] - 322.4) < 1.0
        and abs(summary["cy_px"] - 236.8) < 1.0
    )
    camera = load_intrinsics(out)
    assert np.allclose(
        camera.K, [[summary["fx_px"], 0, summary["cx_px"]], [0, summary["fy_px"], summary["cy_px"]], [0, 0, 1]]
    )
    assert (camera.width, camera.height) == (TRUE_CAMERA.width, TRUE_CAMERA.height)
    assert "RMS px" in result.stderr and f"wrote {out}" in result.stderr


def test_camera_with_too_few_board_images_exits_2_and_writes_nothing(board_dir: Path, tmp_path: Path) -> None:
    out = tmp_path / "camera.yaml"
    images = sorted(board_dir.glob("*.png"))[:4]
    proc = armtool("calibrate", "camera", *map(str, images), "--board", APRILGRID, "-o", str(out))
    assert proc.returncode == 2, proc.stderr
    assert (
        "the board was found in 4 of 4 images; at least 10 are needed" in proc.stderr and "Traceback" not in proc.stderr
    )
    assert not out.exists()
    proc = armtool("calibrate", "camera", str(board_dir), "--board", "charuco:9x7:0.03", "-o", str(out))
    assert proc.returncode == 2 and "needs 4 or 5 fields" in proc.stderr and not out.exists()


@pytest.fixture(scope="module")
def bag(tmp_path_factory: pytest.TempPathFactory) -> Path:
    pytest.importorskip("rosbags", reason="the calib extra (rosbags) is not installed")
    from tests.calib.bag_builder import simulate_motion, write_bag

    path = tmp_path_factory.mktemp("bag") / "cal.bag"
    write_bag(path, "ros1", simulate_motion(n_stops=3), camera_info=True)
    return path


def test_import_bag_builds_a_dataset_that_check_accepts(bag: Path, tmp_path: Path) -> None:
    out = tmp_path / "ds"
    result = runner.invoke(
        app,
        [
            "calibrate",
            "import-bag",
            str(bag),
            "--image-topic",
            "/camera/image_raw",
            "--urdf",
            str(CLEAN_ARM),
            "--flange",
            "tool0",
            "--tag-size",
            "0.05",
            "-o",
            str(out),
            "--format",
            "json",
        ],
    )
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert len(summary["samples"]) == 3 and summary["clock"] == "header stamps"
    assert sorted(p.name for p in out.iterdir()) == [
        "camera.yaml",
        "dataset.yaml",
        "images",
        "robot.urdf",
        "samples.csv",
    ]
    check = runner.invoke(app, ["calibrate", "check", str(out), "--no-detect"])
    assert check.exit_code == 0, check.output


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--image-topic", "/cam/image"], "topic '/cam/image' is not in the bag"),
        (
            ["--image-topic", "/camera/image_raw", "--joints-topic", "/arm/joint_states"],
            "topic '/arm/joint_states' is not in the bag",
        ),
        (["--image-topic", "/camera/image_raw", "--flange", "tool0", "--base", "nowhere"], "nowhere"),
    ],
)
def test_import_bag_bad_input_exits_2_and_writes_nothing(
    bag: Path, tmp_path: Path, args: list[str], message: str
) -> None:
    out = tmp_path / "ds"
    proc = armtool(
        "calibrate", "import-bag", str(bag), "--urdf", str(CLEAN_ARM), "--tag-size", "0.05", "-o", str(out), *args
    )
    assert proc.returncode == 2, proc.stderr
    assert message in proc.stderr and "Traceback" not in proc.stderr
    assert not out.exists() and not list(tmp_path.iterdir())


def test_import_bag_with_joints_the_urdf_lacks_exits_2(tmp_path: Path) -> None:
    pytest.importorskip("rosbags", reason="the calib extra (rosbags) is not installed")
    from tests.calib.bag_builder import JOINTS, simulate_motion, write_bag

    write_bag(tmp_path / "cal", "mcap", simulate_motion(n_stops=2), joint_names=[j.upper() for j in JOINTS])
    proc = armtool(
        "calibrate",
        "import-bag",
        str(tmp_path / "cal"),
        "--image-topic",
        "/camera/image_raw",
        "--urdf",
        str(CLEAN_ARM),
        "--flange",
        "tool0",
        "--tag-size",
        "0.05",
        "-o",
        str(tmp_path / "ds"),
    )
    assert proc.returncode == 2 and "are not in the JointState messages on '/joint_states'" in proc.stderr
    assert "JOINT1" in proc.stderr and not (tmp_path / "ds").exists()
