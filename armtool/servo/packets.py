"""Packet framing for both ends of the wire: Protocol 1.0 (also Feetech SCS/STS) and Protocol 2.0.

The Dynamixel clients use dynamixel-sdk's own framing; this module exists for the Feetech
client (which the SDK does not speak), for the simulator (the servo side, which the SDK
does not have), and for echo detection. Checked byte-for-byte against the e-manual's worked
examples in tests/servo/test_packets.py.

Protocol 1.0: `FF FF ID LEN INST P.. CHK`, LEN = n_params + 2, CHK = ~(ID+LEN+INST+sum(P)) & 0xFF.
Protocol 2.0: `FF FF FD 00 ID LEN_L LEN_H INST P.. CRC_L CRC_H`, byte stuffing of `FF FF FD` in
INST..params, LEN counts the stuffed bytes + 3, CRC-16 (poly 0x8005) over everything before it.
"""

from __future__ import annotations

from dataclasses import dataclass

PING, READ, WRITE, REG_WRITE, ACTION, FACTORY_RESET, REBOOT = 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x08
STATUS2 = 0x55
SYNC_READ, SYNC_WRITE, BULK_READ, BULK_WRITE = 0x82, 0x83, 0x92, 0x93
BROADCAST = 0xFE


@dataclass(frozen=True)
class Packet:
    """A decoded packet: `code` is the instruction, or the error byte for a status packet."""

    id: int
    code: int
    params: bytes


def checksum1(body: bytes) -> int:
    return (~sum(body)) & 0xFF


def encode1(sid: int, code: int, params: bytes = b"") -> bytes:
    body = bytes([sid, len(params) + 2, code]) + bytes(params)
    return b"\xff\xff" + body + bytes([checksum1(body)])


_CRC_TABLE: list[int] = []


def _crc_table() -> list[int]:
    if not _CRC_TABLE:
        for i in range(256):
            crc = i << 8
            for _ in range(8):
                crc = ((crc << 1) ^ 0x8005) if crc & 0x8000 else (crc << 1)
            _CRC_TABLE.append(crc & 0xFFFF)
    return _CRC_TABLE


def crc16(data: bytes, crc: int = 0) -> int:
    """CRC-16/BUYPASS: poly 0x8005, init 0, not reflected (e-manual protocol2 `update_crc`)."""
    table = _crc_table()
    for b in data:
        crc = ((crc << 8) ^ table[((crc >> 8) ^ b) & 0xFF]) & 0xFFFF
    return crc


def stuff(data: bytes) -> bytes:
    out = bytearray()
    for b in data:
        out.append(b)
        if b == 0xFD and out[-3:-1] == b"\xff\xff" and len(out) >= 3:
            out.append(0xFD)
    return bytes(out)


def unstuff(data: bytes) -> bytes:
    out = bytearray()
    i = 0
    while i < len(data):
        out.append(data[i])
        if (
            data[i] == 0xFD
            and out[-3:-1] == b"\xff\xff"
            and len(out) >= 3
            and i + 1 < len(data)
            and data[i + 1] == 0xFD
        ):
            i += 1  # skip the stuffed FD
        i += 1
    return bytes(out)


def encode2(sid: int, inst: int, params: bytes = b"", error: int | None = None) -> bytes:
    """Instruction packet, or a status packet when `error` is given (INST 0x55 then ERR)."""
    payload = bytes([inst]) + (bytes([error]) if error is not None else b"") + bytes(params)
    payload = stuff(payload)
    length = len(payload) + 2
    head = b"\xff\xff\xfd\x00" + bytes([sid, length & 0xFF, length >> 8]) + payload
    crc = crc16(head)
    return head + bytes([crc & 0xFF, crc >> 8])


def status1(sid: int, error: int, params: bytes = b"") -> bytes:
    return encode1(sid, error, params)


def status2(sid: int, error: int, params: bytes = b"") -> bytes:
    return encode2(sid, STATUS2, params, error=error)


class Corrupt(Exception):
    """A complete packet whose checksum/CRC does not match; `frame` holds its bytes."""

    def __init__(self, frame: bytes) -> None:
        super().__init__(frame.hex(" "))
        self.frame = frame


def parse1(buf: bytearray) -> Packet | None:
    """Take one Protocol 1.0 packet off the front of `buf` (resyncing on FF FF).

    Returns None when more bytes are needed; raises Corrupt (after consuming it) on a bad checksum.
    """
    while True:
        start = buf.find(b"\xff\xff")
        if start < 0:
            if buf[-1:] == b"\xff":
                del buf[:-1]
            else:
                buf.clear()
            return None
        del buf[:start]
        if len(buf) >= 3 and buf[2] == 0xFF:  # FF FF FF: skip one, the id cannot be 0xFF
            del buf[0]
            continue
        if len(buf) < 4:
            return None
        length = buf[3]
        if length < 2:
            del buf[:2]
            continue
        total = 4 + length
        if len(buf) < total:
            return None
        frame = bytes(buf[:total])
        del buf[:total]
        if checksum1(frame[2:-1]) != frame[-1]:
            raise Corrupt(frame)
        return Packet(frame[2], frame[4], frame[5:-1])


def parse2(buf: bytearray, status: bool = False) -> Packet | None:
    """Take one Protocol 2.0 packet off the front of `buf`. For a status packet `code` is ERR."""
    while True:
        start = buf.find(b"\xff\xff\xfd\x00")
        if start < 0:
            keep = (
                3
                if buf[-3:] == b"\xff\xff\xfd"
                else (2 if buf[-2:] == b"\xff\xff" else (1 if buf[-1:] == b"\xff" else 0))
            )
            del buf[: len(buf) - keep]
            return None
        del buf[:start]
        if len(buf) < 7:
            return None
        length = buf[5] | (buf[6] << 8)
        if length < 3 or length > 1024:
            del buf[:4]
            continue
        total = 7 + length
        if len(buf) < total:
            return None
        frame = bytes(buf[:total])
        del buf[:total]
        if crc16(frame[:-2]) != (frame[-2] | (frame[-1] << 8)):
            raise Corrupt(frame)
        payload = unstuff(frame[7:-2])
        if status:
            if len(payload) < 2 or payload[0] != STATUS2:
                raise Corrupt(frame)
            return Packet(frame[4], payload[1], payload[2:])
        return Packet(frame[4], payload[0], payload[1:])
