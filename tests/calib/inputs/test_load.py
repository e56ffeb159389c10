"""Loading a dataset with its chain and camera, and what the tag detection adds to `check`."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from armtool.calib.inputs.load import detection_problems, input_files, load_inputs
from armtool.calib.inputs.observations import Observation
from tests.calib.inputs.test_dataset import JOINTS, _dataset


def test_a_good_dataset_loads_with_its_chain_and_camera(tmp_path: Path) -> None:
    ds, chain, camera = load_inputs(_dataset(tmp_path, ["0,images/0.png,0.1,0.2,0.3,0.4,0.5,0.6"]))
    assert not ds.errors and chain is not None and chain.joint_names == JOINTS
    assert camera is not None and camera.width == 1280
    assert tmp_path / "samples.csv" in [p.resolve() for p in input_files(ds, None)]


def test_a_broken_intrinsics_file_is_a_problem_not_an_exception(tmp_path: Path) -> None:
    root = _dataset(tmp_path, ["0,images/0.png,0.1,0.2,0.3,0.4,0.5,0.6"])
    (root / "camera.yaml").write_text("image_width: 1280\n")
    ds, chain, camera = load_inputs(root)
    assert chain is not None and camera is None
    assert any(p.where == "camera.yaml" for p in ds.errors)


def test_detection_problems_warn_per_sample_and_fail_when_most_are_missing(tmp_path: Path) -> None:
    rows = [f"{i},images/{i}.png,0.1,0.2,0.3,0.4,0.5,0.6" for i in range(6)]
    ds, _chain, _camera = load_inputs(_dataset(tmp_path, rows))
    seen = {s.id: Observation(s.id, np.zeros((4, 2)) if s.id in "01" else None, "tag not found") for s in ds.samples}
    problems = detection_problems(ds, seen)
    warnings = [p for p in problems if p.severity == "warning"]
    assert [p.where for p in warnings] == [f"samples.csv:{r}" for r in (4, 5, 6, 7)]
    assert [p.what for p in problems if p.severity == "error"] == ["tag 0 (tag36h11) was usable in only 2 of 6 samples"]
    seen = {s.id: Observation(s.id, np.zeros((4, 2))) for s in ds.samples}
    assert detection_problems(ds, seen) == []
