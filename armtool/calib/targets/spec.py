"""The dataset's target: one AprilTag, or a board declared as `calibrate camera --board` spells it.

dataset.yaml says which:

    target: {type: apriltag, family: tag36h11, id: 0, size_m: 0.08, mounted_on: tool0}
    target: {board: charuco:9x7:0.03:0.022:DICT_5X5_100, mounted_on: tool0}
    target: {board: chessboard:10x7:0.025, mounted_on: tool0}

A board's corners become the observations the fit reprojects (`points_m`, indexed as
`boards.board_points` numbers them); a view that sees only some of them (a partial ChArUco view)
leaves the others NaN. A chessboard that looks the same turned by 180° is refused here: its frame
would flip between images and bend the fit (see `targets.chessboard`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from armtool.calib.model.camera import Array
from armtool.calib.targets.boards import BoardKind, BoardSpec, board_points, board_size_m, parse_board
from armtool.errors import ArmtoolError


class DeclaresTarget(Protocol):
    """What a dataset (armtool.calib.inputs.dataset.Dataset) says of its target."""

    family: str
    tag_id: int
    size_m: float
    board: BoardSpec | None


_BOARD_TYPES = {k.value for k in BoardKind}
_BOARD_HINT = "e.g. target: {board: charuco:9x7:0.03:0.022:DICT_5X5_100} or {board: chessboard:10x7:0.025}"


def declares_board(target: Any) -> bool:
    """True when dataset.yaml's `target:` is a board (it has `board:`, or a board `type:`)."""
    return isinstance(target, dict) and ("board" in target or str(target.get("type", "")).lower() in _BOARD_TYPES)


def board_target(target: Any) -> BoardSpec:
    """The board a `target:` that `declares_board` names; ArmtoolError (what, hint) when it is not usable."""
    if not isinstance(target, dict):
        raise ArmtoolError(f"target must be a mapping, got {target!r}", hint=_BOARD_HINT)
    text = target.get("board")
    kind = str(target.get("type", "")).lower()
    if text is None:
        raise ArmtoolError(f"target.type is '{kind}' but target.board is missing", hint=_BOARD_HINT)
    if not isinstance(text, str):
        raise ArmtoolError(f"target.board must be a board spec (text), got {text!r}", hint=_BOARD_HINT)
    try:
        spec = parse_board(text)
    except ArmtoolError as exc:
        raise ArmtoolError(f"target.board: {exc.what}", hint=exc.hint) from None
    if kind not in ("", "board", spec.kind.value):
        raise ArmtoolError(
            f"target.type is '{kind}' but target.board is a {spec.kind.value}",
            hint=f"write type: {spec.kind.value}, or leave type out",
        )
    if spec.symmetric:
        raise symmetric_board_error(spec, "target.board")
    return spec


def symmetric_board_error(spec: BoardSpec, source: str) -> ArmtoolError:
    """Why a fit refuses a chessboard that looks the same turned by 180° (`source`: where it was named)."""
    return ArmtoolError(
        f"{source} {spec.text()}: a {spec.cols}x{spec.rows} chessboard looks the same turned by 180°, so its "
        "frame cannot be told from an image and would flip between samples",
        hint="print a chessboard with one even and one odd number of squares (e.g. 10x7), or use a ChArUco board",
    )


def fit_board(text: str, source: str) -> BoardSpec:
    """A board spec from the command line (`source`: the option) that a fit can use."""
    spec = parse_board(text)
    if spec.symmetric:
        raise symmetric_board_error(spec, source)
    return spec


@dataclass(frozen=True)
class Target:
    """What every image of a dataset shows: one AprilTag (`board` None) or a board."""

    family: str = "tag36h11"
    tag_id: int = 0
    size_m: float = 0.08
    board: BoardSpec | None = None

    @classmethod
    def of(cls, ds: DeclaresTarget) -> Target:
        return cls(ds.family, ds.tag_id, ds.size_m, ds.board)

    @property
    def usable(self) -> bool:
        """False for a dataset whose board target could not be read (no board, no tag family)."""
        return self.board is not None or bool(self.family)

    @property
    def points_m(self) -> Array:
        """(P, 3) points in the target frame; an observation's corners are (P, 2) in this order."""
        if self.board is not None:
            return board_points(self.board)
        from armtool.calib.targets.apriltag import tag_object_points

        return tag_object_points(self.size_m)

    def describe(self) -> str:
        if self.board is not None:
            return self.board.describe()
        return f"tag {self.tag_id} ({self.family})" if self.usable else "the target"

    def document(self, mounted_on: str) -> dict[str, object]:
        """dataset.yaml's `target:` for a dataset armtool writes."""
        if self.board is None:
            return {
                "type": "apriltag",
                "family": self.family,
                "id": self.tag_id,
                "size_m": self.size_m,
                "size_definition": "edge of the black border square",
                "frame": "opencv aruco: origin at centre, x right, y up, z out of the face",
                "mounted_on": mounted_on,
            }
        return {
            "type": self.board.kind.value,
            "board": self.board.text(),
            "frame": "opencv board: origin at the pattern's first (top-left) corner, x along the columns, "
            "y down the rows, z into the board",
            "mounted_on": mounted_on,
        }

    def face_pose(self) -> Array:
        """The target's face frame in its own frame: origin at the centre of the pattern, z out of the
        printed face, x along the target's x. The identity for a tag (its frame is already that);
        for a board, whose z points into it, a half turn about x moved to the pattern's centre."""
        if self.board is None:
            return np.eye(4)
        width, height = board_size_m(self.board)
        return np.array(
            [[1.0, 0.0, 0.0, width / 2], [0.0, -1.0, 0.0, height / 2], [0.0, 0.0, -1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
        )


def named_target(target: str | None, tag_size: float | None, family: str = "tag36h11", tag_id: int = 0) -> Target:
    """The target a command line names: the board of `--target`, or the AprilTag (whose --tag-size is then
    required), as `import-bag` takes them."""
    if target is not None:
        return Target(board=fit_board(target, "--target"))
    if tag_size is None:
        raise ArmtoolError(
            "--tag-size is required for an AprilTag target",
            hint="measure the black square's edge on the print, in metres (e.g. --tag-size 0.08), or pass --target BOARD",
        )
    return Target(family, tag_id, tag_size)
