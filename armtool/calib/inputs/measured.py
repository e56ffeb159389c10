"""Pose and point observations: the manifest's `observations:` section and the CSV file it names.

A dataset without images states what its measurement device gave per sample:

    observations:
      kind: pose                      # or point
      file: camera_in_board.csv       # one row per sample id (may be samples.csv itself)
      pose: sensor_in_target          # pose only: which frame is in which
      position_units: m               # m or mm
      rotation: matrix                # pose only: matrix, quaternion, rpy or rotation_vector
      position_columns: [T03, T13, T23]
      rotation_columns: [T00, T01, T02, T10, T11, T12, T20, T21, T22]

Every convention that a mistake could hide in must be stated (no defaults for `pose`, the units,
the quaternion order, the rpy order or the angle unit); the columns have defaults (x y z, r00 …
r22, qx qy qz qw, roll pitch yaw, rx ry rz). Each bad value is reported at its file and row.
"""

from __future__ import annotations

import csv
import io
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np

from armtool.calib.inputs.conventions import (
    DEFAULT_POSITION_COLUMNS,
    ROTATION_SIZE,
    RPY_ORDERS,
    AngleUnit,
    LengthUnit,
    PointConvention,
    PoseConvention,
    PoseFrame,
    QuaternionOrder,
    RotationForm,
    default_rotation_columns,
)
from armtool.calib.limits import MAX_SAMPLES
from armtool.calib.model.se3 import Array

MeasurementKind = Literal["pose", "point"]
MAX_POSITION_M = 100.0  # a position beyond 100 m from the sensor is a unit mix-up (millimetres read as metres)
_NAME = re.compile(r"^[a-z][a-z0-9_]{0,31}$")


@dataclass(frozen=True)
class MeasurementSpec:
    """What `observations:` states: the kind, the file, its conventions, and what to call the frames."""

    kind: MeasurementKind
    file: Path
    convention: PoseConvention | PointConvention
    sensor: str  # reports say `<sensor>_in_flange`, `<target>_in_base`, …
    target: str

    @property
    def columns(self) -> tuple[str, ...]:
        return self.convention.columns


@dataclass(frozen=True)
class SpecProblem:
    """A problem of the `observations:` section (dataset.Problem is built from it by the caller)."""

    what: str
    hint: str = ""


def _choice(
    section: dict[str, Any], key: str, choices: tuple[str, ...], problems: list[SpecProblem], needed: str
) -> str | None:
    """`observations.<key>`, one of `choices`; a missing or unknown value is a problem."""
    listed = ", ".join(choices)
    if key not in section:
        problems.append(SpecProblem(f"observations.{key} is missing ({needed})", f"state it: one of {listed}"))
        return None
    value = section[key]
    if not isinstance(value, str) or value not in choices:
        problems.append(SpecProblem(f"observations.{key} is {value!r}", f"one of {listed}"))
        return None
    return value


def _values(enum: Any) -> tuple[str, ...]:
    return tuple(str(e.value) for e in enum)


def _columns(
    section: dict[str, Any], key: str, size: int, default: tuple[str, ...], problems: list[SpecProblem]
) -> tuple[str, ...]:
    value = section.get(key)
    if value is None:
        return default
    if not isinstance(value, list) or len(value) != size or not all(isinstance(v, (str, int)) for v in value):
        problems.append(
            SpecProblem(
                f"observations.{key} must list {size} column names, got {value!r}",
                f"e.g. {key}: [{', '.join(default)}]",
            )
        )
        return default
    return tuple(str(v) for v in value)


def parse_spec(section: Any, root: Path) -> tuple[MeasurementSpec | None, list[SpecProblem]]:
    """The `observations:` section as a spec, and its problems (the spec is None when unusable)."""
    problems: list[SpecProblem] = []
    if not isinstance(section, dict):
        return None, [
            SpecProblem(f"'observations' must be a mapping, got {section!r}", "see the dataset format in the README")
        ]
    kind = section.get("kind")
    if kind not in ("pose", "point"):
        problems.append(
            SpecProblem(f"observations.kind is {kind!r}", "pose (a target's pose per sample) or point (one 3-D point)")
        )
        return None, problems
    name = section.get("file")
    if not isinstance(name, str) or not name:
        problems.append(SpecProblem(f"observations.file must be a file name, got {name!r}", "e.g. file: poses.csv"))
        return None, problems
    units_text = _choice(section, "position_units", _values(LengthUnit), problems, "the unit of the positions")
    units = LengthUnit(units_text) if units_text else None
    sensor = section.get("sensor", "sensor" if kind == "pose" else "tracker")
    target = section.get("target", "target" if kind == "pose" else "point")
    for key, word in (("sensor", sensor), ("target", target)):
        if not isinstance(word, str) or not _NAME.match(word):
            problems.append(
                SpecProblem(
                    f"observations.{key} must be a short lower-case name, got {word!r}",
                    "e.g. sensor: camera, target: board",
                )
            )
    position = _columns(section, "position_columns", 3, DEFAULT_POSITION_COLUMNS, problems)
    convention: PoseConvention | PointConvention | None = None
    if kind == "point":
        if units is not None:
            convention = PointConvention(units, position)
    else:
        frame_text = _choice(section, "pose", _values(PoseFrame), problems, "which frame is in which")
        form_text = _choice(section, "rotation", _values(RotationForm), problems, "how the rotation is written")
        frame = PoseFrame(frame_text) if frame_text else None
        form = RotationForm(form_text) if form_text else None
        order = angles = None
        rpy = None
        if form is RotationForm.QUATERNION:
            text = _choice(section, "quaternion_order", _values(QuaternionOrder), problems, "the order of its columns")
            order = QuaternionOrder(text) if text else None
        if form is RotationForm.RPY:
            rpy = _choice(section, "rpy_order", RPY_ORDERS, problems, "zyx means R = Rz(yaw)·Ry(pitch)·Rx(roll)")
        if form in (RotationForm.RPY, RotationForm.ROTATION_VECTOR):
            text = _choice(section, "angle_units", _values(AngleUnit), problems, "the unit of the angles")
            angles = AngleUnit(text) if text else None
        if frame is not None and units is not None and form is not None and not problems:
            rotation = _columns(
                section, "rotation_columns", ROTATION_SIZE[form], default_rotation_columns(form, order), problems
            )
            listed = section.get("rotation_columns") is not None
            convention = PoseConvention(
                frame, units, form, order, rpy, angles, position, rotation, columns_listed=listed
            )
    if convention is not None and len(set(convention.columns)) != len(convention.columns):
        problems.append(SpecProblem(f"observations names a column twice: {list(convention.columns)}"))
    if problems or convention is None:
        return None, problems
    return MeasurementSpec(kind, root / name, convention, str(sensor), str(target)), problems


@dataclass(frozen=True)
class RowProblem:
    line: int  # 1 is the header
    what: str
    hint: str = ""
    samples: tuple[str, ...] = ()  # the samples whose row this is (they need no "has no row" warning)
    cause: str = ""  # rows of one cause are reported once: "position_units", "angle_units", … ("" = its own)
    size: float = 0.0  # the offending magnitude (m, rad), for the summary


LISTED_ROWS = 3  # more rows of one cause than this are one problem, with the count and the first lines


def read_rows(
    text: str, spec: MeasurementSpec, sample_ids: set[str], by_line: bool = False
) -> tuple[dict[str, Array], list[RowProblem]]:
    """The measurement values of every row (sample id → values in the file's units and column
    order), and each bad row's problem. Raises csv.Error on broken CSV syntax. With
    `by_line` (the measurements are in the samples file itself) a file without an `id` column
    numbers its rows by line, as the samples were. Many rows of one cause (millimetres declared as
    metres: every row) are one problem that names the cause, with the count and the first lines."""
    problems: list[RowProblem] = []
    rows: dict[str, Array] = {}
    read = 0
    with io.StringIO(text, newline="") as handle:
        reader = csv.reader(handle)
        header = [h.strip() for h in next(reader, [])]
        if "id" not in header and not by_line:
            return rows, [
                RowProblem(
                    1,
                    "no 'id' column",
                    "name each row's sample in an 'id' column, as in the samples file, or put the measurements "
                    "in the samples file itself (its rows are then matched by line)",
                )
            ]
        missing = [c for c in spec.columns if c not in header]
        if missing:
            return rows, [
                RowProblem(
                    1,
                    f"column(s) {', '.join(missing)} missing",
                    "name them in observations.position_columns / rotation_columns",
                )
            ]
        id_col = header.index("id") if "id" in header else None
        cols = [header.index(c) for c in spec.columns]
        for line, row in enumerate(reader, start=2):
            if not row or all(not c.strip() for c in row):
                continue
            if line > MAX_SAMPLES + 1:
                problems.append(RowProblem(line, f"more than {MAX_SAMPLES} rows", "one row per sample"))
                break
            if len(row) < len(header):
                problems.append(RowProblem(line, f"{len(row)} values, header has {len(header)}", cause="width"))
                continue
            read += 1
            sid = row[id_col].strip() if id_col is not None else str(line)
            if sid in rows:
                problems.append(RowProblem(line, f"duplicate id '{sid}'", cause="duplicate_id"))
                continue
            if sid not in sample_ids:
                problems.append(RowProblem(line, f"sample id '{sid}' is not in the samples file", cause="unknown_id"))
                continue
            try:
                values = np.array([float(row[c]) for c in cols])
            except ValueError:
                bad = next(spec.columns[k] for k, c in enumerate(cols) if not _is_number(row[c]))
                text = row[cols[spec.columns.index(bad)]]
                problems.append(RowProblem(line, f"'{bad}' is not a number: {text!r}", "", (sid,), f"number:{bad}"))
                continue
            why = _value_problem(values, spec)
            if why is not None:
                problems.append(RowProblem(line, why.what, why.hint, (sid,), why.cause, why.size))
                continue
            rows[sid] = values
    return rows, _summarised(problems, read, spec)


def _summarised(problems: list[RowProblem], rows: int, spec: MeasurementSpec) -> list[RowProblem]:
    """Each cause shared by more than LISTED_ROWS rows as one problem at its first line: the
    count, the first lines, and for a unit the unit the file is likely in."""
    by_cause: dict[str, list[RowProblem]] = {}
    for p in problems:
        by_cause.setdefault(p.cause or f"row:{p.line}", []).append(p)
    out: list[RowProblem] = []
    for cause, group in by_cause.items():
        if len(group) <= LISTED_ROWS:
            out += group
            continue
        first = group[0]
        lines = ", ".join(str(p.line) for p in group[:LISTED_ROWS]) + ", …"
        largest = max(p.size for p in group)
        count = f"{len(group)} of {rows} rows (lines {lines})"
        samples = tuple(sid for p in group for sid in p.samples)
        what, hint = f"{count}: {first.what}", first.hint
        if cause == "position_units" and spec.convention.position_units is LengthUnit.M:
            what = f"{count} have positions of up to {largest:g} m as declared (position_units: m): the file is likely in millimetres"
            hint = "set observations.position_units: mm"
        elif cause == "angle_units":
            what = f"{count} have angles of up to {largest:g} rad: the file is likely in degrees"
            hint = "set observations.angle_units: deg"
        out.append(RowProblem(first.line, what, hint, samples, cause))
    return sorted(out, key=lambda p: p.line)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


@dataclass(frozen=True)
class _ValueProblem:
    what: str
    hint: str
    cause: str
    size: float = 0.0


def _value_problem(values: Array, spec: MeasurementSpec) -> _ValueProblem | None:
    """Why a row's values cannot be a measurement, with the fix."""
    if not np.isfinite(values).all():
        return _ValueProblem(
            "a value is NaN or infinite", "leave the sample out, or mark it in samples.csv only", "nan"
        )
    position = float(np.abs(values[:3]).max()) * spec.convention.position_units.metres
    if position > MAX_POSITION_M:
        return _ValueProblem(
            f"a position of {position:g} m: is it in millimetres?",
            "set observations.position_units to the unit the file uses",
            "position_units",
            position,
        )
    convention = spec.convention
    if isinstance(convention, PoseConvention):
        if (
            convention.rotation in (RotationForm.RPY, RotationForm.ROTATION_VECTOR)
            and convention.angle_units is AngleUnit.RAD
        ):
            largest = float(np.abs(values[3:]).max())
            if largest > 2 * math.pi + 0.5:
                return _ValueProblem(
                    f"an angle of {largest:g} rad: these look like degrees",
                    "set observations.angle_units: deg",
                    "angle_units",
                    largest,
                )
        why = convention.row_problem(values)
        if why is not None:
            return _ValueProblem(why, "check observations.rotation and rotation_columns", "rotation")
    return None
