"""A measured-pose dataset written by hand: every stated convention is checked, each bad value is
reported at its file and line, and the rows become the poses that were written."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from armtool.calib.fit.measurements import dataset_measurements
from armtool.calib.inputs.conventions import PoseFrame
from armtool.calib.inputs.load import load_inputs
from armtool.model.chain import Chain
from tests.calib.measured_files import write_dataset
from tests.calib.synthetic import make_measured


@pytest.mark.parametrize("rotation", ["quaternion", "rpy", "matrix"])
@pytest.mark.parametrize("frame", list(PoseFrame))
def test_rows_become_the_poses_that_were_written(
    tmp_path: Path, clean_chain: Chain, rotation: str, frame: PoseFrame
) -> None:
    m = make_measured(clean_chain, n=5)
    ds, chain, camera = load_inputs(write_dataset(tmp_path / "ds", m, rotation=rotation, frame=frame))
    assert not ds.errors, ds.errors
    assert chain is not None and camera is None
    measured = dataset_measurements(ds.measurement, ds.measured_rows)  # type: ignore[arg-type]
    for sid, T in m.measurements.poses.items():  # type: ignore[attr-defined]
        assert np.allclose(measured.poses[sid], T, atol=1e-9)  # type: ignore[attr-defined]


def _manifest(path: Path) -> dict:  # type: ignore[type-arg]
    return yaml.safe_load((path / "dataset.yaml").read_text())


def _rewrite(path: Path, **observations: object) -> None:
    doc = _manifest(path)
    for key, value in observations.items():
        if value is None:
            doc["observations"].pop(key, None)
        else:
            doc["observations"][key] = value
    (path / "dataset.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"pose": None}, "observations.pose is missing (which frame is in which)"),
        ({"position_units": "inch"}, "observations.position_units is 'inch'"),
        ({"quaternion_order": None}, "observations.quaternion_order is missing"),
        ({"rotation": "euler"}, "observations.rotation is 'euler'"),
        ({"kind": "corners"}, "observations.kind is 'corners'"),
        ({"position_columns": ["x", "y"]}, "observations.position_columns must list 3 column names"),
        ({"sensor": "My Camera"}, "observations.sensor must be a short lower-case name"),
    ],
)
def test_every_convention_must_be_stated(tmp_path: Path, clean_chain: Chain, change: dict, message: str) -> None:  # type: ignore[type-arg]
    path = write_dataset(tmp_path / "ds", make_measured(clean_chain, n=4))
    _rewrite(path, **change)
    ds, _chain, _camera = load_inputs(path)
    assert any(message in p.what for p in ds.errors), [p.what for p in ds.errors]
    problem = next(p for p in ds.errors if message in p.what)
    assert problem.where == "ds/dataset.yaml" and (problem.hint or "one of" in problem.what)


def test_bad_rows_are_reported_at_their_line(tmp_path: Path, clean_chain: Chain) -> None:
    path = write_dataset(tmp_path / "ds", make_measured(clean_chain, n=6))
    lines = (path / "poses.csv").read_text().splitlines()
    fields = [line.split(",") for line in lines]
    fields[2][1] = "twelve"  # line 3: not a number
    fields[3][4] = "2.0"  # line 4: qw of 2, not a unit quaternion
    fields[4][2] = "nan"  # line 5
    fields[5][0] = "99"  # line 6: no such sample
    fields[6][0] = fields[1][0]  # line 7: the id of line 2 again
    (path / "poses.csv").write_text("\n".join(",".join(f) for f in fields) + "\n")
    ds, _chain, _camera = load_inputs(path)
    where = {p.where: p.what for p in ds.problems}
    assert "'x' is not a number" in where["ds/poses.csv:3"]
    assert "quaternion's norm is" in where["ds/poses.csv:4"]
    assert "NaN" in where["ds/poses.csv:5"]
    assert "'99' is not in the samples file" in where["ds/poses.csv:6"]
    assert "duplicate id" in where["ds/poses.csv:7"]
    missing = [p for p in ds.problems if p.severity == "warning" and "has no usable row" in p.what]
    # samples 1-3 have their row's error; 4 (its row names sample 99) and 5 (its row took the id of sample 0) none
    assert [p.what.split()[1] for p in missing] == ["4", "5"]
    assert missing[0].where.startswith("ds/joints.csv:")


def test_millimetres_declared_as_metres_are_caught_row_by_row(tmp_path: Path, clean_chain: Chain) -> None:
    m = make_measured(clean_chain, kind="point", n=3)
    path = write_dataset(tmp_path / "ds", m, units="mm", manifest={"position_units": "m"})
    ds, _chain, _camera = load_inputs(path)
    assert [p.where for p in ds.errors] == ["ds/points.csv:2", "ds/points.csv:3", "ds/points.csv:4"]
    assert all("is it in millimetres?" in p.what for p in ds.errors)


def test_a_unit_wrong_on_every_row_is_one_error_that_names_it(tmp_path: Path, clean_chain: Chain) -> None:
    # A tracker's millimetres declared as metres: one finding with the count and the first lines, not one per row.
    m = make_measured(clean_chain, kind="point", n=200)
    path = write_dataset(tmp_path / "ds", m, units="mm", manifest={"position_units": "m"})
    ds, _chain, _camera = load_inputs(path)
    assert len(ds.errors) == 1 and not [p for p in ds.problems if p.severity == "warning"], ds.problems
    error = ds.errors[0]
    assert error.where == "ds/points.csv:2"
    assert "200 of 200 rows (lines 2, 3, 4, …)" in error.what and "likely in millimetres" in error.what
    assert error.hint == "set observations.position_units: mm"


def test_angles_in_degrees_declared_as_radians_are_one_error(tmp_path: Path, clean_chain: Chain) -> None:
    path = write_dataset(tmp_path / "ds", make_measured(clean_chain, n=40, seed=3), rotation="rpy")
    _rewrite(path, angle_units="rad")
    ds, _chain, _camera = load_inputs(path)
    units = [p for p in ds.errors if "likely in degrees" in p.what]
    assert len(units) == 1 and units[0].hint == "set observations.angle_units: deg", ds.errors
    assert not [p for p in ds.errors if "look like degrees" in p.what]  # the rows it counts, not listed again


def _one_file(path: Path, measured: str) -> Path:
    """The dataset with joints.csv and the measurements merged into all.csv, named as both."""
    joints = (path / "joints.csv").read_text().splitlines()
    rows = (path / measured).read_text().splitlines()
    merged = [a + "," + ",".join(b.split(",")[1:]) for a, b in zip(joints, rows)]
    (path / "all.csv").write_text("\n".join(merged) + "\n")
    doc = _manifest(path)
    doc["samples"] = doc["observations"]["file"] = "all.csv"
    (path / "dataset.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def test_an_invalid_observations_section_in_the_samples_file_keeps_its_columns(
    tmp_path: Path, clean_chain: Chain
) -> None:
    # Joints and points in one CSV, observations: missing its unit: the point columns are the
    # measurements, so the advice is to fix observations:, never to remove them.
    path = _one_file(write_dataset(tmp_path / "ds", make_measured(clean_chain, kind="point", n=5)), "points.csv")
    doc = _manifest(path)
    del doc["observations"]["position_units"]
    (path / "dataset.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    ds, _chain, _camera = load_inputs(path)
    assert [p.what for p in ds.errors] == ["observations.position_units is missing (the unit of the positions)"]
    about_columns = [p for p in ds.problems if "x, y, z" in p.what]
    assert len(about_columns) == 1 and "keep the columns" in about_columns[0].hint
    assert not [p for p in ds.problems if "remove the column" in p.hint]


def test_joints_and_measurements_in_one_file(tmp_path: Path, clean_chain: Chain) -> None:
    # FIGAROH-style: one CSV with the joints and the measurement; its columns are no warning.
    path = _one_file(write_dataset(tmp_path / "ds", make_measured(clean_chain, n=4)), "poses.csv")
    ds, _chain, _camera = load_inputs(path)
    assert not ds.problems, ds.problems
    assert len(ds.measured_rows) == 4


def test_one_file_without_ids_and_with_its_own_joint_names(tmp_path: Path, clean_chain: Chain) -> None:
    # Joints named q1..q6 and the measurement in the same CSV, no id column (FIGAROH's layout):
    # robot.joint_columns maps the names, and the rows are matched by line.
    m = make_measured(clean_chain, n=5)
    path = write_dataset(tmp_path / "ds", m)
    joints = (path / "joints.csv").read_text().splitlines()
    poses = (path / "poses.csv").read_text().splitlines()
    header = ",".join(f"q{i + 1}" for i in range(clean_chain.n)) + "," + ",".join(poses[0].split(",")[1:])
    body = [",".join(a.split(",")[1:] + b.split(",")[1:]) for a, b in zip(joints[1:], poses[1:])]
    (path / "all.csv").write_text("\n".join([header, *body]) + "\n")
    doc = _manifest(path)
    doc["samples"] = doc["observations"]["file"] = "all.csv"
    doc["robot"]["joint_columns"] = {name: f"q{i + 1}" for i, name in enumerate(clean_chain.joint_names)}
    (path / "dataset.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    ds, _chain, _camera = load_inputs(path)
    assert not ds.problems, ds.problems
    assert [s.id for s in ds.samples] == ["2", "3", "4", "5", "6"]
    measured = dataset_measurements(ds.measurement, ds.measured_rows)  # type: ignore[arg-type]
    assert np.allclose(measured.poses["2"], m.measurements.poses["0"], atol=1e-9)  # type: ignore[attr-defined]


def test_two_files_without_ids_are_refused(tmp_path: Path, clean_chain: Chain) -> None:
    path = write_dataset(tmp_path / "ds", make_measured(clean_chain, n=4))
    text = (path / "poses.csv").read_text().splitlines()
    (path / "poses.csv").write_text("\n".join(",".join(line.split(",")[1:]) for line in text) + "\n")
    ds, _chain, _camera = load_inputs(path)
    assert any(p.where == "ds/poses.csv:1" and p.what == "no 'id' column" for p in ds.errors)
