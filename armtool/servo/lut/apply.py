"""Wanted angles -> compensated commands, for a list of angles or a column of a CSV.

Why a column and not a whole trajectory format: a joint trajectory CSV (`time_s,shoulder_rad,
elbow_rad,...`) has one column per joint and every joint has its own table, so one call
converts one column and calls chain through a pipe. A joint angle becomes a servo angle with
`servo_deg = zero_deg + direction * joint_deg`, `zero_deg` being the servo angle at joint zero
(150° for an AX-12A centred at tick 512).
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from armtool.errors import ArmtoolError
from armtool.servo.lut.table import LutTable


@dataclass(frozen=True)
class Applied:
    text: str
    rows: int
    clipped: int


def _to_servo_deg(values: Sequence[float], unit: str, zero_deg: float | None, direction: int) -> np.ndarray:
    x = np.asarray(values, dtype=np.float64)
    if unit == "rad":
        x = np.degrees(x)
    if zero_deg is not None:
        x = zero_deg + direction * x
    return x


def _commands(table: LutTable, servo_deg: np.ndarray, clip: bool, where: Sequence[str]) -> tuple[np.ndarray, int]:
    lo, hi = table.valid_range_deg
    outside = (servo_deg < lo - 1e-9) | (servo_deg > hi + 1e-9)
    if outside.any() and not clip:
        i = int(np.argmax(outside))
        raise ArmtoolError(
            f"servo angle {servo_deg[i]:.3f}° is outside the table's range {lo:.2f}..{hi:.2f}°",
            where[i],
            hint="pass --clip to clamp to the measured range, or measure a wider range",
        )
    return table.command_ticks(np.clip(servo_deg, lo, hi)), int(outside.sum())


def apply_list(table: LutTable, angles_deg: Sequence[float], clip: bool = False) -> Applied:
    """CSV `angle_deg,command_ticks` for servo angles given directly."""
    for i, v in enumerate(angles_deg):
        if not math.isfinite(v):
            raise ArmtoolError(f"angle {v} is not a finite number", f"value {i + 1}")
    ticks, clipped = _commands(
        table, np.asarray(angles_deg, dtype=np.float64), clip, [f"value {i + 1}" for i in range(len(angles_deg))]
    )
    lines = ["angle_deg,command_ticks"] + [f"{a:g},{t}" for a, t in zip(angles_deg, ticks)]
    return Applied("\n".join(lines) + "\n", len(angles_deg), clipped)


def apply_csv(
    table: LutTable,
    text: str,
    source: str,
    column: str | None = None,
    zero_deg: float | None = None,
    direction: int = 1,
    clip: bool = False,
) -> Applied:
    """The CSV with one more column, `<name>_command_ticks`, for the angles in `column`."""
    lines = text.splitlines()
    first = 0
    while first < len(lines) and (not lines[first].strip() or lines[first].lstrip().startswith("#")):
        first += 1
    if first == len(lines):
        raise ArmtoolError("no header row", source, hint="the first line names the columns, e.g. angle_deg")
    from armtool.csvrows import csv_rows

    numbered = csv_rows(lines[first:], source, first + 1, "angle CSV")
    rows = [row for _, row in numbered]
    header = [h.strip() for h in rows[0]]
    angle_cols = [h for h in header if h.endswith(("_deg", "_rad"))]
    if column is None:
        if "angle_deg" in header:
            column = "angle_deg"
        elif len(angle_cols) == 1:
            column = angle_cols[0]
        else:
            raise ArmtoolError(
                "which column holds the angles?",
                f"{source}:{first + 1}",
                hint=f"pass --column, one of: {', '.join(angle_cols) or '(no *_deg or *_rad column)'}",
            )
    if column not in header:
        raise ArmtoolError(f"no column '{column}'", f"{source}:{first + 1}", hint="columns: " + ", ".join(header))
    base, _, unit = column.rpartition("_")
    if unit not in ("deg", "rad"):
        raise ArmtoolError(
            f"column '{column}' does not state its unit",
            f"{source}:{first + 1}",
            hint=f"name it {column}_deg or {column}_rad",
        )
    if unit == "rad" and zero_deg is None:
        raise ArmtoolError(
            f"'{column}' is a joint angle in radians: the servo angle at joint zero is needed",
            hint="pass --zero-deg (e.g. 150 for an AX-12A centred at tick 512) and --direction 1 or -1",
        )
    col = header.index(column)
    values: list[float] = []
    wheres: list[str] = []
    data_rows = []
    for line, row in numbered[1:]:
        if not any(cell.strip() for cell in row):
            continue
        where = f"{source}:{line}"
        if len(row) != len(header):
            raise ArmtoolError(f"row has {len(row)} fields, the header has {len(header)}", where)
        try:
            value = float(row[col])
        except ValueError:
            raise ArmtoolError(f"'{column}' is not a number: {row[col]!r}", where) from None
        if not math.isfinite(value):
            raise ArmtoolError(f"'{column}' is {row[col].strip()}", where)
        values.append(value)
        wheres.append(where)
        data_rows.append(row)
    if not values:
        raise ArmtoolError("no rows to convert", source)
    servo_deg = _to_servo_deg(values, unit, zero_deg, direction)
    ticks, clipped = _commands(table, servo_deg, clip, wheres)
    new_col = f"{base}_command_ticks" if base != "angle" else "command_ticks"
    if new_col in header:
        raise ArmtoolError(f"the CSV already has a column '{new_col}'", f"{source}:{first + 1}")
    out = io.StringIO()
    for comment in lines[:first]:
        out.write(comment + "\n")
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow([*header, new_col])
    for row, tick in zip(data_rows, ticks):
        writer.writerow([*row, int(tick)])
    return Applied(out.getvalue(), len(values), clipped)


def read_input(path: Path) -> tuple[str, str]:
    """(text, source name) of the CSV to convert; `-` is stdin."""
    import sys

    if str(path) == "-":
        return sys.stdin.read(), "<stdin>"
    try:
        return path.read_text(encoding="utf-8-sig"), str(path)
    except FileNotFoundError:
        raise ArmtoolError(f"no such file: {path}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ArmtoolError(f"cannot read {path}: {exc}") from None
