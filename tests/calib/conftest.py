"""Shared builders: a small chain, a synthetic problem with exactly known truth."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from armtool.calib.choices import Setup
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.camera import CameraModel
from armtool.model.chain import Chain, load_chain

ROOT = Path(__file__).resolve().parents[2]
CLEAN_ARM = ROOT / "fixtures" / "robots" / "clean_arm" / "urdf" / "clean_arm.urdf"


@pytest.fixture(scope="session")
def clean_chain() -> Chain:
    return load_chain(CLEAN_ARM, "base_link", "tool0")


@pytest.fixture(scope="session")
def camera() -> CameraModel:
    return CameraModel(np.array([[910.0, 0, 641.3], [0, 910.0, 358.7], [0, 0, 1]]), np.zeros(5), 1280, 720)


def nominal_model(chain: Chain, setup: Setup = Setup.EYE_TO_HAND) -> CalibModel:
    return CalibModel(chain, setup, np.eye(4), np.eye(4))
