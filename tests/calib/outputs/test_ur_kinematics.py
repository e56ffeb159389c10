"""UR's kinematics file: written only for a URDF with the frames of UR's description, checked by
building the arm from the file's values as ur_macro.xacro does."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from armtool.calib.choices import Setup
from armtool.calib.outputs.ur_kinematics import (
    UR_JOINTS,
    check_ur_convention,
    ur_convention_error,
    ur_kinematics_yaml,
)
from armtool.errors import ArmtoolError
from armtool.model.chain import load_chain
from armtool.model.load import urdf_text
from tests.calib.measured_files import write_dataset
from tests.calib.synthetic import make_measured
from tests.ik.robots import erd

UR_DESCRIPTION = (
    Path(__file__).resolve().parents[3] / ".." / "shared" / "realworld" / "Universal_Robots_ROS2_Description"
)
UR_XACRO = UR_DESCRIPTION / "urdf" / "ur.urdf.xacro"
needs_ur = pytest.mark.skipif(not UR_XACRO.is_file(), reason="shared/realworld corpus absent")


@needs_ur
@pytest.mark.parametrize("ur_type", ["ur5", "ur10e"])
def test_ur_description_is_its_own_kinematics_file(ur_type: str) -> None:
    text = urdf_text(UR_XACRO, {"name": "ur", "ur_type": ur_type})
    error = ur_convention_error(text, dict(UR_JOINTS), "ur.urdf.xacro")
    assert error.same and error.max_m < 1e-9 and error.max_rad < 1e-9  # 0.000 mm
    check_ur_convention(text, dict(UR_JOINTS), "ur.urdf.xacro")


@needs_ur
def test_a_tf_prefix_is_followed() -> None:
    text = urdf_text(UR_XACRO, {"name": "ur", "ur_type": "ur5e", "tf_prefix": "left_"})
    joints = {key: "left_" + name for key, name in UR_JOINTS.items()}
    assert ur_convention_error(text, joints, "ur.urdf.xacro").same


def test_example_robot_data_ur5_is_about_a_metre_off() -> None:
    text = urdf_text(erd("ur_description/urdf/ur5_robot.urdf"))
    error = ur_convention_error(text, dict(UR_JOINTS), "ur5_robot.urdf")
    assert not error.same and 0.5 < error.mean_m < 1.5 and error.max_m > 1.0 and error.max_rad > 1.0
    with pytest.raises(ArmtoolError) as caught:
        ur_kinematics_yaml(text, dict(UR_JOINTS), "calib_1", "ur5_robot.urdf")  # never written
    assert "does not use the frames of UR's description" in caught.value.what
    assert "xacro ur.urdf.xacro" in caught.value.hint


def test_a_urdf_without_tool0_is_refused_with_the_frames_named(tmp_path: Path) -> None:
    text = urdf_text(erd("ur_description/urdf/ur5_robot.urdf")).replace('"tool0"', '"tcp"')
    with pytest.raises(ArmtoolError, match="no link 'tool0'"):
        check_ur_convention(text, dict(UR_JOINTS), "ur5_robot.urdf")


def test_fit_refuses_example_robot_data_ur5_before_the_work(tmp_path: Path) -> None:
    urdf = erd("ur_description/urdf/ur5_robot.urdf")
    m = make_measured(load_chain(urdf, "base_link", "tool0"), kind="point", n=12, setup=Setup.EYE_TO_HAND)
    dataset = write_dataset(tmp_path / "ds", m, urdf=urdf)
    kinematics = tmp_path / "kin.yaml"
    kinematics.write_text("kinematics:\n  hash: calib_1\n")
    out, written = tmp_path / "out", tmp_path / "my_robot_calibration.yaml"
    args = ["calibrate", "fit", str(dataset), "-o", str(out), "--ur-kinematics", str(written)]
    result = subprocess.run(
        [sys.executable, "-m", "armtool", *args, "--ur-kinematics-in", str(kinematics)], capture_output=True, text=True
    )
    assert result.returncode == 2, result.stderr
    flat = " ".join(result.stderr.split())
    assert "does not use the frames of UR's description" in flat and "Traceback" not in flat
    assert "mm from the URDF's on average" in flat
    assert not out.exists() and not written.exists()
