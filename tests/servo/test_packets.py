"""Framing against the ROBOTIS e-manual's worked examples (protocol1.md, protocol2.md)."""

from __future__ import annotations

import pytest

from armtool.servo import packets as pk


def h(text: str) -> bytes:
    return bytes.fromhex(text)


@pytest.mark.parametrize(
    "packet, sid, code, params",
    [
        ("FF FF 01 02 01 FB", 1, pk.PING, ""),  # ping ID 1
        ("FF FF 01 04 02 2B 01 CC", 1, pk.READ, "2B 01"),  # read temperature of ID 1
        ("FF FF FE 04 03 03 01 F6", 0xFE, pk.WRITE, "03 01"),  # set ID to 1 by broadcast
        ("FF FF 00 02 06 F7", 0, pk.FACTORY_RESET, ""),  # reset ID 0
        ("FF FF FE 02 05 FA", 0xFE, pk.ACTION, ""),  # ACTION
        (
            "FF FF FE 18 83 1E 04 00 10 00 50 01 01 20 02 60 03 02 30 00 70 01 03 20 02 80 03 12",
            0xFE,
            pk.SYNC_WRITE,
            "1E 04 00 10 00 50 01 01 20 02 60 03 02 30 00 70 01 03 20 02 80 03",
        ),
    ],
)
def test_protocol1_instruction_examples(packet: str, sid: int, code: int, params: str) -> None:
    assert pk.encode1(sid, code, h(params)) == h(packet)
    parsed = pk.parse1(bytearray(h(packet)))
    assert parsed == pk.Packet(sid, code, h(params))


@pytest.mark.parametrize(
    "packet, sid, error, params",
    [
        ("FF FF 01 02 00 FC", 1, 0, ""),  # ping reply
        ("FF FF 01 03 00 20 DB", 1, 0, "20"),  # temperature 32 °C
    ],
)
def test_protocol1_status_examples(packet: str, sid: int, error: int, params: str) -> None:
    assert pk.status1(sid, error, h(params)) == h(packet)


@pytest.mark.parametrize(
    "packet, sid, inst, params",
    [
        ("FF FF FD 00 01 03 00 01 19 4E", 1, pk.PING, ""),
        ("FF FF FD 00 01 07 00 02 84 00 04 00 1D 15", 1, pk.READ, "84 00 04 00"),  # read 4 bytes at 132
        ("FF FF FD 00 01 09 00 03 74 00 00 02 00 00 CA 89", 1, pk.WRITE, "74 00 00 02 00 00"),  # goal 512 at 116
    ],
)
def test_protocol2_instruction_examples(packet: str, sid: int, inst: int, params: str) -> None:
    assert pk.encode2(sid, inst, h(params)) == h(packet)
    assert pk.parse2(bytearray(h(packet))) == pk.Packet(sid, inst, h(params))


def test_protocol2_ping_status_example() -> None:
    # ID 1 answers a PING with model number 1030 (0x0406) and firmware 0x26
    packet = h("FF FF FD 00 01 07 00 55 00 06 04 26 65 5D")
    assert pk.status2(1, 0, h("06 04 26")) == packet
    assert pk.parse2(bytearray(packet), status=True) == pk.Packet(1, 0, h("06 04 26"))


def test_protocol2_byte_stuffing_round_trip() -> None:
    params = h("FF FF FD 10 FF FF FD")
    packet = pk.encode2(3, pk.WRITE, params)
    assert packet.count(h("FF FF FD FD")) == 2  # both occurrences stuffed
    assert pk.parse2(bytearray(packet)) == pk.Packet(3, pk.WRITE, params)


def test_parse_resyncs_after_garbage_and_waits_for_more() -> None:
    buf = bytearray(h("00 13 FF") + h("FF FF 01 02 00"))
    assert pk.parse1(buf) is None  # incomplete: keeps the partial packet
    buf.extend(h("FC"))
    assert pk.parse1(buf) == pk.Packet(1, 0, b"")
    assert buf == bytearray()


def test_bad_checksum_is_reported_and_consumed() -> None:
    buf = bytearray(h("FF FF 01 02 00 FD") + h("FF FF 01 02 00 FC"))
    with pytest.raises(pk.Corrupt):
        pk.parse1(buf)
    assert pk.parse1(buf) == pk.Packet(1, 0, b"")
    bad2 = bytearray(h("FF FF FD 00 01 03 00 01 19 4F"))
    with pytest.raises(pk.Corrupt):
        pk.parse2(bad2)


def test_crc16_check_value() -> None:
    assert pk.crc16(b"123456789") == 0xFEE8  # CRC-16/BUYPASS check value
