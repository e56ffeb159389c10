"""Look-alike chessboards: the turn each image shows, decided by the robot's motion."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.calib.handeye.dataset import load_handeye_dataset
from armtool.calib.handeye.turns import board_turns, resolve_turns
from armtool.calib.handeye.views import View, find_views
from armtool.calib.model import se3
from armtool.calib.model.camera import load_intrinsics
from armtool.calib.targets.boards import parse_board
from tests.calib.handeye_data import Make


def _frames_agree(views: list[View], truth: np.ndarray) -> float:
    """The largest angle (°) between two images' board frames once each is compared with the true
    board pose: 0 when every image numbers the corners alike (whichever turn the first one took)."""
    relative = [se3.inv(truth[k]) @ v.cMt for k, v in enumerate(views) if v.usable and v.cMt is not None]
    return max(np.degrees(se3.pose_difference(relative[0], r)[1]) for r in relative)


@pytest.mark.parametrize(
    ("board", "turns"),
    [("chessboard:9x7:0.025", 2), ("chessboard:8x8:0.025", 2), ("chessboard:7x7:0.025", 4)],
    ids=["9x7 turns by 180°", "8x8 by 180° (90° by colour)", "7x7 by any quarter"],
)
def test_every_image_is_relabelled_to_one_board_frame(rendered: Make, board: str, turns: int) -> None:
    dataset, truth = rendered(board=parse_board(board), images=20, seed=2)
    ds = load_handeye_dataset(dataset)
    assert len(board_turns(ds.target)) == turns
    camera = load_intrinsics(ds.intrinsics)
    found = find_views(ds, camera)
    assert sum(v.usable for v in found) >= 18
    assert _frames_agree(found, truth.board_in_camera) > 80  # as detected, the images disagree
    views, turned = resolve_turns(found, ds.flanges(), ds.setup, ds.target, camera)
    assert turned
    assert _frames_agree(views, truth.board_in_camera) < 1.0


def test_a_board_whose_colours_tell_is_left_as_detected(rendered: Make) -> None:
    dataset, truth = rendered(images=20, seed=2)
    ds = load_handeye_dataset(dataset)
    camera = load_intrinsics(ds.intrinsics)
    found = find_views(ds, camera)
    views, turned = resolve_turns(found, ds.flanges(), ds.setup, ds.target, camera)
    assert turned == {} and views == found
    assert _frames_agree(found, truth.board_in_camera) < 1.0
