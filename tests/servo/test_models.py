"""Control tables: encodings and the registry of models and protocols."""

from __future__ import annotations

import pytest

from armtool.errors import ArmtoolError
from armtool.servo.models import MODELS, Register, by_name, by_number, decode, encode
from armtool.servo.registry import PROTOCOLS, transport_class


def test_sign_magnitude_and_twos_complement() -> None:
    sm10 = Register(40, 2, enc="sm10")
    assert encode(sm10, -300) == (300 | 0x400).to_bytes(2, "little")
    assert decode(sm10, encode(sm10, -300)) == -300
    sm15_be = Register(56, 2, enc="sm15")
    assert encode(sm15_be, -5, big_endian=True) == bytes([0x80, 0x05])
    s32 = Register(132, 4, enc="s")
    assert encode(s32, -1) == b"\xff\xff\xff\xff" and decode(s32, b"\xfe\xff\xff\xff") == -2


def test_tables_are_consistent() -> None:
    for m in MODELS:
        spans = sorted((r.addr, r.addr + r.size, n) for n, r in m.table.items())
        for (a0, a1, n0), (b0, _b1, n1) in zip(spans, spans[1:]):
            assert a1 <= b0, f"{m.name}: {n0} overlaps {n1}"
        for name in ("model_number", "id", "torque_enable", "goal_position", "present_position", "min_limit", "max_limit"):
            assert m.has(name), f"{m.name} lacks {name}"
        assert by_number(m.protocol, m.model_number) is m
    assert by_name("ax12a").model_number == 12 and by_name("STS3215").ticks == 4096
    with pytest.raises(ArmtoolError, match="known models"):
        by_name("MG996R")


def test_every_protocol_module_loads() -> None:
    for name in PROTOCOLS:
        assert transport_class(name).name == name
