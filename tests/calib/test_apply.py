"""`calibrate apply`: the chosen set's joint terms applied to readings, as the fit evaluated them."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

from armtool.calib.apply import apply
from armtool.calib.model import se3
from armtool.cli import app
from armtool.errors import ArmtoolError
from armtool.model.chain import load_chain
from tests.calib.point_dataset import write_point_dataset
from tests.ik.robots import erd

runner = CliRunner()
UR5 = erd("ur_description/urdf/ur5_robot.urdf")


def _tracker_dataset(directory: Path, n: int = 120, seed: int = 3) -> tuple[Path, np.ndarray]:  # type: ignore[type-arg]
    """A UR5 whose elbow has a once-per-turn error of 0.3°, tracked at a point 30 mm out on tool0's z."""
    chain = load_chain(UR5, "base_link", "tool0")
    rng = np.random.default_rng(seed)
    Q = chain.random(rng, n)
    theta = Q.copy()
    theta[:, 2] += math.radians(0.3) * np.sin(Q[:, 2])
    T = chain.fk_batch(theta)
    points = T[:, :3, :3] @ np.array([0.0, 0.0, 0.03]) + T[:, :3, 3] + rng.normal(scale=2e-5, size=(n, 3))
    tracker_base = se3.inv(se3.xyz_rpy([1.2, 0.3, 0.2], [0.0, 0.0, 2.5]))
    measured = points @ tracker_base[:3, :3].T + tracker_base[:3, 3]
    rows = ((str(k), q, p) for k, (q, p) in enumerate(zip(Q, measured * 1e3)))
    write_point_dataset(directory, UR5, chain.joint_names, rows)
    return directory, Q


def _fit(tmp_path: Path, *extra: str) -> Path:
    data, _Q = _tracker_dataset(tmp_path / "data")
    out = tmp_path / "out"
    result = runner.invoke(app, ["calibrate", "fit", str(data), "-o", str(out), *extra])
    assert result.exit_code == 0, result.output
    return out


def test_apply_predicts_what_the_fit_with_terms_predicted(tmp_path: Path) -> None:
    out = _fit(tmp_path, "--params", "origins,offsets,harmonics", "--folds", "0")
    document = yaml.safe_load((out / "calibration.yaml").read_text())
    terms = document["joint_terms"]
    assert terms["fitted"] == "origins + offsets + harmonics" and document["fitted"] == "origins + offsets"
    assert (out / "calibrated_with_terms.urdf").is_file()
    applied = tmp_path / "applied.csv"
    result = runner.invoke(
        app,
        ["calibrate", "apply", str(out / "calibration.yaml"), str(tmp_path / "data" / "data.csv"), "-o", str(applied)],
    )
    assert result.exit_code == 0, result.output
    with applied.open(newline="") as f:
        rows = list(csv.DictReader(f))
    readings = [[float(r[k]) for k in ("x", "y", "z")] for r in rows]  # kept as they were
    assert len(rows) == 120 and readings[0] == [
        float(v) for v in (tmp_path / "data" / "data.csv").read_text().splitlines()[1].split(",")[7:10]
    ]
    from scipy.spatial.transform import Rotation

    flange = np.array([[float(r[f"flange_{a}"]) for a in "xyz"] for r in rows])
    rotation = Rotation.from_quat([[float(r[f"flange_q{a}"]) for a in "xyzw"] for r in rows]).as_matrix()
    frames = terms["frames"]
    base_tracker = se3.xyz_rpy(frames["tracker_in_base"]["xyz"], frames["tracker_in_base"]["rpy"])
    tracker_base = se3.inv(base_tracker)
    in_base = rotation @ np.array(frames["point_in_flange"]["xyz"]) + flange
    predicted = (in_base @ tracker_base[:3, :3].T + tracker_base[:3, 3]) * 1e3
    error = np.linalg.norm(predicted - np.array(readings), axis=1)
    rms = float(np.sqrt(np.mean(error**2)))  # per point, as the fit reports it
    assert abs(rms - terms["fit_rms_mm"]["calibrated"]) < 1e-4  # calibration.yaml's frames are rounded to 1e-9
    assert rms < 0.04  # 0.02 mm noise per coordinate: the elbow's harmonic is applied
    assert document["metrics"]["fit_rms_mm"]["calibrated"] > 2 * rms  # calibrated.urdf alone cannot hold it
    # the joint values differ from the readings by nothing on average: the URDF's zero offsets hold
    # each joint's mean correction, so calibrated_with_terms.urdf read as it is is the arm on average
    names = list(terms["joints"])
    values = np.array([[float(r[name]) for name in names] for r in rows])
    Q = np.array(
        [
            [float(v) for v in line.split(",")[1:7]]
            for line in (tmp_path / "data" / "data.csv").read_text().splitlines()[1:]
        ]
    )
    assert np.abs((values - Q).mean(axis=0)).max() < 1e-9
    elbow = terms["joints"]["elbow_joint"]
    assert elbow["zero_offset_in_urdf"] == pytest.approx(elbow["zero_offset"] + elbow["mean_correction"], abs=1e-11)


def test_apply_refuses_a_calibration_without_terms(tmp_path: Path) -> None:
    out = _fit(tmp_path, "--params", "origins,offsets", "--folds", "0")
    with pytest.raises(ArmtoolError) as info:
        apply(out / "calibration.yaml", tmp_path / "data" / "data.csv")
    assert "chose no joint terms" in info.value.what and "calibrated.urdf as they are" in (info.value.hint or "")


def test_apply_names_the_file_and_line_of_a_bad_reading(tmp_path: Path) -> None:
    out = _fit(tmp_path, "--params", "origins,offsets,harmonics", "--folds", "0")
    bad = tmp_path / "bad.csv"
    lines = (tmp_path / "data" / "data.csv").read_text().splitlines()
    cells = lines[3].split(",")
    cells[3] = "oops"
    bad.write_text("\n".join([*lines[:3], ",".join(cells)]) + "\n")
    with pytest.raises(ArmtoolError) as info:
        apply(out / "calibration.yaml", bad)
    assert info.value.where == f"{bad}:4" and "'oops' is not a number" in info.value.what
    missing = tmp_path / "missing.csv"
    missing.write_text("id,shoulder_pan_joint\n0,0.1\n")
    with pytest.raises(ArmtoolError) as info:
        apply(out / "calibration.yaml", missing)
    assert info.value.where == f"{missing}:1" and "elbow_joint" in info.value.what


def test_joint_terms_asked_for_alone_are_judged_and_written(tmp_path: Path) -> None:
    # --params harmonics: the geometry held nominal, so calibrated.urdf is the nominal robot, and the
    # verdict is on what was fitted, the harmonics (before: "only the measurement frames were fitted",
    # exit 1, and no calibrated_with_terms.urdf to apply them with)
    out = _fit(tmp_path, "--params", "harmonics", "--folds", "0")
    document = yaml.safe_load((out / "calibration.yaml").read_text())
    assert document["joint_terms"]["fitted"] == "harmonics" and document["fitted"] == "hand-eye only"
    assert (out / "calibrated_with_terms.urdf").is_file()
    assert document["verdict"]["improves_on_nominal"]
    terms = document["joint_terms"]["fit_rms_mm"]
    assert terms["calibrated"] < 0.5 * terms["hand_eye_only"]
