"""`calibrate check` without the terminal: every problem of a dataset collected, and the note on
how well a measurement file's declared conventions fit."""

from __future__ import annotations

from pathlib import Path

from armtool.calib.check import check_dataset
from armtool.calib.inputs.dataset import Dataset
from armtool.calib.inputs.observations import Observation
from armtool.calib.model.camera import CameraModel
from armtool.calib.simulation.simulate import SimulationSpec, simulate
from tests.calib.conftest import CLEAN_ARM

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "calib"


def test_declared_conventions_that_fit_give_a_note_and_no_problem() -> None:
    ds, note = check_dataset(FIXTURES / "measured_poses", {}, [], detect=None)
    assert not ds.errors
    assert note is not None and note.startswith("the declared conventions fit best")


def test_a_pose_file_read_inverted_is_a_problem_of_dataset_yaml() -> None:
    ds, note = check_dataset(FIXTURES / "measured_poses_misdeclared", {}, [], detect=None)
    assert note is None
    [problem] = [p for p in ds.errors if p.where == "dataset.yaml"]
    assert "pose: sensor_in_target" in problem.hint


def test_detection_runs_when_asked_and_its_misses_are_problems(tmp_path: Path) -> None:
    simulate(CLEAN_ARM, tmp_path / "ds", None, "tool0", SimulationSpec(samples=4, validation=1))
    seen: list[int] = []

    def detect(ds: Dataset, camera: CameraModel) -> dict[str, Observation]:
        seen.append(len(ds.samples))
        return {s.id: Observation(s.id, None, "no tag found") for s in ds.samples}

    ds, note = check_dataset(tmp_path / "ds", {}, [], detect=None)
    assert not ds.problems and note is None and seen == []
    ds, _ = check_dataset(tmp_path / "ds", {}, [], detect=detect)
    assert seen == [4]
    assert sum(p.what.endswith("no tag found") for p in ds.problems) == 4
    assert [p.where for p in ds.errors] == ["dataset.yaml"]  # usable in 0 of 4 samples
