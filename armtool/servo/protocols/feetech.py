"""Feetech SCS/STS/SMS: Protocol-1.0 framing, its own instruction set and error bits.

dynamixel-sdk cannot be used as is (its PING reads the model number at address 0, Feetech
keeps it at 3, and it has no SYNC_READ for 1.0), so the framing here is our own
(`armtool.servo.packets`), on the same exclusively-opened serial port.
"""

from __future__ import annotations

import time
from collections.abc import Mapping

from armtool.servo.packets import BROADCAST, PING, READ, SYNC_WRITE, WRITE, Corrupt, encode1, parse1
from armtool.servo.transport import CommError, CommErrorKind, Port, Transport

# Status error bits (scservo_sdk protocol_packet_handler)
_ALARM = {1: "input voltage", 2: "angle sensor", 4: "overheating", 8: "over-current", 32: "overload"}


class Feetech(Transport):
    name = "feetech"
    label = "Feetech SCS/STS"
    default_model = "STS3215"
    rearm = "torque_enable"  # overload turns torque off; torque on re-arms
    eeprom_lock = True  # EEPROM writes need Lock = 0 first
    homing_sign = -1  # present = encoder - Homing Offset (feetech-cli measured)
    alarm_register = "status"  # the error byte carries the Status register's bits
    status_read_level = 0  # level 0 still answers READ and PING, level 1 everything
    status_all_level = 1
    torque_enable_calibrate = 128  # writes the present position as the midpoint (2048)

    def __init__(self, port: Port) -> None:
        super().__init__(port)
        self._buf = bytearray()

    def _txrx(self, sid: int, inst: int, params: bytes, what: str) -> tuple[bytes, int]:
        port = self.port
        port.clearPort()
        self._buf.clear()
        packet = encode1(sid, inst, params)
        port.writePort(packet)
        expect = {READ: 6 + (params[1] if len(params) > 1 else 0)}.get(inst, 6)
        deadline = time.monotonic() + (port.tx_time_per_byte * (len(packet) + expect) + port.timeout_ms) / 1000.0
        while True:
            chunk = port.readPort(256)
            if chunk:
                self._buf.extend(chunk)
                while True:  # every packet in the buffer: another ID's late reply may come first
                    try:
                        pkt = parse1(self._buf)
                    except Corrupt as exc:
                        if exc.frame[2] != sid:
                            continue  # another servo's damaged packet: not our reply
                        raise CommError(f"ID {sid}: {what}: corrupt reply (checksum)", "corrupt", sid) from None
                    if pkt is None:
                        break
                    if pkt.id == sid:
                        return pkt.params, pkt.code
            elif time.monotonic() > deadline:
                kind: CommErrorKind = "corrupt" if self._buf else "timeout"
                raise CommError(
                    f"ID {sid}: {what}: " + ("no reply" if kind == "timeout" else "incomplete reply"), kind, sid
                )
            else:
                time.sleep(0.0002)

    def ping(self, sid: int) -> tuple[int, int]:
        _params, err = self._txrx(sid, PING, b"", "ping")
        data, err = self.read(sid, 3, 2)
        little = int.from_bytes(data, "little")
        from armtool.servo.models import by_number

        if by_number(self.name, little) is None:  # SCS series store words big-endian
            big = int.from_bytes(data, "big")
            if by_number(self.name, big) is not None:
                return big, err
        return little, err

    def read(self, sid: int, addr: int, n: int) -> tuple[bytes, int]:
        params, err = self._txrx(sid, READ, bytes([addr, n]), f"read {n} bytes at {addr}")
        if len(params) != n:
            raise CommError(f"ID {sid}: read {n} bytes at {addr}: reply has {len(params)}", "corrupt", sid)
        return params, err

    def write(self, sid: int, addr: int, data: bytes) -> int:
        _params, err = self._txrx(sid, WRITE, bytes([addr]) + data, f"write {len(data)} bytes at {addr}")
        return err

    def sync_write(self, addr: int, n: int, data: Mapping[int, bytes]) -> None:
        params = bytearray([addr, n])
        for sid, value in data.items():
            params += bytes([sid]) + value
        self.port.clearPort()
        self.port.writePort(encode1(BROADCAST, SYNC_WRITE, bytes(params)))

    def ping_packet(self, sid: int) -> bytes:
        return encode1(sid, PING)

    def rejected(self, error: int) -> str | None:
        return None  # Feetech status bits are all alarms, not refusals

    def alarms(self, error: int) -> list[str]:
        return [text for bit, text in _ALARM.items() if error & bit]

    def overload(self, error: int) -> bool:
        return bool(error & 32)
