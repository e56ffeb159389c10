"""Which turn of a look-alike chessboard each image shows, from the robot's motion.

A chessboard with both counts even or both odd looks the same turned by 180° (a square one with an
odd count, by any quarter turn: `targets.chessboard.lookalike_turns`), so no image tells which of
its corners is which, and a fit that took the detector's order would see the board jump between
images. The motion tells: for any two images, the flange's motion A = G_j⁻¹ G_i and the camera's
B = C_j C_i⁻¹ are the same screw seen from two frames (A X = X B), so they turn by the same angle
and slide along their axis by the same distance (Chen's screw invariants, which need neither X nor
Z). Relabelling image j's corners by a turn S changes C_j into C_j S and with it B's angle and slide;
the turn that keeps them equal to A's, over the images already decided, is the one the image shows.
The first image (the one whose board pose is best determined) fixes the board's frame.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from armtool.calib.choices import Setup
from armtool.calib.fit.handeye import kabsch
from armtool.calib.handeye.views import View, posed
from armtool.calib.model import se3
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.calib.targets.boards import BoardKind
from armtool.calib.targets.spec import Target

ANGLE_SCALE_RAD = math.radians(0.5)  # how far apart the two angles of a right pair typically are
SLIDE_SCALE_M = 0.002
REFERENCES = 12  # decided images each new image is compared with


def board_turns(target: Target) -> list[NDArray[np.intp]]:
    """The relabellings of the board's point ids under which it looks alike (the identity first)."""
    from armtool.calib.targets.chessboard import lookalike_turns

    board = target.board
    if board is None or board.kind is not BoardKind.CHESSBOARD:
        return [np.arange(len(target.points_m))]
    count = lookalike_turns(board.cols, board.rows)
    grid = np.arange((board.cols - 1) * (board.rows - 1)).reshape(board.rows - 1, board.cols - 1)
    if count == 2:
        return [grid.reshape(-1), grid[::-1, ::-1].reshape(-1)]
    return [np.rot90(grid, k).reshape(-1) for k in range(count)]


def resolve_turns(
    views: Sequence[View], flanges: Array, setup: Setup, target: Target, camera: CameraModel
) -> tuple[list[View], dict[int, int]]:
    """The views with each look-alike board's corners relabelled to the turn the motion says, and
    {view index: turn} for the views that were turned (module docstring)."""
    turns = board_turns(target)
    usable = [k for k, v in enumerate(views) if v.usable and v.cMt is not None]
    if len(turns) == 1 or len(usable) < 3:
        return list(views), {}
    G = flanges if setup is Setup.EYE_IN_HAND else se3.inv(flanges)
    points = target.points_m
    # Relabelling id m as perm[m] pairs each pixel with S · p_m (points[perm] = S · points), so the
    # image's pose becomes C S⁻¹.
    undo = [se3.inv(kabsch(points, points[perm])) for perm in turns]
    order = sorted(usable, key=lambda k: views[k].pnp_rms_px * float(views[k].cMt[2, 3]))  # type: ignore[index]
    decided: dict[int, Array] = {order[0]: views[order[0]].cMt}  # type: ignore[dict-item]
    chosen: dict[int, int] = {}
    for j in order[1:]:
        Cj = views[j].cMt
        assert Cj is not None
        refs = list(decided)[:REFERENCES]
        costs = [sum(_mismatch(G[i], G[j], decided[i], Cj @ S) for i in refs) for S in undo]
        k = int(np.argmin(costs))
        decided[j] = Cj @ undo[k]
        if k:
            chosen[j] = k
    out = list(views)
    for j, k in chosen.items():
        view = views[j]
        ids = turns[k][view.ids]
        out[j] = posed(replace(view, ids=ids), target, camera)
    return out, chosen


def _mismatch(Gi: Array, Gj: Array, Ci: Array, Cj: Array) -> float:
    """How far the screw invariants (angle, slide along the axis) of the flange's and the camera's
    motion between two images differ, in typical units."""
    A = se3.inv(Gj) @ Gi
    B = Cj @ se3.inv(Ci)
    (ta, sa), (tb, sb) = _screw(A), _screw(B)
    return abs(ta - tb) / ANGLE_SCALE_RAD + abs(sa - sb) / SLIDE_SCALE_M


def _screw(T: Array) -> tuple[float, float]:
    """(rotation angle, translation along the rotation axis) of a rigid motion."""
    r = se3.log3(T[:3, :3])
    angle = float(np.linalg.norm(r))
    slide = float(abs(T[:3, 3] @ r) / angle) if angle > 1e-9 else float(np.linalg.norm(T[:3, 3]))
    return angle, slide
