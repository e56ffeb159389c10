"""The calibration dataset (`format: armtool-calib-dataset/1`): manifest, samples, observations.

One directory holds `dataset.yaml`, the nominal URDF, the camera intrinsics, `samples.csv`
(one row per robot pose, joint columns named after URDF joints, radians) and either the raw
images or `corners.csv` (pre-detected corners in pixels). Every problem is collected with its
file and row, so `armtool calibrate check` can list them all at once.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from armtool.calib.choices import Setup, Severity
from armtool.calib.inputs.files import unreadable_reason
from armtool.calib.limits import MAX_CSV_FIELD, MAX_FILE_BYTES, MAX_SAMPLES, MAX_TAG_ID, TAG_SIZE_M
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError

if TYPE_CHECKING:
    from armtool.calib.inputs.measured import MeasurementSpec
    from armtool.calib.targets.boards import BoardSpec
    from armtool.calib.targets.spec import Target
    from armtool.model.chain import Chain

FORMAT = "armtool-calib-dataset/1"
CORNER_COLUMNS = ["u0", "v0", "u1", "v1", "u2", "v2", "u3", "v3"]
MAX_CORNER_PX = 1e6  # far outside any image: a coordinate beyond is a unit or column mix-up


@dataclass(frozen=True)
class Problem:
    where: str  # file, or file:line
    what: str
    hint: str = ""
    severity: Severity = "error"


@dataclass(frozen=True)
class Sample:
    id: str
    row: int  # line in samples.csv (header is line 1)
    q: Array  # joint values in chain order (rad or m)
    image: Path | None


@dataclass
class Dataset:
    root: Path
    setup: Setup
    urdf: Path
    base_link: str
    flange_link: str
    joints: list[str]
    intrinsics: Path
    images_rectified: bool
    family: str
    tag_id: int
    size_m: float
    samples: list[Sample]
    corners: dict[str, Array] = field(default_factory=dict)  # sample id -> (4,2) pixels, from corners.csv
    corners_file: Path | None = None
    samples_file: Path | None = None
    hints: dict[str, Array] = field(default_factory=dict)  # "camera_in_base", "tag_in_flange", ... -> 4x4
    problems: list[Problem] = field(default_factory=list)
    xacro_args: dict[str, str] = field(default_factory=dict)  # robot.xacro_args: for a .xacro robot.urdf
    package_paths: list[Path] = field(default_factory=list)  # robot.package_paths, resolved against the dataset
    board: BoardSpec | None = None  # target.board: a board instead of one AprilTag (family, tag_id, size_m unused)
    measurement: MeasurementSpec | None = None  # `observations:`: measured poses or points instead of images
    measured_rows: dict[str, Array] = field(default_factory=dict)  # sample id -> raw values
    joint_columns: dict[str, str] = field(default_factory=dict)  # robot.joint_columns: joint -> its column in samples
    observations_file: Path | None = None  # observations.file as named, even when the section is invalid

    def robot_sources(
        self, xacro_args: dict[str, str] | None = None, package_paths: list[Path] | None = None
    ) -> tuple[dict[str, str], list[Path]]:
        """xacro arguments and package paths for robot.urdf: the command line's over the dataset's."""
        return {**self.xacro_args, **(xacro_args or {})}, [*(package_paths or []), *self.package_paths]

    @property
    def errors(self) -> list[Problem]:
        return [p for p in self.problems if p.severity == "error"]


def manifest_document(created_by: str, setup: Setup, chain: Chain, target: Target) -> dict[str, Any]:
    """dataset.yaml of a dataset armtool writes (`simulate`, `import-bag`): robot.urdf, camera.yaml,
    samples.csv and images/ beside it, joints in radians, the target (an AprilTag or a board)."""
    return {
        "format": FORMAT,
        "created_by": created_by,
        "setup": setup.value,
        "robot": {
            "urdf": "robot.urdf",
            "base_link": chain.base,
            "flange_link": chain.tip,
            "joints": list(chain.joint_names),
            "joint_units": "rad",
        },
        "camera": {
            "intrinsics": "camera.yaml",
            "convention": "opencv (x right, y down, z forward)",
            "images_rectified": False,
        },
        "target": target.document(chain.tip if setup is Setup.EYE_TO_HAND else chain.base),
        "samples": "samples.csv",
        "images_dir": "images",
    }


def _resolve(path: Path) -> Path:
    """`path.resolve()`, or the path as given when it cannot be resolved (a NUL byte, a name too
    long): the file check that follows then says what is wrong with it."""
    try:
        return path.resolve()
    except (OSError, ValueError, RuntimeError):
        return path


def _rel(root: Path, path: Path) -> str:
    try:
        return str(path.relative_to(root.parent))
    except ValueError:
        return str(path)


def _get(
    doc: dict[str, Any], dotted: str, problems: list[Problem], where: str, kind: type | tuple[type, ...] = str
) -> Any:
    cur: Any = doc
    for key in dotted.split("."):
        if not isinstance(cur, dict) or key not in cur:
            problems.append(
                Problem(
                    where, f"missing key '{dotted}'", f"add `{dotted}:` (see the dataset format in docs/calibrate.md)"
                )
            )
            return None
        cur = cur[key]
    if not isinstance(cur, kind) or (isinstance(cur, bool) and kind is not bool):
        names = {str: "a string", list: "a list", int: "an integer", bool: "true or false"}
        wanted = "a number" if isinstance(kind, tuple) else names.get(kind, kind.__name__)
        problems.append(Problem(where, f"'{dotted}' must be {wanted}, got {cur!r}"))
        return None
    return cur


def _hint_pose(value: Any) -> Array | None:
    from armtool.calib.model import se3

    try:
        xyz = [float(v) for v in value["xyz"]]
        rpy = [float(v) for v in value.get("rpy", [0, 0, 0])]
        if len(xyz) != 3 or len(rpy) != 3 or not all(math.isfinite(v) for v in xyz + rpy):
            return None
        return se3.xyz_rpy(xyz, rpy)
    except (TypeError, KeyError, ValueError, AttributeError, OverflowError):
        return None


def _robot_sources(
    doc: dict[str, Any], root: Path, where: str, problems: list[Problem]
) -> tuple[dict[str, str], list[Path]]:
    """robot.xacro_args (NAME: VALUE) and robot.package_paths (directories, relative to the dataset)."""
    robot: dict[str, Any] = doc["robot"] if isinstance(doc.get("robot"), dict) else {}
    raw_args = robot.get("xacro_args") or {}
    args: dict[str, str] = {}
    if not isinstance(raw_args, dict):
        problems.append(
            Problem(
                where,
                f"robot.xacro_args must be a mapping NAME: VALUE, got {raw_args!r}",
                "e.g. xacro_args: {ur_type: ur5e, name: ur}",
            )
        )
    else:
        for k, v in raw_args.items():
            args[str(k)] = ("true" if v else "false") if isinstance(v, bool) else str(v)
    raw_paths = robot.get("package_paths") or []
    if isinstance(raw_paths, str):
        raw_paths = [raw_paths]
    paths: list[Path] = []
    if not isinstance(raw_paths, list):
        problems.append(
            Problem(
                where,
                f"robot.package_paths must be a list of directories, got {raw_paths!r}",
                "e.g. package_paths: [../src]",
            )
        )
    else:
        for item in raw_paths:
            path = _resolve(root / str(item))
            if not os.path.isdir(path):
                problems.append(
                    Problem(
                        where, f"robot.package_paths entry '{item}' is not a directory", f"paths are relative to {root}"
                    )
                )
            paths.append(path)
    return args, paths


def _tag_target(doc: dict[str, Any], where: str, problems: list[Problem]) -> tuple[str, int | None, float | None]:
    """target.family, target.id and target.size_m of an AprilTag target (None when invalid, with a problem)."""
    family = _get(doc, "target.family", problems, where) or "tag36h11"
    tag_id = _get(doc, "target.id", problems, where, int)
    size_m = _get(doc, "target.size_m", problems, where, (int, float))
    if size_m is not None and not (TAG_SIZE_M[0] <= float(size_m) <= TAG_SIZE_M[1]):  # NaN fails too
        problems.append(
            Problem(
                where,
                f"target.size_m is {size_m}: the black square's edge in metres, {TAG_SIZE_M[0]:g} to {TAG_SIZE_M[1]:g}",
                "e.g. 0.08 for an 80 mm tag",
            )
        )
        size_m = None
    if tag_id is not None and not 0 <= tag_id <= MAX_TAG_ID:
        problems.append(
            Problem(
                where, f"target.id is {tag_id}: AprilTag ids are 0 to {MAX_TAG_ID}", "the number printed under the tag"
            )
        )
        tag_id = None
    if not isinstance(family, str):
        problems.append(Problem(where, f"target.family must be a string, got {family!r}", "e.g. tag36h11"))
        family = "tag36h11"
    return family, tag_id, size_m


def _target(
    doc: dict[str, Any], where: str, problems: list[Problem]
) -> tuple[BoardSpec | None, str, int | None, float | None]:
    """(board, family, id, size_m): a board target (`target.board`, as `calibrate camera --board`
    spells it) or an AprilTag's keys; what cannot be used is a problem. A board target's tag keys
    are not looked for."""
    from armtool.calib.targets.spec import board_target, declares_board

    target = doc.get("target")
    if not declares_board(target):
        return (None, *_tag_target(doc, where, problems))
    try:
        return board_target(target), "", 0, 0.0
    except ArmtoolError as exc:
        problems.append(Problem(where, exc.what, exc.hint or ""))
        return None, "", 0, 0.0


def _joint_columns(doc: dict[str, Any], where: str, problems: list[Problem]) -> dict[str, str]:
    """robot.joint_columns: {URDF joint: its column in the samples file}, for files whose columns
    are named otherwise (q1, q2, ...)."""
    robot = doc.get("robot") if isinstance(doc.get("robot"), dict) else {}
    raw = robot.get("joint_columns") if isinstance(robot, dict) else None
    if raw is None:
        return {}
    if not isinstance(raw, dict) or not all(isinstance(k, str) and isinstance(v, (str, int)) for k, v in raw.items()):
        problems.append(
            Problem(
                where,
                f"robot.joint_columns must map joint names to column names, got {raw!r}",
                "e.g. joint_columns: {joint1: q1, joint2: q2}",
            )
        )
        return {}
    return {k: str(v) for k, v in raw.items()}


def _measurement(doc: dict[str, Any], root: Path, where: str, problems: list[Problem]) -> MeasurementSpec | None:
    """`observations:` (measured poses or points), or None for a dataset of images or corners."""
    if "observations" not in doc:
        return None
    from armtool.calib.inputs.measured import parse_spec

    spec, found = parse_spec(doc["observations"], root)
    problems += [Problem(where, p.what, p.hint) for p in found]
    return spec


def load_dataset(directory: Path, chain_joint_names: list[str] | None = None, *, with_samples: bool = True) -> Dataset:
    """Read the manifest and samples; problems are collected, not raised (see `require_ok`).

    With `with_samples=False` only the manifest is read: the caller loads the chain it names
    first, then calls `read_samples` with the chain's joint names.
    """
    root = directory.resolve()
    manifest = root / "dataset.yaml" if root.is_dir() else root
    if root.is_file():
        root = root.parent
    where = _rel(root, manifest)
    if not manifest.is_file():
        raise ArmtoolError(
            "no dataset.yaml",
            str(manifest),
            "pass a dataset directory (see `armtool calibrate simulate` for an example)",
        )
    from armtool.fileio import read_yaml

    doc = read_yaml(manifest, "dataset.yaml")
    if not isinstance(doc, dict):
        raise ArmtoolError("dataset.yaml must be a mapping", where)
    problems: list[Problem] = []
    if doc.get("format") != FORMAT:
        problems.append(
            Problem(where, f"format is {doc.get('format')!r}, expected '{FORMAT}'", f"add `format: {FORMAT}`")
        )
    setup_text = doc.get("setup", Setup.EYE_TO_HAND.value)
    try:
        setup = Setup(setup_text)
    except ValueError:
        problems.append(Problem(where, f"setup '{setup_text}' is not eye_to_hand or eye_in_hand"))
        setup = Setup.EYE_TO_HAND
    urdf_name = _get(doc, "robot.urdf", problems, where)
    base = _get(doc, "robot.base_link", problems, where) or ""
    flange = _get(doc, "robot.flange_link", problems, where) or ""
    joints = _get(doc, "robot.joints", problems, where, list) or []
    units = (doc.get("robot") or {}).get("joint_units", "rad") if isinstance(doc.get("robot"), dict) else "rad"
    if units not in ("rad", "radians"):
        problems.append(
            Problem(
                where,
                f"robot.joint_units is '{units}'",
                "armtool expects radians: convert the CSV and set `joint_units: rad`",
            )
        )
    measurement = _measurement(doc, root, where, problems)
    # A dataset of measured poses or points has no camera or image target: their keys are not looked for.
    image_problems: list[Problem] = [] if "observations" in doc else problems
    intr_name = _get(doc, "camera.intrinsics", image_problems, where)
    rectified = (
        (doc.get("camera") or {}).get("images_rectified", False) if isinstance(doc.get("camera"), dict) else False
    )
    if not isinstance(rectified, bool):
        image_problems.append(Problem(where, f"camera.images_rectified must be true or false, got {rectified!r}"))
        rectified = False
    board, family, tag_id, size_m = _target(doc, where, image_problems)
    bad_joints = [j for j in joints if not isinstance(j, str)]
    if bad_joints:
        problems.append(
            Problem(where, f"robot.joints must be joint names, got {bad_joints[0]!r}", "e.g. joints: [joint1, joint2]")
        )
    samples_name = doc.get("samples", "samples.csv")
    if not isinstance(samples_name, str):
        problems.append(
            Problem(where, f"'samples' must be a file name, got {samples_name!r}", "e.g. samples: samples.csv")
        )
        samples_name = "samples.csv"

    def file_in_root(name: str | None, what: str) -> Path:
        if name is None:
            return root / "__missing__"
        path = _resolve(root / name)
        why = unreadable_reason(path)
        if why is not None:
            problems.append(
                Problem(where, f"{what} '{name}' {why}", f"put the file in {root} or fix the path in dataset.yaml")
            )
        return path

    urdf = file_in_root(urdf_name, "robot.urdf")
    intrinsics = file_in_root(intr_name, "camera.intrinsics")
    samples_path = file_in_root(samples_name, "samples")
    xacro_args, package_paths = _robot_sources(doc, root, where, problems)
    joint_columns = _joint_columns(doc, where, problems)
    hints: dict[str, Array] = {}
    raw_hints = doc.get("hints") or {}
    if not isinstance(raw_hints, dict):
        problems.append(
            Problem(
                where,
                f"'hints' must be a mapping, got {raw_hints!r}",
                "e.g. hints: {camera_in_base: {xyz: [...], rpy: [...]}}",
                "warning",
            )
        )
        raw_hints = {}
    for key, value in raw_hints.items():
        pose = _hint_pose(value)
        if pose is None:
            problems.append(Problem(where, f"hint '{key}' needs xyz: [x, y, z] and rpy: [r, p, y]", severity="warning"))
        else:
            hints[key] = pose
    corners_name = doc.get("corners") if "observations" not in doc else None
    if corners_name is not None and not isinstance(corners_name, str):
        problems.append(
            Problem(where, f"'corners' must be a file name, got {corners_name!r}", "e.g. corners: corners.csv")
        )
        corners_name = None
    corners_file = _resolve(root / corners_name) if corners_name else None
    if corners_file is None and "observations" not in doc and (root / "corners.csv").is_file():
        corners_file = _resolve(root / "corners.csv")
    if corners_file is not None and board is not None:
        problems.append(
            Problem(
                where,
                f"{corners_file.name} holds one AprilTag's corners, but the target is a board",
                "a board's corners are found in the images: remove corners.csv (and `corners:`)",
            )
        )
        corners_file = None

    ds = Dataset(
        root,
        setup,
        urdf,
        base,
        flange,
        [str(j) for j in joints],
        intrinsics,
        rectified,
        str(family),
        int(tag_id) if tag_id is not None else 0,
        float(size_m) if size_m is not None else 0.0,
        [],
        corners_file=corners_file,
        hints=hints,
        problems=problems,
        xacro_args=xacro_args,
        package_paths=package_paths,
        board=board,
    )
    ds.samples_file = samples_path
    ds.measurement = measurement
    ds.observations_file = _observations_file(doc, root)
    ds.joint_columns = joint_columns
    if measurement is not None and (why := unreadable_reason(measurement.file)) is not None:
        problems.append(
            Problem(
                where, f"observations.file '{measurement.file.name}' {why}", f"put the file in {root} or fix the path"
            )
        )
    if corners_file is not None and (why := unreadable_reason(corners_file)) is not None:
        problems.append(Problem(where, f"corners file '{corners_name or corners_file.name}' {why}"))
    if with_samples:
        read_samples(ds, chain_joint_names)
    return ds


def read_samples(ds: Dataset, chain_joint_names: list[str] | None = None) -> None:
    """samples.csv (and corners.csv), checked against the chain's joints when they are given."""
    samples, corners = ds.samples_file, ds.corners_file
    if samples is not None and unreadable_reason(samples) is None:
        if _read_csv(ds, samples, lambda handle, where: _sample_rows(ds, handle, where, chain_joint_names)):
            _check_samples(ds, _rel(ds.root, samples))
    if corners is not None and unreadable_reason(corners) is None:
        _read_csv(ds, corners, lambda handle, where: _corner_rows(ds, handle, where))
    spec = ds.measurement
    if spec is not None and unreadable_reason(spec.file) is None:
        _read_measurements(ds, spec)


def _observations_file(doc: dict[str, Any], root: Path) -> Path | None:
    section = doc.get("observations")
    name = section.get("file") if isinstance(section, dict) else None
    return root / name if isinstance(name, str) and name else None


def _measurements_unread_in_samples(ds: Dataset) -> bool:
    """observations: names the samples file but could not be read: the samples' other columns
    are then the measurements it would have named."""
    return ds.measurement is None and _measured_in_samples(ds)


def _measured_in_samples(ds: Dataset) -> bool:
    """The measurements are in the samples file itself: its rows may then go without an id (their
    line number is one), as FIGAROH's calibration CSVs do. Judged by the file observations: names,
    so that an invalid section does not turn into a request for an id column."""
    named, samples = ds.observations_file, ds.samples_file
    return named is not None and samples is not None and _resolve(named) == _resolve(samples)


def _read_measurements(ds: Dataset, spec: MeasurementSpec) -> None:
    """The measured poses or points (`observations.file`), each bad row a problem at its line,
    and a warning for each sample that has no row."""
    import csv as csv_module

    from armtool.calib.inputs.measured import read_rows

    where = _rel(ds.root, spec.file)
    text = _text(spec.file, where, ds.problems)
    if text is None:
        return
    try:
        rows, found = read_rows(text, spec, {s.id for s in ds.samples}, by_line=_measured_in_samples(ds))
    except csv_module.Error as exc:
        ds.problems.append(_csv_problem(exc, where, text))
        return
    ds.problems += [Problem(f"{where}:{p.line}", p.what, p.hint) for p in found]
    ds.measured_rows = rows
    reported = {sid for p in found for sid in p.samples}  # a bad row is an error already
    missing = [s for s in ds.samples if s.id not in rows and s.id not in reported]
    for s in missing[:20]:
        ds.problems.append(
            Problem(
                _rel(ds.root, ds.samples_file) + f":{s.row}" if ds.samples_file else where,
                f"sample {s.id} has no usable row in {spec.file.name}",
                severity="warning",
            )
        )
    if len(missing) > 20:
        ds.problems.append(Problem(where, f"… and {len(missing) - 20} more samples without a row", severity="warning"))


def _read_csv(ds: Dataset, path: Path, parse: Callable[[io.StringIO, str], None]) -> bool:
    """`parse(handle, where)` over the file's text; a read or CSV syntax error becomes a problem
    with the file (and line). False when the file could not be read at all."""
    where = _rel(ds.root, path)
    text = _text(path, where, ds.problems)
    if text is None:
        return False
    try:
        with io.StringIO(text, newline="") as handle:
            parse(handle, where)
    except csv.Error as exc:
        ds.problems.append(_csv_problem(exc, where, text))
    return True


def _sample_rows(ds: Dataset, handle: io.StringIO, where: str, chain_joint_names: list[str] | None) -> None:
    reader = csv.reader(handle)
    header = next(reader, None)
    if header is None:
        ds.problems.append(Problem(where, "samples.csv is empty", "one row per pose: id,image,<joint names>"))
        return
    header = [h.strip() for h in header]
    if "id" not in header and not _measured_in_samples(ds):
        ds.problems.append(Problem(f"{where}:1", "no 'id' column", "the header must start with id,image,<joint names>"))
        return
    names = chain_joint_names if chain_joint_names is not None else ds.joints
    column_of = {n: ds.joint_columns.get(n, n) for n in names}
    missing = [column_of[n] for n in names if column_of[n] not in header]
    if missing:
        ds.problems.append(
            Problem(
                f"{where}:1",
                f"joint column(s) missing: {', '.join(missing)}",
                "the header names URDF joints: " + ", ".join(names) + " (or map them with robot.joint_columns)",
            )
        )
        return
    measured = set(ds.measurement.columns) if ds.measurement is not None else set()
    known = {"id", "image", *column_of.values(), *measured}
    unknown = [h for h in header if h not in known]
    if unknown and chain_joint_names is not None and _measurements_unread_in_samples(ds):
        others = [u for u in unknown if u not in ds.joints]  # a dataset joint outside the chain stays an error below
        unknown = [u for u in unknown if u in ds.joints]
        if others:
            ds.problems.append(
                Problem(
                    f"{where}:1",
                    f"column(s) {', '.join(others)} are not joints of the chain {ds.base_link} → {ds.flange_link}, "
                    "and observations: (which names this file) has errors, so they are not read as measurements either",
                    "fix observations: as the errors above say; keep the columns, they hold the measurements",
                    severity="warning",
                )
            )
    if unknown and chain_joint_names is not None:
        from armtool.suggest import did_you_mean

        for u in unknown:
            ds.problems.append(
                Problem(
                    f"{where}:1",
                    f"column '{u}' is not a joint of the chain {ds.base_link} → {ds.flange_link}{did_you_mean(u, names)}",
                    "remove the column, or fix robot.base_link / robot.flange_link",
                    severity="warning" if u not in ds.joints else "error",
                )
            )
    cols = [header.index(column_of[n]) for n in names]
    id_col = header.index("id") if "id" in header else None  # then a row's id is its line number
    image_col = header.index("image") if "image" in header else None
    seen: set[str] = set()
    for line, row in enumerate(reader, start=2):
        if not row or all(not c.strip() for c in row):
            continue
        if len(ds.samples) >= MAX_SAMPLES:
            ds.problems.append(
                Problem(
                    f"{where}:{line}",
                    f"more than {MAX_SAMPLES} samples",
                    "split the dataset: 30-300 well-spread poses are plenty",
                )
            )
            break
        if len(row) < len(header):
            ds.problems.append(Problem(f"{where}:{line}", f"{len(row)} values, header has {len(header)}"))
            continue
        sid = row[id_col].strip() if id_col is not None else str(line)
        if sid in seen:
            ds.problems.append(Problem(f"{where}:{line}", f"duplicate id '{sid}'"))
            continue
        seen.add(sid)
        try:
            q = np.array([float(row[c]) for c in cols])
        except ValueError:
            ds.problems.append(Problem(f"{where}:{line}", "a joint value is not a number"))
            continue
        if not np.isfinite(q).all():
            ds.problems.append(Problem(f"{where}:{line}", "a joint value is NaN or infinite"))
            continue
        image = None
        if image_col is not None and row[image_col].strip():
            image = _resolve(ds.root / row[image_col].strip())
        ds.samples.append(Sample(sid, line, q, image))


def _check_samples(ds: Dataset, where: str) -> None:
    """Problems of the samples as a whole: none at all, or values that look like degrees."""
    if not ds.samples and not any(p.where.startswith(where) for p in ds.problems):
        ds.problems.append(
            Problem(
                where, "samples.csv has a header but no rows", "one row per robot pose: id,image,<joint values in rad>"
            )
        )
    if ds.samples and ds.samples[0].q.size:  # no joint columns when robot.joints is missing (reported)
        Q = np.stack([s.q for s in ds.samples])
        if float(np.abs(Q).max()) > 2 * math.pi + 0.5:
            worst = int(np.abs(Q).max(axis=1).argmax())
            ds.problems.append(
                Problem(
                    f"{where}:{ds.samples[worst].row}",
                    f"joint values up to {float(np.abs(Q).max()):.1f}: these look like degrees, but the dataset states radians",
                    "convert the joint columns to radians (value × π/180)",
                )
            )


def _corner_rows(ds: Dataset, handle: io.StringIO, where: str) -> None:
    reader = csv.DictReader(handle)
    fields = [f.strip() for f in (reader.fieldnames or [])]
    missing = [c for c in ["id", "tag_id", *CORNER_COLUMNS] if c not in fields]
    if missing:
        ds.problems.append(
            Problem(
                f"{where}:1",
                f"corners.csv lacks column(s) {', '.join(missing)}",
                "header: id,tag_id,u0,v0,u1,v1,u2,v2,u3,v3",
            )
        )
        return
    ids = {s.id for s in ds.samples}
    for line, row in enumerate(reader, start=2):
        if line > MAX_SAMPLES + 1:
            ds.problems.append(Problem(f"{where}:{line}", f"more than {MAX_SAMPLES} rows", "one row per sample"))
            break
        row = {k.strip(): (v or "").strip() for k, v in row.items() if k}
        try:
            if int(row["tag_id"]) != ds.tag_id:
                continue
            uv = np.array([float(row[c]) for c in CORNER_COLUMNS]).reshape(4, 2)
        except ValueError:
            ds.problems.append(Problem(f"{where}:{line}", "tag_id or a corner coordinate is not a number"))
            continue
        if not np.isfinite(uv).all():
            ds.problems.append(Problem(f"{where}:{line}", "a corner coordinate is NaN or infinite"))
            continue
        if float(np.abs(uv).max()) > MAX_CORNER_PX:
            ds.problems.append(
                Problem(
                    f"{where}:{line}",
                    f"a corner coordinate is beyond ±{MAX_CORNER_PX:g} px",
                    "corners are pixel coordinates in the image",
                )
            )
            continue
        if row["id"] not in ids:
            ds.problems.append(Problem(f"{where}:{line}", f"sample id '{row['id']}' is not in samples.csv"))
            continue
        ds.corners[row["id"]] = uv


def _csv_problem(exc: csv.Error, where: str, text: str) -> Problem:
    """A CSV syntax error with the line it is on (the reader stops there)."""
    message = str(exc)
    if "field larger than field limit" in message:
        line = _line_of_long_field(text)
        return Problem(
            f"{where}:{line}",
            f"a field is longer than {MAX_CSV_FIELD // 1024} KB",
            "is this the right file? each field is one id, path or number",
        )
    return Problem(where, f"not a readable CSV file: {message}", "one row per line, fields separated by commas")


def _line_of_long_field(text: str) -> int:
    for number, line in enumerate(text.splitlines(), start=1):
        if len(line) > MAX_CSV_FIELD:
            return number
    return 1


def _text(path: Path, where: str, problems: list[Problem]) -> str | None:
    try:
        size = path.stat().st_size
        if size > MAX_FILE_BYTES:
            problems.append(
                Problem(
                    where,
                    f"file is {size / 2**20:.0f} MB, more than the {MAX_FILE_BYTES // 2**20} MB armtool reads",
                    f"a dataset holds at most {MAX_SAMPLES} samples",
                )
            )
            return None
        return path.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = path.read_bytes()[: exc.start].count(b"\n") + 1
        problems.append(Problem(f"{where}:{line}", "not UTF-8 text", "save the CSV as UTF-8"))
    except OSError as exc:
        problems.append(Problem(where, f"cannot read: {exc.strerror}"))
    return None


def require_ok(ds: Dataset) -> None:
    """Raise one ArmtoolError that lists every error-level problem."""
    errors = ds.errors
    if errors:
        first = errors[0]
        more = "".join(f"\n  {p.where}: {p.what}" for p in errors[1:8])
        extra = f"\n  … and {len(errors) - 8} more" if len(errors) > 8 else ""
        raise ArmtoolError(
            first.what + more + extra, first.where, first.hint or "run `armtool calibrate check` for the full list"
        )
