"""LeRobot calibration files: offsets that keep ranges off the seam, the register limits, strict
reading, comparison; and the simulator's homing offset that the command relies on."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from armtool.errors import ArmtoolError
from armtool.servo import lerobot as LR
from armtool.servo.limits import Joint
from armtool.servo.models import by_name
from armtool.servo.sim import SimBus

from .conftest import sim_config

STS = by_name("STS3215")
XL = by_name("XL430-W250")
FEETECH = LR.offset_rule(STS)
DXL_POSITION = LR.offset_rule(XL, operating_mode=3)


def reading(encoder: int, offset: int, rule: LR.OffsetRule) -> int:
    """What the servo reports for an encoder count under an offset (the rule being tested)."""
    return (encoder + rule.sign * offset) % rule.ticks


def test_rules_per_family() -> None:
    assert (FEETECH.sign, FEETECH.lo, FEETECH.hi) == (-1, -2047, 2047)
    assert (DXL_POSITION.sign, DXL_POSITION.lo, DXL_POSITION.hi) == (1, -1024, 1024)
    assert LR.offset_rule(XL, operating_mode=4).hi == 1044479  # extended position mode: the whole register
    with pytest.raises(ArmtoolError, match="AX-12A has no homing offset register"):
        LR.offset_rule(by_name("AX-12A"))


def test_middle_of_the_range_reads_2047() -> None:
    cal = LR.calibrate_joint("shoulder_pan", 1, 1000, 3000, 0, FEETECH)
    assert cal.homing_offset == -47 and (cal.range_min, cal.range_max) == (1047, 3047)
    assert reading(2000, cal.homing_offset, FEETECH) == 2047  # LeRobot's half-turn rule
    cal = LR.calibrate_joint("elbow", 3, 1000, 3000, 0, LR.offset_rule(XL))
    assert cal.homing_offset == 47 and reading(2000, 47, LR.offset_rule(XL)) == 2047


def test_a_range_across_the_seam_is_moved_off_it() -> None:
    """lerobot #3586/#3587: wrist_roll travels 3500..4700 encoder ticks (the reading wraps at 4096);
    plain min/max would give 0..4095. The chosen offset puts both ends inside 0..4095."""
    cal = LR.calibrate_joint("wrist_roll", 5, 3500, 4700, 0, FEETECH)
    assert -2047 <= cal.homing_offset <= 2047
    assert (cal.range_min, cal.range_max) == (1447, 2647)
    assert (
        reading(3500, cal.homing_offset, FEETECH) == 1447 and reading(4700 % 4096, cal.homing_offset, FEETECH) == 2647
    )
    # recorded under another offset: the same physical range gives the same new readings
    again = LR.calibrate_joint(
        "wrist_roll", 5, reading(3500, 700, FEETECH), reading(3500, 700, FEETECH) + 1200, 700, FEETECH
    )
    assert (again.homing_offset, again.range_min, again.range_max) == (cal.homing_offset, 1447, 2647)


def test_feetech_offset_never_overflows_the_sign_magnitude_register() -> None:
    """lerobot #1296: a middle pose at encoder 4095 needs offset 2048, one past the register; the
    offset is taken modulo a turn and, where even that does not fit, the middle moves one tick."""
    for mid in range(0, 4096, 7):
        lo, hi = mid - 1500, mid + 1500
        cal = LR.calibrate_joint("j", 1, lo, hi, 0, FEETECH)
        assert -2047 <= cal.homing_offset <= 2047
        assert 0 <= cal.range_min < cal.range_max <= 4095 and cal.range_max - cal.range_min == 3000
        assert reading(lo % 4096, cal.homing_offset, FEETECH) == cal.range_min
    cal = LR.calibrate_joint("j", 1, 3095, 5095, 0, FEETECH)  # middle at encoder 4095
    assert abs(cal.homing_offset) <= 2047 and (cal.range_min + cal.range_max) // 2 in (2046, 2047, 2048)


def test_dynamixel_position_mode_accepts_only_1024() -> None:
    cal = LR.calibrate_joint("j", 1, 3000, 3800, 0, DXL_POSITION)
    assert cal.homing_offset == -1024 and (cal.range_min, cal.range_max) == (1976, 2776)  # as near 2047 as it can
    with pytest.raises(ArmtoolError, match=r"no homing offset the register accepts \(-1024..1024\)") as exc:
        LR.calibrate_joint("j", 1, 100, 3900, 2000, DXL_POSITION)
    assert "extended position mode" in (exc.value.hint or "")
    assert LR.calibrate_joint("j", 1, 100, 3900, 2000, LR.offset_rule(XL, 4)).range_min >= 0


def test_full_turn() -> None:
    with pytest.raises(ArmtoolError, match="a full turn or more") as exc:
        LR.calibrate_joint("wrist_roll", 5, 0, 4200, 0, FEETECH)
    assert "--lerobot-full-turn" in (exc.value.hint or "")
    cal = LR.calibrate_joint("wrist_roll", 5, 0, 4200, 0, FEETECH, full_turn=True)
    assert (cal.range_min, cal.range_max) == (0, 4095) and abs(cal.homing_offset) <= 2047


def write(tmp_path: Path, doc: Any, name: str = "cal.json") -> Path:
    path = tmp_path / name
    path.write_text(doc if isinstance(doc, str) else json.dumps(doc, indent=4))
    return path


GOOD = {
    "shoulder_pan": {"id": 1, "drive_mode": 0, "homing_offset": -47, "range_min": 1047, "range_max": 3047},
    "gripper": {"id": 6, "drive_mode": 0, "homing_offset": 2000, "range_min": 2000, "range_max": 3400},
}


def test_document_is_lerobots_layout_and_reads_back(tmp_path: Path) -> None:
    cal = {name: LR.MotorCalibration(**v) for name, v in GOOD.items()}
    text = LR.document(cal)
    assert text.startswith('{\n    "shoulder_pan": {\n        "id": 1,\n        "drive_mode": 0,')
    assert LR.read_calibration(write(tmp_path, text)) == cal


@pytest.mark.parametrize(
    "change, message, line",
    [
        (lambda d: d["gripper"].pop("range_max"), "motor 'gripper' has no range_max", 9),
        (
            lambda d: d["gripper"].update(range_min=2000.5),
            "gripper.range_min must be a whole number of ticks, got 2000.5",
            13,
        ),
        (lambda d: d["gripper"].update(range_min=2000.0), "gripper.range_min must be a whole number", 13),
        (lambda d: d["gripper"].update(id=True), "gripper.id must be a whole number", 10),
        (
            lambda d: d["gripper"].update(homing_offset="12"),
            'gripper.homing_offset must be a whole number of ticks, got "12"',
            12,
        ),
        (
            lambda d: d["gripper"].update(range_min=3400),
            "motor 'gripper': range_min 3400 is not below range_max 3400",
            13,
        ),
        (lambda d: d["gripper"].update(range_max=5000), "gripper.range_max = 5000 is outside 0..4095", 14),
        (lambda d: d["gripper"].update(extra=1), "unknown key(s) extra", 9),
        (lambda d: d["gripper"].update(id=1), "ID 1 is given to more than one motor", None),
        (lambda d: d.update(gripper=[1, 2]), "motor 'gripper' must be an object", 9),
    ],
)
def test_bad_files_name_the_file_line_and_key(tmp_path: Path, change: Any, message: str, line: int | None) -> None:
    doc = json.loads(json.dumps(GOOD))
    change(doc)
    path = write(tmp_path, doc)
    with pytest.raises(ArmtoolError) as exc:
        LR.read_calibration(path)
    assert message in exc.value.what, exc.value.what
    assert exc.value.where == (f"{path}:{line}" if line else str(path))


def test_not_json_and_not_an_object(tmp_path: Path) -> None:
    with pytest.raises(ArmtoolError, match="not valid JSON") as exc:
        LR.read_calibration(write(tmp_path, '{\n  "a": {\n  ,\n}'))
    assert exc.value.where.endswith(":3")
    with pytest.raises(ArmtoolError, match="is a JSON object"):
        LR.read_calibration(write(tmp_path, "[]"))
    with pytest.raises(ArmtoolError, match="not found"):
        LR.read_calibration(tmp_path / "none.json")


def test_check_against_arm(tmp_path: Path) -> None:
    path = write(tmp_path, GOOD)
    cal = LR.read_calibration(path)
    joints = [Joint("shoulder_pan", 1, STS), Joint("gripper", 6, STS)]
    LR.check_against_arm(cal, joints, path, {j.name: FEETECH for j in joints})
    with pytest.raises(ArmtoolError, match="motor\\(s\\) elbow_flex of the arm file are missing"):
        LR.check_against_arm(cal, joints + [Joint("elbow_flex", 3, STS)], path, {})
    with pytest.raises(ArmtoolError, match="gripper.id is 6, the arm file gives ID 7"):
        LR.check_against_arm(cal, [Joint("shoulder_pan", 1, STS), Joint("gripper", 7, STS)], path, {})
    doc = json.loads(json.dumps(GOOD))
    doc["gripper"]["homing_offset"] = 2100  # lerobot #1296: past the sign-magnitude register
    path = write(tmp_path, doc, "over.json")
    with pytest.raises(
        ArmtoolError, match=r"gripper.homing_offset 2100 does not fit the register \(-2047..2047\)"
    ) as exc:
        LR.check_against_arm(LR.read_calibration(path), joints, path, {j.name: FEETECH for j in joints})
    assert exc.value.where == f"{path}:12" and "-1996 reads the same" in (exc.value.hint or "")


def test_compare_aligns_turns_and_measures_overreach() -> None:
    c = LR.compare("j", (1000, 3100), (4096 + 1010, 4096 + 3000))
    assert (c.file_min, c.file_max, c.past_min, c.past_max) == (5096, 7196, 10, 100)
    assert not c.ok(2) and LR.compare("j", (1010, 3000), (1009, 3001)).ok(2)
    assert LR.frame_shift(100, 40, FEETECH) == 60 and LR.frame_shift(100, 40, DXL_POSITION) == -60


# ---------------------------------------------------------------- the simulator
@pytest.mark.parametrize("protocol, offset, shift", [("feetech", 300, -300), ("dxl2", 300, 300), ("dxl2", 1500, 0)])
def test_sim_present_follows_the_offset_rule(protocol: str, offset: int, shift: int) -> None:
    """STS: present = encoder - offset; X: present = encoder + offset, an offset past ±1024 ignored
    in Position Control Mode (research/servo.md 1.4)."""
    cfg = sim_config(protocol, ids=(1,))
    cfg["joints"][0].update(stops=[800, 3300], start=2000)
    with SimBus.start(cfg) as sim:
        before = sim.present_ticks(1)
        lo, hi = sim.stop_ticks(1)
        sim.poke(1, "homing_offset", offset)
        assert sim.peek(1, "homing_offset") == offset
        assert sim.present_ticks(1) == (before + shift) % 4096
        assert sim.stop_ticks(1) == ((lo + shift) % 4096, (hi + shift) % 4096)
        # a goal is taken in the offset reading: the joint goes where the reading says
        sim.poke(1, "goal_position", (before + shift + 200) % 4096)
        if protocol == "dxl2":
            sim.poke(1, "torque_enable", 1)
        sim.wait(1.0)
        assert abs(sim.present_ticks(1) - (before + shift + 200) % 4096) <= 2
        assert abs(sim.true_angle_deg(1) - (2000 + 200) * 360 / 4096) < 0.5


def test_sim_config_offset_checked() -> None:
    cfg = sim_config("feetech", ids=(1,))
    cfg["joints"][0]["homing_offset"] = 2048
    with pytest.raises(ArmtoolError, match=r"'homing_offset' 2048 does not fit the STS3215's register \(-2047..2047\)"):
        SimBus.start(cfg)
    cfg["joints"][0]["homing_offset"] = -500
    with SimBus.start(cfg) as sim:
        assert sim.peek(1, "homing_offset") == -500
        sim.servo(1).power_cycle()
        assert sim.peek(1, "homing_offset") == -500  # an EEPROM value
