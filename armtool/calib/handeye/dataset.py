"""The hand-eye dataset (`format: armtool-handeye-dataset/1`): images of a board and the flange pose of each.

One directory holds `dataset.yaml`, the camera intrinsics, the images and one CSV row per image:
the image's file and the flange pose the controller reported when it was taken. The pose's
conventions are stated in `poses:`, with the same keys and the same machinery as a calibration
dataset's `observations:` (`armtool.calib.inputs.conventions`); nothing is guessed:

    format: armtool-handeye-dataset/1
    setup: eye_in_hand                 # camera on the flange, board fixed (eye_to_hand: the reverse)
    camera: {intrinsics: camera.yaml}
    target: {board: chessboard:10x7:0.025}
    poses:
      file: poses.csv                  # image,x,y,z,qw,qx,qy,qz: one row per image
      image_column: image
      pose: flange_in_base             # or base_in_flange
      position_units: mm
      rotation: quaternion             # matrix, quaternion, rpy or rotation_vector
      quaternion_order: wxyz
      rotation_columns: [qw, qx, qy, qz]

Every problem is collected with its file and line, and raised together (`require_ok`).
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from armtool.calib.choices import Setup
from armtool.calib.inputs.conventions import (
    DEFAULT_POSITION_COLUMNS,
    ROTATION_SIZE,
    RPY_ORDERS,
    AngleUnit,
    LengthUnit,
    PoseConvention,
    PoseFrame,
    QuaternionOrder,
    RotationForm,
    default_rotation_columns,
)
from armtool.calib.inputs.dataset import Problem
from armtool.calib.limits import MAX_FILE_BYTES, MAX_SAMPLES
from armtool.calib.model.se3 import Array
from armtool.calib.targets.spec import Target
from armtool.errors import ArmtoolError

FORMAT = "armtool-handeye-dataset/1"
SECTION = "poses"
# How `poses.pose` spells each frame: a row holds the flange's pose in the base (what controllers
# report: KUKA's $POS_ACT, ABB's CRobT, UR's actual TCP pose with a zero TCP), or its inverse.
FRAMES = {PoseFrame.TARGET_IN_SENSOR: "flange_in_base", PoseFrame.SENSOR_IN_TARGET: "base_in_flange"}
_FRAME_OF = {text: frame for frame, text in FRAMES.items()}
_HINT = "see the hand-eye dataset format in docs/calibrate.md"


@dataclass(frozen=True)
class Shot:
    """One image and the flange pose the controller reported for it (the row's pose columns, as written)."""

    image: Path
    line: int  # in the poses file; 1 is the header
    values: Array


@dataclass
class HandEyeDataset:
    root: Path
    setup: Setup
    intrinsics: Path
    target: Target
    poses_file: Path
    convention: PoseConvention | None
    shots: list[Shot] = field(default_factory=list)
    problems: list[Problem] = field(default_factory=list)

    @property
    def errors(self) -> list[Problem]:
        return [p for p in self.problems if p.severity == "error"]

    def flanges(self, convention: PoseConvention | None = None) -> Array:
        """The flange's pose in the base (N, 4, 4), metres, of every shot, read as `convention` says
        (default: as declared)."""
        convention = convention or self.convention
        assert convention is not None
        return convention.poses(np.stack([s.values for s in self.shots]))

    def where(self, shot: Shot) -> str:
        return f"{self.poses_file.name}:{shot.line}"


def load_handeye_dataset(directory: Path) -> HandEyeDataset:
    """Read dataset.yaml and the poses file; problems are collected, not raised (see `require_ok`)."""
    from armtool.fileio import read_yaml

    root = directory.resolve()
    manifest = root / "dataset.yaml" if root.is_dir() else root
    root = manifest.parent
    if not manifest.is_file():
        raise ArmtoolError("no dataset.yaml", str(manifest), "pass a hand-eye dataset directory (" + _HINT + ")")
    doc = read_yaml(manifest, "dataset.yaml")
    if not isinstance(doc, dict):
        raise ArmtoolError("dataset.yaml must be a mapping", str(manifest), _HINT)
    where = "dataset.yaml"
    problems: list[Problem] = []
    if doc.get("format") != FORMAT:
        problems.append(
            Problem(where, f"format is {doc.get('format')!r}, expected '{FORMAT}'", f"add `format: {FORMAT}`")
        )
    setup_text = doc.get("setup")
    try:
        setup = Setup(setup_text)
    except ValueError:
        problems.append(
            Problem(
                where,
                f"setup is {setup_text!r}",
                "eye_in_hand (camera on the flange, board fixed) or eye_to_hand (camera fixed, board on the flange)",
            )
        )
        setup = Setup.EYE_IN_HAND
    camera = doc.get("camera")
    intrinsics_name = camera.get("intrinsics") if isinstance(camera, dict) else None
    if not isinstance(intrinsics_name, str):
        problems.append(
            Problem(where, "camera.intrinsics must name the intrinsics file", "e.g. camera: {intrinsics: camera.yaml}")
        )
    intrinsics = _file(root, intrinsics_name, "camera.intrinsics", problems)
    target = _target(doc, where, problems)
    section = doc.get(SECTION)
    if not isinstance(section, dict):
        problems.append(
            Problem(where, f"'{SECTION}' must be a mapping that names the poses file and its conventions", _HINT)
        )
        section = {}
    convention = _convention(section, where, problems)
    name = section.get("file", "poses.csv")
    poses_file = _file(root, name if isinstance(name, str) else None, f"{SECTION}.file", problems)
    ds = HandEyeDataset(root, setup, intrinsics, target, poses_file, convention, problems=problems)
    image_column = section.get("image_column", "image")
    if not isinstance(image_column, str):
        problems.append(Problem(where, f"{SECTION}.image_column must be a column name, got {image_column!r}"))
    elif convention is not None and poses_file.is_file():
        _read_poses(ds, convention, image_column)
    return ds


def require_ok(ds: HandEyeDataset) -> None:
    """Raise one ArmtoolError that lists every error-level problem."""
    from armtool.calib.inputs.dataset import require_ok as raise_problems

    raise_problems(ds, _HINT)


def _file(root: Path, name: str | None, key: str, problems: list[Problem]) -> Path:
    from armtool.calib.inputs.files import unreadable_reason

    if name is None:
        return root / "__missing__"
    path = root / name
    why = unreadable_reason(path)
    if why is not None:
        problems.append(Problem("dataset.yaml", f"{key} '{name}' {why}", f"put the file in {root} or fix the path"))
    return path


def _target(doc: dict[str, Any], where: str, problems: list[Problem]) -> Target:
    """A board (`target.board`, as `calibrate camera --board` spells it; one that looks the same
    turned is fine: the motion tells its turn) or one AprilTag (`type: apriltag`, family, id, size_m)."""
    from armtool.calib.inputs.dataset import _tag_target
    from armtool.calib.targets.spec import board_target, declares_board

    raw = doc.get("target")
    if declares_board(raw):
        try:
            return Target(board=board_target(raw, allow_symmetric=True))
        except ArmtoolError as exc:
            problems.append(Problem(where, exc.what, exc.hint or ""))
            return Target(family="")
    family, tag_id, size_m = _tag_target(doc, where, problems)
    if tag_id is None or size_m is None:
        return Target(family="")
    return Target(family, tag_id, float(size_m))


def _convention(section: dict[str, Any], where: str, problems: list[Problem]) -> PoseConvention | None:
    """The `poses:` conventions: every one a mistake could hide in must be stated."""
    from armtool.calib.inputs.measured import SpecProblem, _choice, _columns

    found: list[SpecProblem] = []
    frame = _choice(section, "pose", tuple(FRAMES.values()), found, "which frame is in which", SECTION)
    units = _choice(
        section, "position_units", tuple(u.value for u in LengthUnit), found, "the unit of the positions", SECTION
    )
    form_text = _choice(
        section, "rotation", tuple(r.value for r in RotationForm), found, "how the rotation is written", SECTION
    )
    form = RotationForm(form_text) if form_text else None
    order = rpy = angles = None
    if form is RotationForm.QUATERNION:
        text = _choice(
            section,
            "quaternion_order",
            tuple(q.value for q in QuaternionOrder),
            found,
            "the order of its columns",
            SECTION,
        )
        order = QuaternionOrder(text) if text else None
    if form is RotationForm.RPY:
        rpy = _choice(section, "rpy_order", RPY_ORDERS, found, "zyx means R = Rz(yaw)·Ry(pitch)·Rx(roll)", SECTION)
    if form in (RotationForm.RPY, RotationForm.ROTATION_VECTOR):
        text = _choice(
            section, "angle_units", tuple(a.value for a in AngleUnit), found, "the unit of the angles", SECTION
        )
        angles = AngleUnit(text) if text else None
    position = _columns(section, "position_columns", 3, DEFAULT_POSITION_COLUMNS, found, SECTION)
    rotation: tuple[str, ...] = ()
    if form is not None:
        rotation = _columns(
            section, "rotation_columns", ROTATION_SIZE[form], default_rotation_columns(form, order), found, SECTION
        )
    problems += [Problem(where, p.what, p.hint) for p in found]
    if found or frame is None or units is None or form is None:
        return None
    convention = PoseConvention(
        _FRAME_OF[frame],
        LengthUnit(units),
        form,
        order,
        rpy,
        angles,
        position,
        rotation,
        columns_listed=section.get("rotation_columns") is not None,
    )
    if len(set(convention.columns)) != len(convention.columns):
        problems.append(Problem(where, f"{SECTION} names a column twice: {list(convention.columns)}"))
        return None
    return convention


def _read_poses(ds: HandEyeDataset, convention: PoseConvention, image_column: str) -> None:
    """One shot per row; each bad row is a problem at its line, a file that is not CSV one at the file."""
    from armtool.calib.inputs.files import unreadable_reason
    from armtool.calib.inputs.measured import _is_number, _value_problem

    where = ds.poses_file.name
    size = ds.poses_file.stat().st_size
    if size > MAX_FILE_BYTES:
        ds.problems.append(
            Problem(where, f"file is {size / 2**20:.0f} MB, more than the {MAX_FILE_BYTES // 2**20} MB armtool reads")
        )
        return
    try:
        text = ds.poses_file.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError:
        ds.problems.append(Problem(where, "not UTF-8 text", "save the CSV as UTF-8"))
        return
    try:
        with io.StringIO(text, newline="") as handle:
            reader = csv.reader(handle)
            header = [h.strip() for h in next(reader, [])]
            missing = [c for c in (image_column, *convention.columns) if c not in header]
            if missing:
                ds.problems.append(
                    Problem(
                        f"{where}:1",
                        f"column(s) {', '.join(missing)} missing (the header has {', '.join(header) or 'nothing'})",
                        f"name them in {SECTION}.image_column, {SECTION}.position_columns and {SECTION}.rotation_columns",
                    )
                )
                return
            image_at = header.index(image_column)
            cols = [header.index(c) for c in convention.columns]
            seen: set[str] = set()
            for line, row in enumerate(reader, start=2):
                if not row or all(not c.strip() for c in row):
                    continue
                if len(ds.shots) >= MAX_SAMPLES:
                    ds.problems.append(
                        Problem(f"{where}:{line}", f"more than {MAX_SAMPLES} rows", "15-100 images are plenty")
                    )
                    break
                if len(row) < len(header):
                    ds.problems.append(Problem(f"{where}:{line}", f"{len(row)} values, the header has {len(header)}"))
                    continue
                name = row[image_at].strip()
                if name in seen:
                    ds.problems.append(Problem(f"{where}:{line}", f"image '{name}' is listed twice"))
                    continue
                seen.add(name)
                image = ds.root / name
                why = unreadable_reason(image) if name else "is not named"
                if why is not None:
                    ds.problems.append(
                        Problem(f"{where}:{line}", f"image '{name}' {why}", "paths are relative to the dataset")
                    )
                    continue
                try:
                    values = np.array([float(row[c]) for c in cols])
                except ValueError:
                    bad = next(convention.columns[k] for k, c in enumerate(cols) if not _is_number(row[c]))
                    ds.problems.append(
                        Problem(f"{where}:{line}", f"'{bad}' is not a number: {row[header.index(bad)]!r}")
                    )
                    continue
                problem = _value_problem(values, convention, SECTION)
                if problem is not None:
                    ds.problems.append(Problem(f"{where}:{line}", problem.what, problem.hint))
                    continue
                ds.shots.append(Shot(image, line, values))
    except csv.Error as exc:
        ds.problems.append(
            Problem(where, f"not a readable CSV file: {exc}", "one row per line, fields separated by commas")
        )
        return
    if not ds.shots and not ds.errors:
        ds.problems.append(
            Problem(where, "no rows", f"one row per image: {image_column},{','.join(convention.columns)}")
        )
