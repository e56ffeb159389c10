"""LeRobot calibration files around a recording (`--lerobot-calibration`, `--from-lerobot`):
each servo's offset state read before recording, the file written from the recorded ranges,
a file's ranges compared with the recorded ones, and a file converted without a bus."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from armtool.errors import ArmtoolError
from armtool.servo import lerobot as LR
from armtool.servo.bus import ServoBus
from armtool.servo.limits.arm_file import Joint, JointRange
from armtool.servo.limits.document import convert
from armtool.servo.registry import transport_class
from armtool.servo.summary import Summary

TOLERANCE_TICKS = 2  # how far a file's end may pass a recorded one (the recording finds stops within 2 ticks)


@dataclass(frozen=True)
class ServoState:
    """A joint's offset rule and registers, read before recording (the recording is in ticks
    under the offset the servo holds now)."""

    rule: LR.OffsetRule
    homing_offset: int
    drive_mode: int  # Dynamixel: LeRobot compares it with the Drive Mode register; Feetech: software, 0
    min_limit: int
    max_limit: int


def servo_states(bus: ServoBus, joints: list[Joint]) -> dict[str, ServoState]:
    """Each joint's `ServoState`; a model without a homing offset is refused here."""
    state: dict[str, ServoState] = {}
    for j in joints:
        model = bus.model(j.id)
        mode = bus.read(j.id, "operating_mode") if transport_class(model.protocol).position_mode is not None else None
        state[j.name] = ServoState(
            LR.offset_rule(model, mode),
            bus.read(j.id, "homing_offset"),
            bus.read(j.id, "drive_mode") if model.has("drive_mode") else 0,
            bus.read(j.id, "min_limit"),
            bus.read(j.id, "max_limit"),
        )
    return state


def calibration_document(
    ranges: list[JointRange], rows: list[dict[str, Any]], state: dict[str, ServoState], full_turn: set[str]
) -> str:
    """The LeRobot JSON for the safe range of every joint (the margin inside each recorded end)."""
    bad = [r.joint.name for r in ranges if not r.confirmed and r.joint.name not in full_turn]
    if bad:
        raise ArmtoolError(
            f"not writing the LeRobot calibration: unconfirmed ends on {', '.join(bad)}",
            hint="manual: hold each joint at each end for --min-dwell seconds; a joint that turns "
            "freely can take LeRobot's full-turn range with --lerobot-full-turn",
        )
    out = {}
    for r, row in zip(ranges, rows):
        st = state[r.joint.name]
        out[r.joint.name] = LR.calibrate_joint(
            r.joint.name,
            r.joint.id,
            row["safe_min_ticks"],
            row["safe_max_ticks"],
            st.homing_offset,
            st.rule,
            st.drive_mode,
            r.joint.name in full_turn,
        )
    return LR.document(out)


def compare_ranges(
    calibration: dict[str, LR.MotorCalibration], source: Path, ranges: list[JointRange], state: dict[str, ServoState]
) -> tuple[list[LR.RangeCheck], Summary]:
    """Each motor's file range against the recorded one (in ticks under the servo's present offset)."""
    checks = []
    summary = Summary(
        f"LeRobot file {source} against the recorded ranges (ticks)",
        ("motor", "file range", "recorded", "past low end", "past high end", "verdict"),
        left=("motor", "verdict"),
    )
    differ = []
    for r in ranges:
        cal, st = calibration[r.joint.name], state[r.joint.name]
        shift = LR.frame_shift(cal.homing_offset, st.homing_offset, st.rule)
        check = LR.compare(r.joint.name, (cal.range_min + shift, cal.range_max + shift), (r.raw_min, r.raw_max))
        checks.append(check)
        held = (st.homing_offset, st.min_limit, st.max_limit)
        if held != (cal.homing_offset, cal.range_min, cal.range_max):
            differ.append(f"{r.joint.name} (offset {held[0]}, limits {held[1]}..{held[2]})")
        verdict = "ok" if check.ok(TOLERANCE_TICKS) else (("file reaches past the recorded stop", "red"),)
        summary.rows.append(
            (
                r.joint.name,
                f"{check.file_min}..{check.file_max}",
                f"{check.recorded_min}..{check.recorded_max}",
                str(check.past_min),
                str(check.past_max),
                verdict,
            )
        )
    if differ:
        summary.notes.append(
            "the servos' registers differ from the file on "
            + ", ".join(differ)
            + "; LeRobot will offer to write the file at its next connect"
        )
    return checks, summary


def converted_ranges(
    calibration: dict[str, LR.MotorCalibration], source: Path, joints: list[Joint], margin_deg: float
) -> tuple[list[JointRange], list[dict[str, Any]]]:
    """--from-lerobot without a bus: the file's ranges as recorded ranges and limits rows. The arm
    file's zero_ticks are taken as readings under the file's homing offsets (the offsets LeRobot
    writes into the servos)."""
    from armtool.servo.limits.request import check_motion_options

    ranges = []
    for j in joints:
        if j.model is None:
            raise ArmtoolError(
                f"joint '{j.name}' has no model in the arm file",
                str(source),
                hint="give every joint a model (e.g. model: STS3215) to convert ticks to radians",
            )
        check_motion_options(j, margin_deg, 0.0)
        cal = calibration[j.name]
        evidence = {
            "source": str(source),
            "lerobot_homing_offset": cal.homing_offset,
            "lerobot_drive_mode": cal.drive_mode,
        }
        ranges.append(JointRange(j, j.model, cal.range_min, cal.range_max, "lerobot", evidence))
    rows = [convert(r, margin_deg) for r in ranges]
    for row, j in zip(rows, joints):
        row["homing_offset"] = calibration[j.name].homing_offset
    return ranges, rows
