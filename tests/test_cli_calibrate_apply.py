"""`armtool calibrate apply` as a user runs it: a bad input is a message and exit 2, never a traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]


def armtool(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "armtool", *args], capture_output=True, text=True, cwd=ROOT)


def test_a_calibration_without_terms_is_refused_with_what_to_do(tmp_path: Path) -> None:
    calibration = tmp_path / "calibration.yaml"
    calibration.write_text(yaml.safe_dump({"format": "armtool-calibration/1", "joint_terms": None}))
    readings = tmp_path / "readings.csv"
    readings.write_text("shoulder_pan_joint\n0.1\n")
    result = armtool("calibrate", "apply", str(calibration), str(readings), "-o", str(tmp_path / "out.csv"))
    assert result.returncode == 2, result.stderr
    assert "chose no joint terms" in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "out.csv").exists()


def test_a_file_that_is_not_a_calibration_is_refused(tmp_path: Path) -> None:
    calibration = tmp_path / "calibration.yaml"
    calibration.write_text("just: text\n")
    result = armtool("calibrate", "apply", str(calibration), str(calibration), "-o", str(tmp_path / "out.csv"))
    assert result.returncode == 2 and "armtool-calibration/1" in result.stderr
