"""The hand-eye dataset format: read as written, every convention stated, each bad row at its line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from armtool.calib.choices import Setup
from armtool.calib.handeye.dataset import load_handeye_dataset, require_ok
from armtool.errors import ArmtoolError
from tests.calib.handeye_data import Make, copied


def _edit(dataset: Path, change: dict[str, object], drop: tuple[str, ...] = ()) -> None:
    doc = yaml.safe_load((dataset / "dataset.yaml").read_text())
    doc["poses"].update(change)
    for key in drop:
        doc["poses"].pop(key)
    (dataset / "dataset.yaml").write_text(yaml.safe_dump(doc))


def test_a_simulated_dataset_reads_back_its_flange_poses(rendered: Make) -> None:
    dataset, truth = rendered()
    ds = load_handeye_dataset(dataset)
    require_ok(ds)
    assert ds.setup is Setup.EYE_IN_HAND and ds.target.board is not None
    assert len(ds.shots) == len(truth.images)
    assert np.allclose(ds.flanges(), truth.flanges, atol=1e-8)


def test_a_missing_convention_is_named_with_its_choices(rendered: Make, tmp_path: Path) -> None:
    dataset = copied(rendered()[0], tmp_path)
    _edit(dataset, {}, drop=("quaternion_order", "position_units"))
    ds = load_handeye_dataset(dataset)
    whats = [p.what for p in ds.errors]
    assert "poses.position_units is missing (the unit of the positions)" in whats
    assert "poses.quaternion_order is missing (the order of its columns)" in whats
    with pytest.raises(ArmtoolError) as raised:
        require_ok(ds)
    assert raised.value.where == "dataset.yaml" and "state it: one of m, mm" in (raised.value.hint or "")


def test_bad_rows_are_reported_at_their_line(rendered: Make, tmp_path: Path) -> None:
    dataset = copied(rendered()[0], tmp_path)
    lines = (dataset / "poses.csv").read_text().splitlines()
    lines[3] = lines[3].replace("images/0002.png", "images/missing.png")
    fields = lines[5].split(",")
    fields[4] = "x"  # qx
    lines[5] = ",".join(fields)
    fields = lines[7].split(",")
    fields[1] = "1200"  # metres: a unit mix-up
    lines[7] = ",".join(fields)
    fields = lines[9].split(",")
    fields[4:8] = ["0.5", "0.5", "0.5", "0.9"]  # not a unit quaternion
    lines[9] = ",".join(fields)
    (dataset / "poses.csv").write_text("\n".join(lines) + "\n")
    ds = load_handeye_dataset(dataset)
    found = {p.where: p.what for p in ds.errors}
    assert found["poses.csv:4"] == "image 'images/missing.png' does not exist"
    assert found["poses.csv:6"] == "'qx' is not a number: 'x'"
    assert found["poses.csv:8"] == "a position of 1200 m: is it in millimetres?"
    assert found["poses.csv:10"].startswith("the quaternion's norm is 1.2")
    assert len(ds.shots) == len(lines) - 1 - 4


def test_a_missing_column_names_the_header(rendered: Make, tmp_path: Path) -> None:
    dataset = copied(rendered()[0], tmp_path)
    _edit(dataset, {"rotation_columns": ["qw", "qx", "qy", "qz"], "quaternion_order": "wxyz", "image_column": "file"})
    ds = load_handeye_dataset(dataset)
    (problem,) = ds.errors
    assert problem.where == "poses.csv:1"
    assert problem.what.startswith("column(s) file missing (the header has image, x, y, z, qx, qy, qz, qw)")


def test_a_look_alike_chessboard_is_a_valid_target(rendered: Make, tmp_path: Path) -> None:
    """The kinematic fit refuses a 9x7 chessboard; hand-eye takes it (the motion tells its turn)."""
    dataset = copied(rendered()[0], tmp_path)
    doc = yaml.safe_load((dataset / "dataset.yaml").read_text())
    doc["target"] = {"board": "chessboard:9x7:0.025"}
    (dataset / "dataset.yaml").write_text(yaml.safe_dump(doc))
    ds = load_handeye_dataset(dataset)
    assert not ds.errors and ds.target.board is not None and ds.target.board.symmetric


def test_not_a_dataset_directory(tmp_path: Path) -> None:
    with pytest.raises(ArmtoolError, match="no dataset.yaml"):
        load_handeye_dataset(tmp_path)
