"""Dataset loading: every problem named with its file and row."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from armtool.calib.inputs.dataset import load_dataset, require_ok
from armtool.errors import ArmtoolError
from tests.calib.conftest import CLEAN_ARM

JOINTS = ["joint1", "joint2", "joint3", "joint4", "joint5", "joint6"]


def _dataset(tmp_path: Path, rows: list[str], header: str = "id,image," + ",".join(JOINTS), extra: str = "") -> Path:
    shutil.copy(CLEAN_ARM, tmp_path / "robot.urdf")
    (tmp_path / "camera.yaml").write_text(
        "image_width: 1280\nimage_height: 720\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [910, 0, 640, 0, 910, 360, 0, 0, 1]\ndistortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [0, 0, 0, 0, 0]\n"
    )
    (tmp_path / "samples.csv").write_text("\n".join([header, *rows]) + "\n")
    (tmp_path / "dataset.yaml").write_text(
        "format: armtool-calib-dataset/1\nsetup: eye_to_hand\n"
        f"robot: {{urdf: robot.urdf, base_link: base_link, flange_link: tool0, joints: [{', '.join(JOINTS)}], joint_units: rad}}\n"
        "camera: {intrinsics: camera.yaml}\n"
        "target: {type: apriltag, family: tag36h11, id: 0, size_m: 0.08, mounted_on: tool0}\n"
        "samples: samples.csv\n" + extra
    )
    return tmp_path


def test_good_dataset_loads(tmp_path: Path) -> None:
    ds = load_dataset(_dataset(tmp_path, ["0,images/0.png,0.1,0.2,0.3,0.4,0.5,0.6"]), JOINTS)
    assert not ds.errors
    assert np.allclose(ds.samples[0].q, [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]) and ds.samples[0].row == 2


def test_degrees_are_caught_with_the_row(tmp_path: Path) -> None:
    ds = load_dataset(_dataset(tmp_path, ["0,a.png,0,0,0,0,0,0", "1,b.png,10,45,90,120,-30,170"]), JOINTS)
    (p,) = ds.errors
    assert p.where.endswith("samples.csv:3") and "degrees" in p.what


def test_unknown_and_missing_joint_columns(tmp_path: Path) -> None:
    header = "id,image,joint1,joint2,joint3,joint4,joint5,jiont6"
    ds = load_dataset(_dataset(tmp_path, ["0,a.png,0,0,0,0,0,0"], header=header), JOINTS)
    (p,) = ds.errors
    assert p.where.endswith("samples.csv:1") and "joint6" in p.what


def test_missing_files_and_bad_values(tmp_path: Path) -> None:
    root = _dataset(tmp_path, ["0,a.png,0,0,0,0,0,x", "0,a.png,0,0,0,0,0,0", "1,a.png,0,0,0,0,0,nan"])
    (root / "camera.yaml").unlink()
    ds = load_dataset(root, JOINTS)
    messages = [(p.where.split("/")[-1], p.what) for p in ds.errors]
    assert any("camera.intrinsics 'camera.yaml' does not exist" in m for _, m in messages)
    assert ("samples.csv:2", "a joint value is not a number") in messages
    assert ("samples.csv:4", "a joint value is NaN or infinite") in messages
    with pytest.raises(ArmtoolError, match="does not exist"):
        require_ok(ds)


def test_units_other_than_radians_are_refused(tmp_path: Path) -> None:
    root = _dataset(tmp_path, ["0,a.png,0,0,0,0,0,0"])
    text = (root / "dataset.yaml").read_text().replace("joint_units: rad", "joint_units: deg")
    (root / "dataset.yaml").write_text(text)
    ds = load_dataset(root, JOINTS)
    assert any("joint_units is 'deg'" in p.what for p in ds.errors)


def test_corners_csv(tmp_path: Path) -> None:
    root = _dataset(tmp_path, ["0,,0,0,0,0,0,0", "1,,0,0,0,0,0,0.1"], extra="corners: corners.csv\n")
    (root / "corners.csv").write_text(
        "id,tag_id,u0,v0,u1,v1,u2,v2,u3,v3\n0,0,1,2,3,4,5,6,7,8\n1,5,1,2,3,4,5,6,7,8\n7,0,1,2,3,4,5,6,7,8\n"
    )
    ds = load_dataset(root, JOINTS)
    assert list(ds.corners) == ["0"] and ds.corners["0"].shape == (4, 2)
    (p,) = ds.errors
    assert p.where.endswith("corners.csv:4") and "'7'" in p.what


def test_wrong_types_in_the_manifest(tmp_path: Path) -> None:
    root = _dataset(tmp_path, ["0,a.png,0,0,0,0,0,0"])
    text = (root / "dataset.yaml").read_text().replace("size_m: 0.08", "size_m: eighty").replace("id: 0,", "id: zero,")
    (root / "dataset.yaml").write_text(text)
    whats = [p.what for p in load_dataset(root, JOINTS).errors]
    assert "'target.size_m' must be a number, got 'eighty'" in whats
    assert "'target.id' must be an integer, got 'zero'" in whats
