"""Synthetic datasets: eye-in-hand views are found on arms with fewer than six joints (issue 10 item 16)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from armtool.calib.choices import Setup
from armtool.calib.fit.calibration import FitOptions, calibrate
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.simulation.simulate import SimulationSpec, _place, _visible, default_camera
from armtool.calib.simulation.truth import score
from armtool.cli import app
from armtool.model.chain import load_chain
from tests.calib.conftest import CLEAN_ARM
from tests.calib.synthetic import make_problem
from tests.ik.robots import erd

FIVE_DOF = {  # robot: (path, base, flange)
    "so101": (lambda: erd("so_arm_description/urdf/so101.urdf"), "base_link", "gripper_frame_link"),
    "clean_arm_to_link5": (lambda: CLEAN_ARM, "base_link", "link5"),
}


@pytest.mark.parametrize("robot", sorted(FIVE_DOF))
def test_eye_in_hand_views_on_a_5_dof_arm(robot: str) -> None:
    path, base, flange = FIVE_DOF[robot]
    chain = load_chain(path(), base, flange)
    assert chain.n == 5
    spec = SimulationSpec(samples=60, validation=30, setup=Setup.EYE_IN_HAND, seed=0)
    nominal = CalibModel(chain, Setup.EYE_IN_HAND, np.eye(4), np.eye(4))
    L, R, pool = _place(nominal, spec, np.random.default_rng(0), default_camera())
    visible = _visible(nominal.with_frames(L, R), np.zeros(nominal.size), default_camera(), pool, spec)
    assert len(visible) >= 90
    # The views are spread over the joint space, not one pose repeated.
    assert (pool[visible].std(axis=0) > 0.1).sum() >= 4


def test_eye_in_hand_5_dof_calibrates() -> None:
    """The views found for a 5-DOF arm make a good calibration (clean_arm cut at link5: 0.2 m links;
    SO-101's fit works too but is slow, its 3-6 cm wrist makes the problem nearly degenerate)."""
    chain = load_chain(CLEAN_ARM, "base_link", "link5")
    p = make_problem(chain, n=40, seed=0, setup=Setup.EYE_IN_HAND)
    result = calibrate(p.model, p.measurements, p.samples, FitOptions(folds=0))
    before, after = score(result.model, result.x_handeye, p.truth), score(result.model, result.x, p.truth)
    assert before.position_rms_mm > 2 and after.position_rms_mm < 0.1


def test_simulate_eye_in_hand_on_a_5_dof_arm_from_the_command_line(tmp_path: Path) -> None:
    out = tmp_path / "so101"
    result = CliRunner().invoke(
        app,
        [
            "calibrate",
            "simulate",
            str(erd("so_arm_description/urdf/so101.urdf")),
            "--flange",
            "gripper_frame_link",
            "--setup",
            "eye_in_hand",
            "-o",
            str(out),
            "--samples",
            "8",
            "--validation",
            "4",
        ],
    )
    assert result.exit_code == 0, result.output
    assert len(list((out / "images").glob("*.png"))) == 8


def test_spec_takes_plain_strings_and_names_a_wrong_one() -> None:
    from armtool.calib.choices import Quality
    from armtool.errors import ArmtoolError

    spec = SimulationSpec(quality="poor", setup="eye_in_hand")  # type: ignore[arg-type]
    assert spec.quality is Quality.POOR and spec.setup is Setup.EYE_IN_HAND
    with pytest.raises(ArmtoolError) as err:
        SimulationSpec(quality="great")  # type: ignore[arg-type]
    assert "quality 'great'" in err.value.what and "typical" in (err.value.hint or "")
