"""LeRobot calibration files: choose homing offsets from a recorded range, write, read, compare.

LeRobot (SO-100/SO-101 with Feetech STS3215, Koch with Dynamixel X) keeps one JSON per arm:
`{motor name: {id, drive_mode, homing_offset, range_min, range_max}}`, raw ticks, under
`~/.cache/huggingface/lerobot/calibration/robots/<robot type>/<id>.json`. At connect it compares
the file with the servos' Homing_Offset / Min / Max Position Limit registers and, if they differ,
offers to write the file into them (research/servo.md 2.1).

Its own calibration writes the offset that makes the pose held at "middle of range" read 2047
(Feetech: present = encoder - offset; Dynamixel: present = encoder + offset), then records plain
min/max. Two of its open problems are the reason this module exists:
* a range that crosses the 0/4095 seam is recorded as 0..4095 (lerobot #3586, #3587): here the
  offset is chosen from the recorded, unwrapped range, so that the range's middle reads 2047 and
  no end crosses the seam;
* the Feetech offset register is sign-magnitude, ±2047 (lerobot #1296): the offset only matters
  modulo one turn, so the representative that fits the register is taken, and a range that no
  offset the register accepts can keep off the seam is refused with the reason.

Pure functions; the command that uses them is `armtool limits --lerobot-calibration/--from-lerobot`.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from armtool.errors import ArmtoolError
from armtool.servo.models import ServoModel
from armtool.servo.registry import transport_class

if TYPE_CHECKING:
    from armtool.servo.limits.arm_file import Joint

HALF_TURN = 2047  # what LeRobot makes the middle of a range read (int(4095 / 2))
KEYS = ("id", "drive_mode", "homing_offset", "range_min", "range_max")
POSITION_MODE = 3  # Dynamixel X Operating Mode: single-turn position control
DXL_POSITION_MODE_OFFSET = 1024  # e-manual: outside ±1024 the offset is ignored in Position Control Mode


@dataclass(frozen=True)
class MotorCalibration:
    """One motor's entry, raw ticks, as LeRobot stores it."""

    id: int
    drive_mode: int
    homing_offset: int
    range_min: int
    range_max: int

    def as_dict(self) -> dict[str, int]:
        return {
            "id": self.id,
            "drive_mode": self.drive_mode,
            "homing_offset": self.homing_offset,
            "range_min": self.range_min,
            "range_max": self.range_max,
        }


@dataclass(frozen=True)
class OffsetRule:
    """How a model's homing offset moves the reading, and which register values it accepts."""

    sign: int  # present = encoder + sign * offset (Feetech -1, Dynamixel +1)
    lo: int
    hi: int
    ticks: int = 4096


def offset_rule(model: ServoModel, operating_mode: int | None = None) -> OffsetRule:
    """The rule of a 4096-tick model with a Homing_Offset register (STS3215, X series).
    `operating_mode` is the X servo's Operating Mode: in Position Control Mode (3) the servo
    ignores offsets outside ±1024; unknown (None) or extended modes accept the whole register."""
    if not model.has("homing_offset") or not model.wraps:
        raise ArmtoolError(
            f"a {model.name} has no homing offset register: LeRobot calibration files are for "
            "Feetech STS3215 (SO-100/SO-101) and Dynamixel X (Koch) servos"
        )
    reg = model.reg("homing_offset")
    if transport_class(model.protocol).homing_sign < 0:
        return OffsetRule(-1, reg.lo, reg.hi, model.ticks)
    if operating_mode == POSITION_MODE:
        return OffsetRule(1, -DXL_POSITION_MODE_OFFSET, DXL_POSITION_MODE_OFFSET, model.ticks)
    return OffsetRule(1, reg.lo, reg.hi, model.ticks)


def _fit(offset: int, rule: OffsetRule) -> int | None:
    """The value congruent to `offset` modulo one turn that the register accepts, nearest 0."""
    base = offset % rule.ticks
    fits = [v for v in (base - rule.ticks, base, base + rule.ticks) if rule.lo <= v <= rule.hi]
    return min(fits, key=abs) if fits else None


def choose_offset(
    lo: int, hi: int, recorded_offset: int, rule: OffsetRule, name: str, full_turn: bool = False
) -> tuple[int, int]:
    """(homing offset, shift) for a range lo..hi recorded while the servo held `recorded_offset`.

    lo..hi is the unwrapped recording (hi may pass 4095 when the travel crossed the seam). With the
    new offset every reading moves by `shift` (new = old + shift, modulo a turn); the offset puts the
    middle of the range at 2047, or as near as the register allows while both ends stay inside
    0..4095. A full-turn joint only needs its middle near 2047 (its range is 0..4095 anyway)."""
    ticks = rule.ticks
    span = hi - lo
    ideal = HALF_TURN - (lo + hi) // 2
    if full_turn:
        shifts = sorted(range(ideal - ticks // 2, ideal + ticks // 2), key=lambda s: (abs(s - ideal), s))
    else:
        if span > ticks - 1:
            raise ArmtoolError(
                f"joint '{name}': the recorded range {lo}..{hi} spans {span} ticks, a full turn or more; "
                "no homing offset keeps it off the 0/4095 seam",
                hint="give it LeRobot's full-turn range 0..4095 with --lerobot-full-turn",
            )
        shifts = sorted(range(-lo, ticks - 1 - hi + 1), key=lambda s: (abs(s - ideal), s))
    for shift in shifts:
        offset = _fit(recorded_offset + rule.sign * shift, rule)
        if offset is not None:
            return offset, shift
    raise ArmtoolError(
        f"joint '{name}': no homing offset the register accepts ({rule.lo}..{rule.hi}) keeps the "
        f"recorded range {lo}..{hi} (offset {recorded_offset} while recording) off the 0/4095 seam",
        hint="on a Dynamixel X, extended position mode (Operating Mode 4) accepts any offset; "
        "or turn the horn on the servo spline so the range lies away from the seam",
    )


def calibrate_joint(
    name: str,
    sid: int,
    lo: int,
    hi: int,
    recorded_offset: int,
    rule: OffsetRule,
    drive_mode: int = 0,
    full_turn: bool = False,
) -> MotorCalibration:
    """One motor's LeRobot entry from its range lo..hi (the ends the servo may reach)."""
    offset, shift = choose_offset(lo, hi, recorded_offset, rule, name, full_turn)
    if full_turn:
        return MotorCalibration(sid, drive_mode, offset, 0, rule.ticks - 1)
    return MotorCalibration(sid, drive_mode, offset, lo + shift, hi + shift)


def document(calibration: dict[str, MotorCalibration]) -> str:
    """The JSON text LeRobot reads (its own layout: 4-space indent, keys in this order)."""
    return json.dumps({name: cal.as_dict() for name, cal in calibration.items()}, indent=4) + "\n"


# ---------------------------------------------------------------- reading
def _line_of(text: str, motor: str, key: str | None = None) -> int | None:
    m = re.search(r'"' + re.escape(motor) + r'"\s*:', text)
    if m is None:
        return None
    pos = m.start()
    if key is not None:
        k = re.compile(r'"' + re.escape(key) + r'"\s*:').search(text, m.end())
        if k is not None:
            pos = k.start()
    return text.count("\n", 0, pos) + 1


def read_calibration(path: Path) -> dict[str, MotorCalibration]:
    """A LeRobot calibration file, checked strictly: every motor an object with exactly the five
    keys, whole numbers (JSON integers, not 12.0 or "12"), ticks 0..4095, range_min < range_max."""
    from armtool.fileio import read_text

    text = read_text(path, "LeRobot calibration file", 1024 * 1024)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ArmtoolError(f"not valid JSON: {exc.msg}", f"{path}:{exc.lineno}") from None
    except RecursionError:
        raise ArmtoolError("LeRobot calibration file is nested too deeply", str(path)) from None
    if not isinstance(data, dict) or not data:
        raise ArmtoolError(
            "a LeRobot calibration file is a JSON object: motor name -> {id, drive_mode, "
            "homing_offset, range_min, range_max}",
            str(path),
        )
    out: dict[str, MotorCalibration] = {}
    for motor, entry in data.items():
        where = f"{path}:{_line_of(text, motor) or 1}"
        if not isinstance(entry, dict):
            raise ArmtoolError(f"motor '{motor}' must be an object with {', '.join(KEYS)}", where)
        missing = [k for k in KEYS if k not in entry]
        if missing:
            raise ArmtoolError(
                f"motor '{motor}' has no {', '.join(missing)}", where, hint="every motor needs " + ", ".join(KEYS)
            )
        unknown = [str(k) for k in entry if k not in KEYS]
        if unknown:
            raise ArmtoolError(
                f"motor '{motor}': unknown key(s) {', '.join(unknown)}",
                where,
                hint="LeRobot refuses keys other than " + ", ".join(KEYS),
            )
        values: dict[str, int] = {}
        for key in KEYS:
            value = entry[key]
            kwhere = f"{path}:{_line_of(text, motor, key) or 1}"
            if isinstance(value, bool) or not isinstance(value, int):
                raise ArmtoolError(f"{motor}.{key} must be a whole number of ticks, got {json.dumps(value)}", kwhere)
            values[key] = value
        bounds = {
            "id": (0, 252),
            "drive_mode": (0, 255),
            "range_min": (0, 4095),
            "range_max": (0, 4095),
            "homing_offset": (-1044479, 1044479),
        }
        for key, (lo, hi) in bounds.items():
            if not lo <= values[key] <= hi:
                raise ArmtoolError(
                    f"{motor}.{key} = {values[key]} is outside {lo}..{hi}", f"{path}:{_line_of(text, motor, key) or 1}"
                )
        if values["range_min"] >= values["range_max"]:
            raise ArmtoolError(
                f"motor '{motor}': range_min {values['range_min']} is not below range_max {values['range_max']}",
                f"{path}:{_line_of(text, motor, 'range_min') or 1}",
                hint="record the range again (the joint did not move, or the file was edited)",
            )
        out[str(motor)] = MotorCalibration(**values)
    ids = [c.id for c in out.values()]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    if dup:
        raise ArmtoolError(f"ID {dup[0]} is given to more than one motor", str(path))
    return out


def check_against_arm(
    calibration: dict[str, MotorCalibration], joints: list[Joint], path: Path, rules: dict[str, OffsetRule]
) -> None:
    """The file names exactly the arm's joints, with the arm's IDs, and offsets its registers accept.
    `rules` maps joint name -> OffsetRule."""
    from armtool.fileio import read_text

    text = read_text(path, "LeRobot calibration file", 1024 * 1024)  # for line numbers in messages
    names = [j.name for j in joints]
    missing = [n for n in names if n not in calibration]
    if missing:
        raise ArmtoolError(
            f"motor(s) {', '.join(missing)} of the arm file are missing",
            str(path),
            hint="the file has " + ", ".join(calibration) + "; motor names must be the arm file's joint names",
        )
    extra = [n for n in calibration if n not in names]
    if extra:
        raise ArmtoolError(
            f"motor(s) {', '.join(extra)} are not joints of the arm file", str(path), hint="joints: " + ", ".join(names)
        )
    for j in joints:
        cal = calibration[j.name]
        if cal.id != j.id:
            raise ArmtoolError(
                f"{j.name}.id is {cal.id}, the arm file gives ID {j.id}", f"{path}:{_line_of(text, j.name, 'id') or 1}"
            )
        rule = rules.get(j.name)
        if rule is not None and not rule.lo <= cal.homing_offset <= rule.hi:
            same = _fit(cal.homing_offset, rule)
            raise ArmtoolError(
                f"{j.name}.homing_offset {cal.homing_offset} does not fit the register ({rule.lo}..{rule.hi})",
                f"{path}:{_line_of(text, j.name, 'homing_offset') or 1}",
                hint=f"an offset only matters modulo 4096: {same} reads the same"
                if same is not None
                else "record the arm again with `armtool limits --lerobot-calibration`",
            )


def frame_shift(file_offset: int, servo_offset: int, rule: OffsetRule) -> int:
    """Ticks to add to a reading under the file's offset to get the reading under the servo's
    present offset (the arm file's zero_ticks frame)."""
    return rule.sign * (servo_offset - file_offset)


def align(lo: int, hi: int, near: float, ticks: int = 4096) -> tuple[int, int]:
    """lo..hi moved by whole turns so that its middle is nearest `near`."""
    k = round((near - (lo + hi) / 2) / ticks)
    return lo + k * ticks, hi + k * ticks


@dataclass(frozen=True)
class RangeCheck:
    name: str
    file_min: int
    file_max: int
    recorded_min: int
    recorded_max: int
    past_min: int  # ticks the file's range reaches beyond the recorded low end (> 0: into the stop)
    past_max: int

    def ok(self, tolerance: int) -> bool:
        return self.past_min <= tolerance and self.past_max <= tolerance


def compare(name: str, file_range: tuple[int, int], recorded: tuple[int, int], ticks: int = 4096) -> RangeCheck:
    """A file's range against the recorded one, both in ticks under the same offset."""
    rlo, rhi = recorded
    flo, fhi = align(file_range[0], file_range[1], (rlo + rhi) / 2, ticks)
    return RangeCheck(name, flo, fhi, rlo, rhi, rlo - flo, fhi - rhi)
