"""A target's corners in one image, as the fit reprojects them: (P, 2) pixels in the order of
`Target.points_m`, NaN for the points the image does not show, or None with the reason.

An AprilTag goes through armtool's tag detector (`apriltag.detect_tag`: edge-fitted corners, the
half-pixel convention corrected); a board through `boards.find_board` (OpenCV's ChArUco detector,
which keeps a partial view's corners with their ids; the chessboard detector with its orientation
decided; AprilTag grids through the tag refinement).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from armtool.calib.model.camera import Array, CameraModel
from armtool.calib.targets.spec import Target


def detect_corners(gray: NDArray[Any], target: Target, camera: CameraModel) -> tuple[Array | None, str]:
    """(corners (P, 2) or None, why not) of `target` in an 8-bit image of the camera's size."""
    if target.board is None:
        from armtool.calib.targets.apriltag import detect_tag

        det = detect_tag(gray, target.family, target.tag_id, camera)
        return (np.asarray(det.corners_px, dtype=np.float64), "") if det.ok else (None, det.reason)
    from armtool.calib.targets.apriltag import _as_gray
    from armtool.calib.targets.boards import board_points, find_board

    view = find_board(_as_gray(gray), target.board)
    if view.reason:
        return None, view.reason
    corners = np.full((len(board_points(target.board)), 2), np.nan)
    corners[view.ids] = view.pixels
    return corners, ""
