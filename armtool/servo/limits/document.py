"""Ticks to radians with a safety margin, and the limits YAML document."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from armtool.errors import ArmtoolError
from armtool.servo.limits.arm_file import JointRange

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
