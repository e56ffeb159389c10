"""Ticks to radians with a safety margin, the limits YAML document, its summary table and the
writing of the YAML and the edited URDF."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from armtool.errors import ArmtoolError
from armtool.servo.limits.arm_file import JointRange
from armtool.servo.summary import Cell, Summary

SCHEMA = "armtool.limits/1"
LIMITS_VERSION = 1


def convert(r: JointRange, margin_deg: float) -> dict[str, Any]:
    model = r.model
    margin = math.ceil(margin_deg / model.deg_per_tick - 1e-9) if margin_deg > 0 else 0
    safe_min, safe_max = r.raw_min + margin, r.raw_max - margin
    if safe_min >= safe_max:
        raise ArmtoolError(
            f"joint '{r.joint.name}': range {r.raw_min}..{r.raw_max} ticks is too small for a {margin_deg:g}° margin",
            hint="lower --margin",
        )
    zero = r.joint.zero_ticks if r.joint.zero_ticks is not None else model.default_zero
    if model.wraps:  # the zero in the turn nearest the middle of the range
        mid = (r.raw_min + r.raw_max) / 2
        zero = zero + model.ticks * round((mid - zero) / model.ticks)
    d = r.joint.direction
    a = d * (safe_min - zero) * model.rad_per_tick
    b = d * (safe_max - zero) * model.rad_per_tick
    evidence = dict(r.evidence)
    if r.crosses_seam:
        evidence["crosses_seam"] = True
    return {
        "name": r.joint.name,
        "id": r.joint.id,
        "model": model.name,
        "model_number": model.model_number,
        "ticks_per_range": model.ticks,
        "range_deg": model.range_deg,
        "homing_offset": None,
        "drive_mode": None,
        "zero_ticks": zero,
        "direction": d,
        "raw_min_ticks": r.raw_min,
        "raw_max_ticks": r.raw_max,
        "safe_min_ticks": safe_min,
        "safe_max_ticks": safe_max,
        "margin_deg": margin_deg,
        "lower_rad": round(min(a, b), 6),
        "upper_rad": round(max(a, b), 6),
        "method": r.method,
        "evidence": evidence,
    }


def limits_document(joints: list[dict[str, Any]], port: str, protocol: str, baud: int) -> dict[str, Any]:
    from datetime import datetime, timezone

    from armtool import __version__

    return {
        "schema": SCHEMA,
        "version": LIMITS_VERSION,
        "created": datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "tool": f"armtool {__version__}",
        "bus": {"port": port, "protocol": protocol, "baud": baud},
        "joints": joints,
    }


def dump_yaml(doc: dict[str, Any]) -> str:
    import yaml

    return yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=120)


def write_atomic(path: Path, text: str) -> None:
    from armtool.fileio import write_atomic as write

    write(path, text)


def summary(rows: list[dict[str, Any]], ranges: list[JointRange]) -> Summary:
    """The recorded limits as a table for the terminal: raw and safe ticks, degrees, how found."""
    table = Summary(
        "limits",
        ("joint", "id", "raw ticks", "safe ticks", "lower°", "upper°", "how"),
        left=("joint", "how"),
        no_wrap=("joint", "id", "raw ticks", "safe ticks", "lower°", "upper°"),
    )
    for row, r in zip(rows, ranges):
        how = (
            r.method
            if r.method != "auto"
            else "auto: " + "/".join(str(r.evidence[k]).split(" (")[0] for k in ("reason_min", "reason_max"))
        )
        how_cell: Cell = how if r.confirmed else ((how, ""), (" (unconfirmed)", "yellow"))
        table.rows.append(
            (
                row["name"],
                str(row["id"]),
                f"{row['raw_min_ticks']}..{row['raw_max_ticks']}",
                f"{row['safe_min_ticks']}..{row['safe_max_ticks']}",
                f"{math.degrees(row['lower_rad']):.1f}",
                f"{math.degrees(row['upper_rad']):.1f}",
                how_cell,
            )
        )
    return table


def write_outputs(
    doc_text: str,
    output: Path | None,
    urdf: Path | None,
    urdf_text: str | None,
    new_urdf: str | None,
    urdf_out: Path | None,
    in_place: bool,
    note: Callable[[str], None],
    stdout: Callable[[str], None],
) -> None:
    """The limits YAML (to -o, else to `stdout`) and the URDF with the new limits. A failed -o
    keeps the limits in a .partial file: a recording must not be repeated for a write."""
    from armtool.fileio import rescue_write, write_with_backup

    if output is not None:
        try:
            write_atomic(output, doc_text)
        except ArmtoolError as exc:
            saved = rescue_write(output, doc_text, "armtool-limits")
            raise ArmtoolError(f"{exc.what}; the limits were saved to {saved}", exc.where, exc.hint) from None
        note(f"wrote {output}")
    else:
        stdout(doc_text)
    if new_urdf is not None and urdf is not None:
        if in_place:
            backup = write_with_backup(urdf, new_urdf, urdf_text or "")
            note(f"wrote {urdf} (previous version in {backup.name})")
        elif urdf_out is not None:
            write_atomic(urdf_out, new_urdf)
            note(f"wrote {urdf_out}")
