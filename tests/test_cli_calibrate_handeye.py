"""`armtool calibrate handeye` and `handeye-simulate` end to end: JSON, the result file, exit codes."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

from armtool.calib.handeye.simulate import HandEyeSimulation, Rendered, render, write_dataset
from armtool.calib.model import se3
from armtool.cli import app
from tests.calib.handeye_data import DEFAULTS, copied

ROOT = Path(__file__).resolve().parents[1]
runner = CliRunner()


def armtool(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "armtool", *args], capture_output=True, text=True, cwd=ROOT)


@pytest.fixture(scope="module")
def dataset(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Rendered]:
    spec = HandEyeSimulation(**{**DEFAULTS, "images": 16, "seed": 11})
    out = tmp_path_factory.mktemp("handeye") / "dataset"
    truth = render(spec)
    write_dataset(out, spec, truth)
    return out, truth


def _pose(doc: dict[str, object]) -> np.ndarray:
    return se3.xyz_rpy(doc["xyz_m"], doc["rpy_rad"])  # type: ignore[arg-type]


def test_handeye_prints_json_and_writes_the_frames(dataset: tuple[Path, Rendered], tmp_path: Path) -> None:
    path, truth = dataset
    out = tmp_path / "handeye.yaml"
    result = runner.invoke(app, ["calibrate", "handeye", str(path), "-o", str(out), "--format", "json", "--folds", "4"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["schema_version"] == 1 and summary["setup"] == "eye_in_hand"
    assert summary["heldout"]["folds"] == 4 and summary["heldout"]["rms_px"] < 1.0
    assert {m["method"] for m in summary["methods"]} >= {
        "tsai",
        "park",
        "horaud",
        "andreff",
        "daniilidis",
        "shah",
        "li",
    }
    written = yaml.safe_load(out.read_text())
    assert written["camera_in_flange"] == summary["camera_in_flange"]
    dt, angle = se3.pose_difference(_pose(written["camera_in_flange"]), truth.X)
    assert dt < 1e-3 and angle < np.radians(0.1)
    assert "held out" in result.stderr and "camera_in_flange: xyz" in result.stderr


def test_a_held_out_rms_above_max_rms_exits_1(dataset: tuple[Path, Rendered]) -> None:
    result = runner.invoke(app, ["calibrate", "handeye", str(dataset[0]), "--folds", "3", "--max-rms", "0.001"])
    assert result.exit_code == 1, result.output


def test_a_misdeclared_unit_exits_2_with_the_fix(dataset: tuple[Path, Rendered], tmp_path: Path) -> None:
    path = copied(dataset[0], tmp_path)
    doc = yaml.safe_load((path / "dataset.yaml").read_text())
    doc["poses"]["position_units"] = "mm"
    (path / "dataset.yaml").write_text(yaml.safe_dump(doc))
    proc = armtool("calibrate", "handeye", str(path), "--folds", "0")
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "the flange poses fit" in proc.stderr and "set poses.position_units: m" in proc.stderr
    kept = runner.invoke(app, ["calibrate", "handeye", str(path), "--folds", "0", "--keep-conventions"])
    assert kept.exit_code == 0 and "kept as declared (--keep-conventions)" in kept.stderr


def test_bad_input_exits_2_without_a_traceback(dataset: tuple[Path, Rendered], tmp_path: Path) -> None:
    proc = armtool("calibrate", "handeye", str(tmp_path))
    assert proc.returncode == 2 and "no dataset.yaml" in proc.stderr and "Traceback" not in proc.stderr
    proc = armtool("calibrate", "handeye", str(dataset[0]), "-o", str(dataset[0] / "dataset.yaml"))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr and "--out" in proc.stderr


def test_handeye_simulate_writes_a_dataset_that_handeye_reads(tmp_path: Path) -> None:
    out = tmp_path / "sim"
    result = runner.invoke(app, ["calibrate", "handeye-simulate", "-o", str(out), "--images", "3", "--seed", "2"])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in (out / "images").iterdir()) == ["0000.png", "0001.png", "0002.png"]
    truth = yaml.safe_load((out / "truth" / "truth.yaml").read_text())
    assert set(truth) >= {"camera_in_flange", "board_in_base"}
    from armtool.calib.handeye.dataset import load_handeye_dataset

    assert not load_handeye_dataset(out).errors
