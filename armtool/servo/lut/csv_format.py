"""The measurement CSV that `servo-lut measure` writes and `servo-lut fit` reads.

Why a documented CSV and not an internal format: measurements taken by other means (a
protractor, a lab encoder, a spreadsheet) should feed the same fit. Every quantity column
names its unit in a suffix, so a file can never be read in the wrong unit:

    # armtool servo-lut measurements
    # schema_version: 1
    # servo_id: 1
    # servo_model: AX-12A
    # reference: encoder:/dev/ttyACM1
    command_ticks,present_ticks,reference_deg,load_pct,temperature_c,voltage_v,approach,repeat
    101,101,29.71,-3.2,34,11.9,up,0

Required columns: `command_ticks` (integer goal position) and `reference_deg` (or
`reference_rad`), the angle the reference measured, in the servo's datasheet frame (0° at
tick 0). Optional: `present_ticks`, `load_pct` (signed, % of maximum torque),
`temperature_c`, `voltage_v`, `approach` (`up` or `down`: the side the point was approached
from), `repeat` (0, 1, ...: several readings of one point), `settled` (1/0). Other columns
are kept out of the way; a column for a known quantity without a unit (`reference`,
`load`, `angle`) is refused. `# key: value` lines before the header carry metadata.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from armtool.errors import ArmtoolError
from armtool.servo.lut.choices import SIDES, Side
from armtool.servo.models import ServoModel, by_name

SCHEMA_VERSION = 1
TITLE = "armtool servo-lut measurements"
COLUMNS = (
    "command_ticks",
    "present_ticks",
    "reference_deg",
    "load_pct",
    "temperature_c",
    "voltage_v",
    "approach",
    "repeat",
    "settled",
)

# quantity -> units we understand (the first is the one we write)
_UNITS: dict[str, tuple[str, ...]] = {
    "command": ("ticks",),
    "present": ("ticks",),
    "reference": ("deg", "rad"),
    "load": ("pct",),
    "temperature": ("c",),
    "voltage": ("v",),
}
# names people use for those quantities without a unit -> the column we want
_UNITLESS = {
    "command": "command_ticks",
    "goal": "command_ticks",
    "present": "present_ticks",
    "position": "present_ticks",
    "reference": "reference_deg",
    "angle": "reference_deg",
    "load": "load_pct",
    "temperature": "temperature_c",
    "temp": "temperature_c",
    "voltage": "voltage_v",
}


@dataclass(frozen=True)
class Sample:
    """One row: the command, what the reference measured, and the servo's own telemetry."""

    line: int  # line in the CSV file (1-based), for messages
    command_ticks: int
    reference_deg: float
    present_ticks: float | None = None
    load_pct: float | None = None
    temperature_c: float | None = None
    voltage_v: float | None = None
    approach: Side = "up"
    repeat: int | None = None
    settled: bool | None = None


@dataclass(frozen=True)
class Measurements:
    """A measurement file: metadata plus samples, already checked."""

    source: str
    model: ServoModel
    samples: tuple[Sample, ...]
    servo_id: int | None = None
    reference: str = "unknown"
    meta: dict[str, str] = field(default_factory=dict)


def model_named(name: str, where: str | None = None) -> ServoModel:
    """The servo model called `name` (aliases such as ax12a accepted), or an error saying where."""
    try:
        return by_name(name)
    except ArmtoolError as exc:
        raise ArmtoolError(exc.what, where, exc.hint) from None


def _number(text: str, column: str, where: str, required: bool) -> float | None:
    text = text.strip()
    if not text:
        if required:
            raise ArmtoolError(f"empty '{column}'", where, hint=f"every row needs a {column} value")
        return None
    try:
        value = float(text)
    except ValueError:
        raise ArmtoolError(f"'{column}' is not a number: {text!r}", where) from None
    if not math.isfinite(value):
        raise ArmtoolError(f"'{column}' is {text.strip()}", where, hint="drop the row or measure the point again")
    return value


def _check_header(header: Sequence[str], where: str) -> dict[str, int]:
    """Column index per known column; refuses quantities without units and unknown units."""
    index: dict[str, int] = {}
    for pos, raw in enumerate(header):
        name = raw.strip().lower()
        if name in index:
            raise ArmtoolError(f"column '{name}' appears twice", where)
        if name in _UNITLESS:
            raise ArmtoolError(
                f"column '{raw.strip()}' does not state its unit",
                where,
                hint=f"name it {_UNITLESS[name]} (see `armtool servo-lut fit --help` for the format)",
            )
        base, _, unit = name.rpartition("_")
        if base in _UNITS and unit not in _UNITS[base]:
            wanted = " or ".join(f"{base}_{u}" for u in _UNITS[base])
            raise ArmtoolError(f"column '{raw.strip()}': unit '{unit}' not understood", where, hint=f"use {wanted}")
        index[name] = pos
    missing = [c for c in ("command_ticks",) if c not in index]
    if "reference_deg" not in index and "reference_rad" not in index:
        missing.append("reference_deg")
    if missing:
        found = ", ".join(h.strip() for h in header) or "none"
        raise ArmtoolError(
            f"missing column{'s' if len(missing) > 1 else ''} {', '.join(missing)}",
            where,
            hint=f"found: {found}; needed: command_ticks and reference_deg (or reference_rad)",
        )
    return index


def parse_measurements(text: str, source: str, model: str | None = None) -> Measurements:
    """Parse and check a measurement CSV. `model` overrides (or supplies) the file's servo_model."""
    meta: dict[str, str] = {}
    lines = text.splitlines()
    first = 0
    while first < len(lines) and (not lines[first].strip() or lines[first].lstrip().startswith("#")):
        meta_key, sep, value = lines[first].lstrip().lstrip("#").partition(":")
        if sep and meta_key.strip():
            meta[meta_key.strip().lower()] = value.strip()
        first += 1
    if first == len(lines):
        raise ArmtoolError(
            "no header row",
            source,
            hint="the first non-comment line names the columns: command_ticks,reference_deg,...",
        )
    from armtool.csvrows import csv_rows

    numbered = csv_rows(lines[first:], source, first + 1, "measurement CSV")
    rows = [row for _, row in numbered]
    index = _check_header(rows[0], f"{source}:{first + 1}")
    model_name = model or meta.get("servo_model")
    if not model_name:
        raise ArmtoolError(
            "the servo model is not stated",
            source,
            hint="add a line '# servo_model: AX-12A' above the header, or pass --model",
        )
    servo = model_named(model_name, f"{source}: servo_model")
    to_deg = 1.0 if "reference_deg" in index else 180.0 / math.pi
    ref_col = "reference_deg" if "reference_deg" in index else "reference_rad"
    samples: list[Sample] = []
    seen: dict[tuple[int, str, int | None], int] = {}
    for line, row in numbered[1:]:
        where = f"{source}:{line}"
        if not any(cell.strip() for cell in row):
            continue
        if len(row) != len(rows[0]):
            raise ArmtoolError(f"row has {len(row)} fields, the header has {len(rows[0])}", where)

        def cell(name: str) -> str:
            return row[index[name]] if name in index else ""

        command = _number(cell("command_ticks"), "command_ticks", where, True)
        assert command is not None
        if command != round(command) or not 0 <= command <= servo.max_tick:
            raise ArmtoolError(
                f"command_ticks {cell('command_ticks').strip()} is not a whole tick in "
                f"0..{servo.max_tick} ({servo.name})",
                where,
            )
        reference = _number(cell(ref_col), ref_col, where, True)
        assert reference is not None
        text = cell("approach").strip().lower() or meta.get("approach", "up").lower()
        approach = next((side for side in SIDES if side == text), None)
        if approach is None:
            raise ArmtoolError(f"approach '{text}' is neither 'up' nor 'down'", where)
        repeat_value = _number(cell("repeat"), "repeat", where, False)
        repeat = None if repeat_value is None else int(repeat_value)
        key = (int(command), approach, repeat)
        if key in seen:
            which = f"repeat {repeat}" if repeat is not None else "no repeat number"
            raise ArmtoolError(
                f"duplicated command {int(command)} (approach {approach}, {which}); first at line {seen[key]}",
                where,
                hint="give each reading of a point its own repeat number (a `repeat` column: 0, 1, ...), or drop the copy",
            )
        seen[key] = line
        settled_value = _number(cell("settled"), "settled", where, False)
        samples.append(
            Sample(
                line=line,
                command_ticks=int(command),
                reference_deg=reference * to_deg,
                present_ticks=_number(cell("present_ticks"), "present_ticks", where, False),
                load_pct=_number(cell("load_pct"), "load_pct", where, False),
                temperature_c=_number(cell("temperature_c"), "temperature_c", where, False),
                voltage_v=_number(cell("voltage_v"), "voltage_v", where, False),
                approach=approach,
                repeat=repeat,
                settled=None if settled_value is None else bool(settled_value),
            )
        )
    if not samples:
        raise ArmtoolError("no measurement rows", source, hint="measure with `armtool servo-lut measure`")
    servo_id = None
    if meta.get("servo_id", "").strip():
        try:
            servo_id = int(meta["servo_id"])
        except ValueError:
            raise ArmtoolError(f"servo_id '{meta['servo_id']}' is not a whole number", f"{source}: servo_id") from None
        if not 0 <= servo_id <= 252:
            raise ArmtoolError(f"servo_id {servo_id} is outside 0..252", f"{source}: servo_id")
    return Measurements(
        source=source,
        model=servo,
        samples=tuple(samples),
        servo_id=servo_id,
        reference=meta.get("reference", "unknown"),
        meta=meta,
    )


def read_measurements(path: Path, model: str | None = None) -> Measurements:
    from armtool.fileio import read_text

    return parse_measurements(read_text(path, "measurement file"), str(path), model)


def _fmt(value: float | int | bool | str | None) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, float):
        return f"{value:.4f}".rstrip("0").rstrip(".") if value != int(value) else str(int(value))
    return str(value)


def render_measurements(meta: dict[str, str], samples: Iterable[Sample]) -> str:
    """The CSV text for `samples` (metadata first, as `# key: value`)."""
    out = io.StringIO()
    out.write(f"# {TITLE}\n# schema_version: {SCHEMA_VERSION}\n")
    for key, value in meta.items():
        if key != "schema_version":
            out.write(f"# {key}: {value}\n")
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(COLUMNS)
    for s in samples:
        writer.writerow(
            [
                _fmt(v)
                for v in (
                    s.command_ticks,
                    s.present_ticks,
                    s.reference_deg,
                    s.load_pct,
                    s.temperature_c,
                    s.voltage_v,
                    s.approach,
                    s.repeat,
                    s.settled,
                )
            ]
        )
    return out.getvalue()


def write_atomic(path: Path, text: str) -> None:
    """Write the whole file or nothing (see armtool.fileio)."""
    from armtool.fileio import write_atomic as write

    write(path, text)
