"""Calibration boards: chessboards, ChArUco boards and AprilTag grids, and finding their corners.

A board is given on the command line (`calibrate camera --board`, `simulate --target`,
`import-bag --target`) and in dataset.yaml (`target.board`) as a short spec (`parse_board`):

* `chessboard:COLSxROWS:SQUARE`: a plain chessboard of COLS×ROWS squares (not inner corners:
  OpenCV's `patternSize` is (COLS−1, ROWS−1)) of edge SQUARE metres. Its inner corners come from
  OpenCV's `findChessboardCornersSB`, the whole board must be in view, and their order is decided
  from the squares' colours (`armtool.calib.targets.chessboard`): with one even and one odd count
  (e.g. 10x7) the board frame is the same in every image; with both even or both odd the board
  looks the same turned by 180°, which is fine for `calibrate camera` but refused as a fit target.
* `charuco:COLSxROWS:SQUARE:MARKER[:DICT]`: OpenCV's ChArUco board of COLS×ROWS chessboard
  squares of edge SQUARE metres with ArUco markers of edge MARKER in the white squares (OpenCV
  ≥ 4.6 layout: the top-left square is black). DICT defaults to DICT_6X6_250, as in OpenCV's
  ChArUco tutorial; any `cv2.aruco` dictionary name works, with or without the `DICT_` prefix.
  Its inner chessboard corners are what the calibration uses: saddle points refined by
  `cornerSubPix`, which blur does not move.
* `aprilgrid:COLSxROWS:TAG:GAP[:FAMILY]`: a grid of AprilTags (OpenCV's `aruco.GridBoard`) of
  edge TAG metres (the black square) with GAP metres between tags, ids 0, 1, 2, … row by row
  from the top-left; FAMILY defaults to tag36h11. Its tag corners come from armtool's AprilTag detector (`armtool.calib.targets.apriltag`: edge-fitted
  corners, the half-pixel convention corrected).

Board frame (OpenCV's): origin at the top-left corner of the board's pattern, x right, y down
(as printed), z into the board. A chessboard's frame starts at the outer corner of its black
corner square from which the COLS squares run along x with y down the ROWS (OpenCV's ChArUco layout
without the markers: the first square is black).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from enum import Enum
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armtool.calib.model.camera import Array
from armtool.errors import ArmtoolError

DEFAULT_CHARUCO_DICT = "DICT_6X6_250"
DEFAULT_GRID_FAMILY = "tag36h11"
_SPEC_HINT = (
    "e.g. chessboard:10x7:0.025 (squares, not inner corners), charuco:9x7:0.030:0.022[:DICT_6X6_250] "
    "or aprilgrid:6x4:0.04:0.01[:tag36h11] (lengths in metres)"
)


class BoardKind(str, Enum):
    CHESSBOARD = "chessboard"
    CHARUCO = "charuco"
    APRILGRID = "aprilgrid"


@dataclass(frozen=True)
class BoardSpec:
    """What is printed: `cols`×`rows` squares (chessboard, ChArUco) or tags (grid), lengths in metres."""

    kind: BoardKind
    cols: int
    rows: int
    square_m: float  # chessboard, ChArUco: square edge; grid: tag edge (black square)
    marker_m: float  # ChArUco: ArUco marker edge; grid: gap between tags; chessboard: 0
    dictionary: str  # cv2.aruco constant name (DICT_...) or AprilTag family (tag36h11); chessboard: ""

    @property
    def symmetric(self) -> bool:
        """A chessboard that looks the same turned by 180°: its frame cannot be told from one image."""
        from armtool.calib.targets.chessboard import symmetric

        return self.kind is BoardKind.CHESSBOARD and symmetric(self.cols, self.rows)

    def text(self) -> str:
        """The spec as `parse_board` reads it back (for dataset.yaml)."""
        if self.kind is BoardKind.CHESSBOARD:
            return f"chessboard:{self.cols}x{self.rows}:{self.square_m:g}"
        last = self.family if self.kind is BoardKind.APRILGRID else self.dictionary
        return f"{self.kind.value}:{self.cols}x{self.rows}:{self.square_m:g}:{self.marker_m:g}:{last}"

    @property
    def family(self) -> str:
        """The AprilTag family of a grid board (tag36h11, ...)."""
        from armtool.calib.targets.apriltag import FAMILIES

        return next((f for f, d in FAMILIES.items() if d == self.dictionary), self.dictionary)

    @property
    def min_points_per_view(self) -> int:
        """Corners a view needs to constrain a pose well: 2 tags, or 8 ChArUco corners; a chessboard
        is found whole or not at all."""
        return (self.cols - 1) * (self.rows - 1) if self.kind is BoardKind.CHESSBOARD else 8

    def describe(self) -> str:
        if self.kind is BoardKind.CHESSBOARD:
            inner = f"{self.cols - 1}x{self.rows - 1} inner corners"
            return f"chessboard {self.cols}x{self.rows} squares ({inner}), squares {self.square_m * 1000:g} mm"
        if self.kind is BoardKind.CHARUCO:
            return f"ChArUco {self.cols}x{self.rows}, squares {self.square_m * 1000:g} mm, markers {self.marker_m * 1000:g} mm, {self.dictionary}"
        return f"AprilTag grid {self.cols}x{self.rows} ({self.family}), tags {self.square_m * 1000:g} mm, gaps {self.marker_m * 1000:g} mm"


def parse_board(text: str) -> BoardSpec:
    """`chessboard:COLSxROWS:SQUARE`, `charuco:COLSxROWS:SQUARE:MARKER[:DICT]` or
    `aprilgrid:COLSxROWS:TAG:GAP[:FAMILY]`."""
    import cv2

    from armtool.calib.targets.apriltag import FAMILIES

    parts = [p.strip() for p in str(text).split(":")]
    try:
        kind = BoardKind(parts[0].lower())
    except ValueError:
        raise ArmtoolError(f"unknown board type '{parts[0]}' in board '{text}'", hint=_SPEC_HINT) from None
    fields = (3,) if kind is BoardKind.CHESSBOARD else (4, 5)
    if len(parts) not in fields:
        wanted = "3 fields (chessboard:COLSxROWS:SQUARE)" if kind is BoardKind.CHESSBOARD else "4 or 5 fields"
        raise ArmtoolError(f"board '{text}' needs {wanted} separated by ':'", hint=_SPEC_HINT)
    grid = re.fullmatch(r"(\d+)[xX](\d+)", parts[1])
    if grid is None:
        raise ArmtoolError(f"board size '{parts[1]}' is not COLSxROWS", hint=_SPEC_HINT)
    cols, rows = int(grid.group(1)), int(grid.group(2))
    lengths = parts[2:4]
    try:
        a, b = (float(v) for v in lengths) if len(lengths) == 2 else (float(lengths[0]), 0.0)
    except ValueError:
        raise ArmtoolError(
            f"board length(s) {' and '.join(repr(v) for v in lengths)} must be numbers in metres", hint=_SPEC_HINT
        ) from None
    if not (0 < a < 2 and (0 < b < 2 or kind is BoardKind.CHESSBOARD)):
        got = f"{a} and {b}" if len(lengths) == 2 else f"{a}"
        raise ArmtoolError(f"board lengths must be in metres (0 < length < 2), got {got}", hint="e.g. 0.03 for 30 mm")
    if kind is BoardKind.CHESSBOARD:
        if cols < 3 or rows < 3:
            raise ArmtoolError(
                f"a chessboard needs at least 3x3 squares, got {cols}x{rows}",
                hint="COLSxROWS counts squares; OpenCV's patternSize counts inner corners, one fewer each way",
            )
        return BoardSpec(kind, cols, rows, a, 0.0, "")
    if kind is BoardKind.CHARUCO:
        if cols < 3 or rows < 3:
            raise ArmtoolError(f"a ChArUco board needs at least 3x3 squares, got {cols}x{rows}")
        if b >= a:
            raise ArmtoolError(f"the ChArUco marker ({b} m) must be smaller than the square ({a} m)", hint=_SPEC_HINT)
        name = parts[4] if len(parts) == 5 else DEFAULT_CHARUCO_DICT
        name = name.upper() if name.upper().startswith("DICT_") else "DICT_" + name.upper()
        if name.startswith("DICT_APRILTAG_"):
            name = "DICT_APRILTAG_" + name[len("DICT_APRILTAG_") :].lower()
        if not isinstance(getattr(cv2.aruco, name, None), int):
            known = sorted(
                n for n in dir(cv2.aruco) if n.startswith("DICT_") and isinstance(getattr(cv2.aruco, n), int)
            )
            raise ArmtoolError(f"unknown ArUco dictionary '{parts[4]}'", hint="known: " + ", ".join(known))
        spec = BoardSpec(kind, cols, rows, a, b, name)
        markers = (cols * rows) // 2
    else:
        if cols * rows < 2:
            raise ArmtoolError(f"an AprilTag grid needs at least 2 tags, got {cols}x{rows}")
        family = parts[4] if len(parts) == 5 else DEFAULT_GRID_FAMILY
        if family not in FAMILIES:
            raise ArmtoolError(f"unknown AprilTag family '{family}'", hint="valid families: " + ", ".join(FAMILIES))
        spec = BoardSpec(kind, cols, rows, a, b, FAMILIES[family])
        markers = cols * rows
    size = int(_dictionary(spec.dictionary).bytesList.shape[0])
    if markers > size:
        raise ArmtoolError(
            f"the board needs {markers} markers but {spec.dictionary} has only {size}", hint="use a larger dictionary"
        )
    return spec


def _dictionary(name: str) -> Any:
    import cv2

    return cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, name))


def cv_board(spec: BoardSpec) -> Any:
    """The cv2.aruco.CharucoBoard or GridBoard of a spec (a chessboard has none: it has no markers)."""
    import cv2

    if spec.kind is BoardKind.CHESSBOARD:
        raise ArmtoolError("internal: a chessboard has no cv2.aruco board")
    if spec.kind is BoardKind.CHARUCO:
        return cv2.aruco.CharucoBoard(
            (spec.cols, spec.rows), spec.square_m, spec.marker_m, _dictionary(spec.dictionary)
        )
    return cv2.aruco.GridBoard((spec.cols, spec.rows), spec.square_m, spec.marker_m, _dictionary(spec.dictionary))


def board_size_m(spec: BoardSpec) -> tuple[float, float]:
    """Width and height (m) of a board's pattern (squares, or tags and the gaps between them)."""
    if spec.kind is BoardKind.APRILGRID:
        pitch = spec.square_m + spec.marker_m
        return spec.cols * pitch - spec.marker_m, spec.rows * pitch - spec.marker_m
    return spec.cols * spec.square_m, spec.rows * spec.square_m


def board_points(spec: BoardSpec) -> Array:
    """Every corner the calibration can use, (N,3) in the board frame, indexed by point id.

    Chessboard and ChArUco: the inner chessboard corners, row by row from the first square (id =
    OpenCV's ChArUco corner id; the point between squares (i, j) and (i+1, j+1) is at ((i+1)·s,
    (j+1)·s)). Grid: the 4 corners of each tag in cv2.aruco's order (TL, TR, BR, BL as printed),
    id = 4 × tag index + corner.
    """
    if spec.kind is BoardKind.CHESSBOARD:
        j, i = np.mgrid[1 : spec.rows, 1 : spec.cols]
        s = spec.square_m
        return np.stack([i.ravel() * s, j.ravel() * s, np.zeros(i.size)], axis=1).astype(np.float64)
    board = cv_board(spec)
    if spec.kind is BoardKind.CHARUCO:
        return np.asarray(board.getChessboardCorners(), dtype=np.float64).reshape(-1, 3)
    return np.asarray(board.getObjPoints(), dtype=np.float64).reshape(-1, 3)


@dataclass(frozen=True)
class BoardView:
    """The board's corners found in one image: point ids into `board_points` and their pixels."""

    ids: NDArray[np.int64]
    pixels: Array  # (N,2), OpenCV pixel convention (centres at integers)
    reason: str = ""  # why the view is unusable ("" when usable)


def find_board(gray: NDArray[np.uint8], spec: BoardSpec) -> BoardView:
    """The board's corners in an 8-bit grey image; too few corners give an empty view with a reason."""
    if spec.kind is BoardKind.CHESSBOARD:
        from armtool.calib.targets.chessboard import find_chessboard

        found = find_chessboard(gray, spec.cols, spec.rows)
        if found.pixels is None:
            return BoardView(np.zeros(0, dtype=np.int64), np.zeros((0, 2)), found.reason)
        return BoardView(np.arange(len(found.pixels), dtype=np.int64), found.pixels)
    ids, pixels = _charuco_corners(gray, spec) if spec.kind is BoardKind.CHARUCO else _grid_corners(gray, spec)
    if spec.kind is BoardKind.CHARUCO and len(ids) >= spec.min_points_per_view and _collinear(ids, spec):
        return BoardView(ids, pixels, f"board not usable: its {len(ids)} ChArUco corners lie on one line")
    if len(ids) < spec.min_points_per_view:
        what = "ChArUco corners" if spec.kind is BoardKind.CHARUCO else "tag corners"
        return BoardView(
            ids, pixels, f"board not found: {len(ids)} {what} (at least {spec.min_points_per_view} needed)"
        )
    return BoardView(ids, pixels)


def _collinear(ids: NDArray[np.int64], spec: BoardSpec) -> bool:
    """ChArUco corners that all lie on one row or column of the board give no pose."""
    return bool(cv_board(spec).checkCharucoCornersCollinear(ids.reshape(-1, 1).astype(np.int32)))


def _charuco_corners(gray: NDArray[np.uint8], spec: BoardSpec) -> tuple[NDArray[np.int64], Array]:
    import cv2

    detector = cv2.aruco.CharucoDetector(cv_board(spec))
    corners, ids, _, _ = detector.detectBoard(gray)
    if ids is None or corners is None or len(ids) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 2))
    return np.asarray(ids, dtype=np.int64).reshape(-1), np.asarray(corners, dtype=np.float64).reshape(-1, 2)


def _grid_corners(gray: NDArray[np.uint8], spec: BoardSpec) -> tuple[NDArray[np.int64], Array]:
    """Every tag of the grid: found by cv2.aruco, corners refined by armtool's AprilTag refinement."""
    from armtool.calib.targets.apriltag import _detect, _refine

    family = spec.family
    rough_corners, tag_ids = _detect(gray, family, "none")
    count = spec.cols * spec.rows
    seen = [i for i in tag_ids if 0 <= i < count]
    ids: list[int] = []
    pixels: list[Array] = []
    for rough, tag in zip(rough_corners, tag_ids):
        if not 0 <= tag < count or seen.count(tag) > 1:
            continue  # not on this board, or ambiguous
        refined, hits = _refine(gray, family, tag, rough, None)
        if refined is None or hits != 1:
            continue
        ids.extend(4 * tag + k for k in range(4))
        pixels.append(refined)
    if not ids:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 2))
    return np.asarray(ids, dtype=np.int64), np.concatenate(pixels).reshape(-1, 2)
