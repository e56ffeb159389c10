"""The protocol registry: a new protocol is one module plus one registry line."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from armtool.errors import ArmtoolError
from armtool.servo import eeprom, lerobot
from armtool.servo import limits as L
from armtool.servo.limits.auto import _rearm
from armtool.servo.models import by_name
from armtool.servo.registry import PROTOCOLS, Protocol, check_protocol, protocol_names, transport_class
from armtool.servo.transport import Transport


class FakeProtocol(Transport):
    """A protocol nobody ships: its facts differ from every real one's where they can."""

    name = "fake"
    label = "Fake bus"
    default_model = "STS3215"
    rearm = "torque_enable"
    eeprom_lock = True
    homing_sign = -1
    position_mode = 7
    alarm_register = "status"
    alert_bit = 0x40  # STS carries the Status bits themselves, X uses 0x80
    goal_outside_limits = "refuse"  # STS clamps
    status_read_level, status_all_level = 0, 3


FAKE_MODEL = dataclasses.replace(by_name("STS3215"), name="FAKE-1", protocol="fake")


class RecordingBus:
    def __init__(self) -> None:
        self.writes: list[tuple[int, str, int]] = []
        self.values: dict[str, int] = {"operating_mode": 7, "min_limit": 10}

    def model(self, sid: int) -> object:
        return FAKE_MODEL

    def read(self, sid: int, name: str) -> int:
        return self.values.get(name, 0)

    def write(self, sid: int, name: str, value: int, retry: bool = False) -> None:
        self.writes.append((sid, name, value))
        self.values[name] = value


@pytest.fixture
def fake(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(PROTOCOLS, "fake", f"{__name__}:FakeProtocol")


def test_every_protocol_enum_member_is_registered() -> None:
    assert [p.value for p in Protocol] == protocol_names()
    for p in Protocol:
        assert transport_class(p.value).name == p.value
    with pytest.raises(ArmtoolError, match="unknown protocol 'nope'"):
        check_protocol("nope")


def test_a_registered_fake_protocol_drives_limits_eeprom_and_lerobot(fake: None, tmp_path: Path) -> None:
    assert "fake" in protocol_names() and transport_class("fake") is FakeProtocol
    arm = tmp_path / "arm.yaml"
    arm.write_text("protocol: fake\njoints: [{name: a, id: 1}]\n")
    assert L.load_arm(arm).protocol == "fake"
    bus = RecordingBus()
    _rearm(bus, 1, FAKE_MODEL, 300)  # type: ignore[arg-type]
    assert bus.writes == [(1, "torque_enable", 1)]  # the fake's re-arm register, not dxl1's torque limit
    bus.writes.clear()
    eeprom.apply_writes(bus, [eeprom.EepromWrite(1, "min_limit", 10, 20)])  # type: ignore[arg-type]
    assert (1, "lock", 0) in bus.writes  # the fake locks its EEPROM
    assert lerobot.offset_rule(FAKE_MODEL).sign == -1
    bus.values["operating_mode"] = 3
    with pytest.raises(ArmtoolError, match="Operating Mode 7"):
        L.seek_joint(bus, None, L.Joint("a", 1), L.AutoParams())  # type: ignore[arg-type]


def test_the_simulator_plays_a_registered_fake_protocol_from_its_facts(fake: None) -> None:
    from armtool.servo.models import encode
    from armtool.servo.sim.config import ServoSpec
    from armtool.servo.sim.servo import E_LIMIT, OK, SimServo

    servo = SimServo(ServoSpec(1, FAKE_MODEL, 10.0, 350.0, 180.0))  # no table of families to extend
    assert servo.proto is FakeProtocol
    servo.set("homing_offset", 100)
    assert servo.offset_shift() == -100  # the fake's homing sign
    servo.set("alarm_shutdown", 0x20)
    servo._trip()
    assert servo.error_bits() == 0x40 and servo.get("torque_enable") == 0  # its alert bit, its cut
    limits = (FAKE_MODEL.reg("min_limit"), FAKE_MODEL.reg("max_limit"))
    servo.mem[limits[0].addr : limits[0].addr + 2] = encode(limits[0], 1000)
    servo.mem[limits[1].addr : limits[1].addr + 2] = encode(limits[1], 3000)
    goal = FAKE_MODEL.reg("goal_position")
    assert servo.write(goal.addr, encode(goal, 500)) == E_LIMIT  # refused, not clamped as on an STS
    assert servo.write(goal.addr, encode(goal, 2000)) == OK
    servo.set("status_return_level", 2)
    assert servo.answers(True, False) and not servo.answers(False, False)  # levels 0 (read) and 3 (all)
