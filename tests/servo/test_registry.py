"""The protocol registry: a new protocol is one module plus one registry line."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from armtool.errors import ArmtoolError
from armtool.servo import eeprom, lerobot
from armtool.servo import limits as L
from armtool.servo.bus import Transport
from armtool.servo.limits.auto import _rearm
from armtool.servo.models import by_name
from armtool.servo.registry import PROTOCOLS, Protocol, check_protocol, protocol_names, transport_class


class FakeProtocol(Transport):
    """A protocol nobody ships: its facts differ from every real one's where they can."""

    name = "fake"
    label = "Fake bus"
    default_model = "STS3215"
    rearm = "torque_enable"
    eeprom_lock = True
    homing_sign = -1
    position_mode = 7


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
