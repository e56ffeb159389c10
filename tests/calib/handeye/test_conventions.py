"""A wrong pose convention is named with the dataset.yaml line that fixes it; the right one passes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from armtool.calib.handeye.conventions import check_conventions
from armtool.calib.handeye.dataset import load_handeye_dataset, require_ok
from armtool.calib.handeye.views import find_views
from armtool.calib.model import se3
from armtool.calib.model.camera import load_intrinsics
from tests.calib.handeye_data import Make, copied


def _check(dataset: Path):  # type: ignore[no-untyped-def]
    ds = load_handeye_dataset(dataset)
    require_ok(ds)
    camera = load_intrinsics(ds.intrinsics)
    return check_conventions(ds, find_views(ds, camera), camera)


def _declare(dataset: Path, **poses: object) -> None:
    doc = yaml.safe_load((dataset / "dataset.yaml").read_text())
    doc["poses"].update(poses)
    (dataset / "dataset.yaml").write_text(yaml.safe_dump(doc))


def test_the_declared_conventions_pass(rendered: Make) -> None:
    found = _check(rendered(images=15)[0])
    assert found.better is None and found.tried == 16
    assert found.message().startswith("the declared conventions fit best")


@pytest.mark.parametrize(
    ("declared", "fix"),
    [
        ({"position_units": "mm"}, "poses.position_units: m"),
        ({"quaternion_order": "wxyz"}, "poses.quaternion_order: xyzw"),
    ],
)
def test_a_wrong_convention_is_named(rendered: Make, tmp_path: Path, declared: dict[str, str], fix: str) -> None:
    dataset = copied(rendered(images=15)[0], tmp_path)
    _declare(dataset, **declared)
    found = _check(dataset)
    assert found.better is not None, found.message()
    assert found.better.changes == [fix]
    assert found.declared.median_rms_px > 30 * found.better.median_rms_px
    assert found.fix() == f"in dataset.yaml, set {fix}"


def test_an_inverted_pose_names_both_fixes(rendered: Make, tmp_path: Path) -> None:
    """base_in_flange declared for flange_in_base rows: the same equations as the other setup."""
    dataset = copied(rendered(images=15)[0], tmp_path)
    _declare(dataset, pose="base_in_flange")
    found = _check(dataset)
    assert found.better is not None and found.better.changes == ["poses.pose: flange_in_base"]
    assert "setup: eye_to_hand" in found.fix() and "check which is true" in found.fix()


def test_kuka_style_rpy_in_degrees_and_millimetres(rendered: Make, tmp_path: Path) -> None:
    """A, B, C = yaw, pitch, roll (R = Rz·Ry·Rx) in degrees and positions in mm, declared as
    roll-pitch-yaw multiplied the other way round: the rpy order is named."""
    dataset = copied(rendered(images=15)[0], tmp_path)
    ds = load_handeye_dataset(dataset)
    rows = ["image,X,Y,Z,A,B,C"]
    for shot, F in zip(ds.shots, ds.flanges()):
        roll, pitch, yaw = np.degrees(se3.rpy_of(F[:3, :3]))
        x, y, z = F[:3, 3] * 1000
        rows.append(f"{shot.image.relative_to(dataset)},{x:.4f},{y:.4f},{z:.4f},{yaw:.5f},{pitch:.5f},{roll:.5f}")
    (dataset / "poses.csv").write_text("\n".join(rows) + "\n")
    doc = yaml.safe_load((dataset / "dataset.yaml").read_text())
    doc["poses"] = {
        "file": "poses.csv",
        "pose": "flange_in_base",
        "position_units": "mm",
        "rotation": "rpy",
        "rpy_order": "xyz",
        "angle_units": "deg",
        "position_columns": ["X", "Y", "Z"],
        "rotation_columns": ["C", "B", "A"],  # roll, pitch, yaw
    }
    (dataset / "dataset.yaml").write_text(yaml.safe_dump(doc))
    found = _check(dataset)
    assert found.better is not None and found.better.changes == ["poses.rpy_order: zyx"]
    assert found.tried == 96
