"""`armtool calibrate check|fit` on datasets of measured poses and points written by hand, the
convention check, and the verdict when no calibration beats the nominal robot (issue 23)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import yaml
from typer.testing import CliRunner

from armtool.calib.choices import Setup
from armtool.calib.model.camera import save_intrinsics
from armtool.calib.targets.apriltag import tag_object_points  # noqa: F401  (calib extra present)
from armtool.cli import app
from armtool.model.chain import load_chain
from tests.calib.conftest import CLEAN_ARM
from tests.calib.measured_files import write_dataset
from tests.calib.synthetic import make_measured, make_problem

runner = CliRunner()
CHAIN = load_chain(CLEAN_ARM, "base_link", "tool0")
ROOT = Path(__file__).resolve().parents[1]


def armtool(*args: str) -> subprocess.CompletedProcess[str]:
    """The installed entry point: user errors exit 2 with what, where and a hint."""
    return subprocess.run([sys.executable, "-m", "armtool", *args], capture_output=True, text=True, cwd=ROOT)


def test_check_and_fit_a_pose_dataset(tmp_path: Path) -> None:
    m = make_measured(CHAIN, "pose", n=40, noise_mm=0.1, noise_deg=0.02, seed=11)
    ds = write_dataset(tmp_path / "ds", m, rotation="quaternion", units="mm")
    check = runner.invoke(app, ["calibrate", "check", str(ds)])
    assert check.exit_code == 0, check.output
    assert "the declared conventions fit best" in check.output
    out = tmp_path / "out"
    pdf = tmp_path / "fit.pdf"
    result = runner.invoke(
        app, ["calibrate", "fit", str(ds), "-o", str(out), "--format", "json", "--no-nested", "--plot", str(pdf)]
    )
    assert result.exit_code == 0, result.output
    assert pdf.read_bytes()[:5] == b"%PDF-"  # the format the extension names
    summary = json.loads(result.stdout)
    assert summary["fitted"] == "origins + offsets"
    assert set(summary["frames"]) == {"camera_in_flange", "board_in_base"}
    assert summary["noise"]["position_mm"] < 0.15 and summary["noise"]["rotation_deg"] < 0.03
    assert (
        summary["metrics"]["fit_rms_mm"]["calibrated"] < 0.3 < 1.0 < summary["metrics"]["fit_rms_mm"]["hand_eye_only"]
    )
    assert summary["verdict"]["improves_on_nominal"] is True
    assert summary["measurement_conventions"]["better_reading"] is None
    assert (out / "calibrated.urdf").is_file()
    document = yaml.safe_load((out / "calibration.yaml").read_text())
    assert {"hand_eye_only_mm", "calibrated_mm", "hand_eye_only_deg", "calibrated_deg"} <= set(document["samples"][0])
    assert "position (mm)" in result.stderr or "position" in result.output


def test_check_names_the_line_that_fixes_an_inverted_pose(tmp_path: Path) -> None:
    m = make_measured(CHAIN, "pose", n=30, seed=12)
    ds = write_dataset(tmp_path / "ds", m, rotation="rpy", manifest={"pose": "target_in_sensor"})
    check = runner.invoke(app, ["calibrate", "check", str(ds)])
    assert check.exit_code == 1
    flat = " ".join(check.output.split())
    assert "fit" in flat and "times better read another way" in flat
    assert "set observations.pose: sensor_in_target" in flat
    fit = armtool("calibrate", "fit", str(ds), "-o", str(tmp_path / "out"))
    assert fit.returncode == 2 and not (tmp_path / "out").exists() and "Traceback" not in fit.stderr
    flat = " ".join(fit.stderr.split())
    assert "observations.pose: sensor_in_target" in flat and "--keep-conventions" in flat


def test_check_names_the_rpy_order_and_the_setup(tmp_path: Path) -> None:
    m = make_measured(CHAIN, "pose", n=30, seed=13)
    ds = write_dataset(tmp_path / "ds", m, rotation="rpy", manifest={"rpy_order": "xyz"})
    flat = " ".join(runner.invoke(app, ["calibrate", "check", str(ds)]).output.split())
    assert "set observations.rpy_order: zyx" in flat
    doc = yaml.safe_load((ds / "dataset.yaml").read_text())
    doc["observations"]["rpy_order"] = "zyx"
    doc["setup"] = "eye_to_hand"
    (ds / "dataset.yaml").write_text(yaml.safe_dump(doc))
    flat = " ".join(runner.invoke(app, ["calibrate", "check", str(ds)]).output.split())
    # A camera on the flange seeing a fixed board, or a fixed camera seeing a board on the flange
    # with the pose inverted: the same equations, so both fixes are named.
    assert "set observations.pose: target_in_sensor" in flat
    assert "fit exactly as well with setup: eye_in_hand" in flat


def test_params_none_fits_only_the_frames_and_exits_0(tmp_path: Path) -> None:
    # Hand-eye only, asked for: the baseline every calibration is compared with. The robot is held
    # nominal, so calibrated.urdf is not written, and that is the answer, not a failed verdict.
    m = make_measured(CHAIN, "point", n=30, setup=Setup.EYE_TO_HAND, seed=5)
    ds = write_dataset(tmp_path / "ds", m)
    out = tmp_path / "out"
    result = armtool("calibrate", "fit", str(ds), "-o", str(out), "--params", "none", "--holdout", "0.3")
    assert result.returncode == 0, result.stderr
    assert not (out / "calibrated.urdf").exists()
    assert "hand-eye only (--params none)" in " ".join(result.stderr.split())
    assert "not written:" not in result.stderr  # nothing was refused
    doc = yaml.safe_load((out / "calibration.yaml").read_text())
    assert doc["fitted"] == "hand-eye only"
    assert all(name.startswith(("tracker", "point")) for name in doc["identifiability"]["identified_parameters"])
    assert set(doc["frames"]) == {"tracker_in_base", "point_in_flange"}
    holdout = doc["metrics"]["holdout_rms_mm"]
    assert holdout["hand_eye_only"] == holdout["calibrated"] > 0  # scored on the held-out poses
    refused = armtool("calibrate", "fit", str(ds), "-o", str(out), "--params", "none", "--ur-kinematics", "u.yaml")
    assert refused.returncode == 2 and "no calibrated arm to write" in refused.stderr


def test_points_in_millimetres_declared_as_metres(tmp_path: Path) -> None:
    # 1000 times too large is caught row by row; 1000 times too small by the convention check.
    m = make_measured(CHAIN, "point", n=30, setup=Setup.EYE_TO_HAND, seed=14)
    ds = write_dataset(tmp_path / "ds", m, units="m", manifest={"position_units": "mm"})
    flat = " ".join(runner.invoke(app, ["calibrate", "check", str(ds)]).output.split())
    assert "set observations.position_units: m" in flat


def test_a_correct_urdf_is_not_rewritten_and_fit_exits_1(tmp_path: Path) -> None:
    # The case on the tag path: few noisy poses of a robot that is its URDF. Every
    # kinematic set fitted to them predicts held-out poses worse than hand-eye only.
    p = make_problem(CHAIN, n=20, noise_px=0.3, seed=2, errors=False)
    ds = tmp_path / "ds"
    ds.mkdir()
    (ds / "robot.urdf").write_text(CLEAN_ARM.read_text())
    save_intrinsics(p.camera, ds / "camera.yaml")
    names = CHAIN.joint_names
    (ds / "samples.csv").write_text(
        "\n".join(
            ["id,image," + ",".join(names)] + [f"{s.id},," + ",".join(repr(float(v)) for v in s.q) for s in p.samples]
        )
        + "\n"
    )
    rows = ["id,tag_id,u0,v0,u1,v1,u2,v2,u3,v3"]
    rows += [
        f"{sid},0," + ",".join(repr(float(v)) for v in ob.corners_px.ravel()) for sid, ob in p.observations.items()
    ]  # type: ignore[union-attr]
    (ds / "corners.csv").write_text("\n".join(rows) + "\n")
    manifest = {
        "format": "armtool-calib-dataset/1",
        "setup": "eye_to_hand",
        "robot": {"urdf": "robot.urdf", "base_link": "base_link", "flange_link": "tool0", "joints": names},
        "camera": {"intrinsics": "camera.yaml"},
        "target": {"type": "apriltag", "family": "tag36h11", "id": 0, "size_m": 0.08},
        "samples": "samples.csv",
    }
    (ds / "dataset.yaml").write_text(yaml.safe_dump(manifest))
    out = tmp_path / "out"
    result = runner.invoke(app, ["calibrate", "fit", str(ds), "-o", str(out), "--format", "json", "--no-nested"])
    assert result.exit_code == 1, result.output
    summary = json.loads(result.stdout)
    assert summary["fitted"] == "hand-eye only"
    assert summary["verdict"]["improves_on_nominal"] is False
    assert "no kinematic calibration beats the nominal robot" in summary["verdict"]["summary"]
    assert "poses" in summary["verdict"]["advice"]
    assert (out / "calibration.yaml").is_file() and not (out / "calibrated.urdf").exists()
    flat = " ".join(result.stderr.split())
    assert "not written:" in flat and "calibrated.urdf" in flat
    allowed = runner.invoke(app, ["calibrate", "fit", str(ds), "-o", str(out), "--no-nested", "--allow-nominal"])
    assert allowed.exit_code == 0 and not (out / "calibrated.urdf").exists()
    forced = runner.invoke(
        app, ["calibrate", "fit", str(ds), "-o", str(out), "--no-nested", "--no-select", "--format", "json"]
    )
    assert forced.exit_code == 1 and not (out / "calibrated.urdf").exists()
    assert "predicts held-out poses worse than the nominal robot" in json.loads(forced.stdout)["verdict"]["summary"]


def test_a_validation_dataset_in_its_own_conventions(tmp_path: Path) -> None:
    # A second session of the same setup, written by another script (metres, rotation matrices,
    # board-in-camera): each file is read in its own conventions, and only the kind must match.
    m = make_measured(CHAIN, "pose", n=40, noise_mm=0.1, noise_deg=0.02, seed=15)
    ds = write_dataset(tmp_path / "ds", m, rotation="quaternion", units="mm")
    other = make_measured(CHAIN, "pose", n=12, noise_mm=0.1, noise_deg=0.02, seed=15)  # the same robot and placements
    from armtool.calib.inputs.conventions import PoseFrame

    vds = write_dataset(tmp_path / "vds", other, rotation="matrix", units="m", frame=PoseFrame.TARGET_IN_SENSOR)
    args = [
        "calibrate",
        "fit",
        str(ds),
        "-o",
        str(tmp_path / "out"),
        "--validation",
        str(vds),
        "--folds",
        "0",
        "--format",
        "json",
    ]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    metrics = json.loads(result.stdout)["metrics"]
    assert metrics["holdout_rms_mm"]["calibrated"] < 0.3 < 1.0 < metrics["holdout_rms_mm"]["hand_eye_only"]
    points = write_dataset(tmp_path / "pts", make_measured(CHAIN, "point", n=12, seed=16))
    refused = armtool("calibrate", "fit", str(ds), "-o", str(tmp_path / "o2"), "--validation", str(points))
    assert refused.returncode == 2 and "observations (kind, sensor or target)" in refused.stderr
