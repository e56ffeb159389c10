"""Rendered hand-eye datasets with known truth for the tests: a 640x480 camera (f = 600 px,
webcam-like distortion) and a 10x7 chessboard of 25 mm squares at 0.5-1.0 m, so that images render
fast; `copied` for a test that changes a dataset. The fits alone, without images, are tested on
`armtool.calib.handeye.simulate.corner_observations`.
"""

from __future__ import annotations

import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

from armtool.calib.handeye.simulate import SMALL_CAMERA, Rendered

CAMERA = SMALL_CAMERA
DEFAULTS: dict[str, Any] = {"images": 25, "camera": CAMERA, "distance_m": (0.5, 1.0)}
Make = Callable[..., tuple[Path, Rendered]]  # the `rendered` fixture: (dataset directory, truth) of a spec


def copied(dataset: Path, tmp_path: Path) -> Path:
    """A copy of a dataset that a test may change."""
    out = tmp_path / "dataset"
    shutil.copytree(dataset, out)
    return out
