"""Feetech transport framing: the reply is found among other packets in the same read."""

from __future__ import annotations

import pytest

from armtool.servo import packets as pk
from armtool.servo.protocols.feetech import Feetech
from armtool.servo.transport import CommError


class FakePort:
    """Hands out pre-set chunks, one per readPort call, as a serial port would."""

    tx_time_per_byte = 0.01
    timeout_ms = 20.0

    def __init__(self, chunks: list[bytes]) -> None:
        self.chunks = list(chunks)
        self.sent: list[bytes] = []

    def clearPort(self) -> None:
        pass

    def writePort(self, data: bytes) -> None:
        self.sent.append(bytes(data))

    def readPort(self, n: int) -> bytes:
        return self.chunks.pop(0) if self.chunks else b""


def test_reply_after_another_ids_packet_in_the_same_read() -> None:
    other = pk.status1(2, 0, bytes([0x10, 0x20]))
    ours = pk.status1(1, 0, bytes([0x34, 0x12]))
    port = FakePort([other + ours])
    data, err = Feetech(port).read(1, 56, 2)
    assert (data, err) == (bytes([0x34, 0x12]), 0)


def test_reply_after_a_damaged_packet_of_another_id() -> None:
    bad = bytearray(pk.status1(2, 0, b"\x01\x02"))
    bad[-1] ^= 0x5A
    port = FakePort([bytes(bad) + pk.status1(1, 0, b"\x07\x00")])
    assert Feetech(port).read(1, 56, 2) == (b"\x07\x00", 0)


def test_our_damaged_reply_is_corrupt() -> None:
    bad = bytearray(pk.status1(1, 0, b"\x01\x02"))
    bad[-1] ^= 0x5A
    with pytest.raises(CommError) as info:
        Feetech(FakePort([bytes(bad)])).read(1, 56, 2)
    assert info.value.kind == "corrupt"
