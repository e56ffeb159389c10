"""Dynamixel Protocol 2.0 (X series, MX in 2.0 firmware), framed by dynamixel-sdk (CRC16, stuffing).

The error byte's low 7 bits say why an instruction was refused; bit 7 (Alert) says the servo
is in a hardware-error state (read Hardware Error Status, 70) and has turned its torque off.
"""

from __future__ import annotations

from collections.abc import Mapping

from armtool.servo.packets import PING, encode2
from armtool.servo.protocols._sdk import SdkTransport

ALERT = 0x80
_REJECT = {
    1: "result fail",
    2: "instruction error",
    3: "CRC error",
    4: "data range error",
    5: "data length error",
    6: "data limit error",
    7: "access error (EEPROM write with torque on, or read-only)",
}


class Dxl2(SdkTransport):
    name = "dxl2"
    label = "Dynamixel Protocol 2.0"
    version = 2.0
    default_model = "XL430-W250"
    rearm = None  # Hardware Error Status latches until REBOOT or a power cycle
    position_mode = 3  # Operating Mode 3 = position control
    framing = 2
    alarm_register = "hardware_error"  # Hardware Error Status (70); the error byte only says Alert
    alert_bit = ALERT
    alarm_needs_shutdown = True
    eeprom_needs_torque_off = True
    goal_outside_limits = "refuse"  # data limit error
    goal_torque_on_bit = ("drive_mode", 8)  # Drive Mode bit 3: torque on by goal update
    position_mode_offset_limit = 1024  # e-manual: Homing Offset in Position Control Mode
    refusal_bits: Mapping[str, int] = {
        "instruction": 2,
        "checksum": 3,
        "range": 4,
        "length": 5,
        "angle": 6,
        "limit": 6,
        "access": 7,
    }

    def ping_packet(self, sid: int) -> bytes:
        return encode2(sid, PING)

    def rejected(self, error: int) -> str | None:
        code = error & 0x7F
        return _REJECT.get(code, f"error {code}") if code else None

    def alarms(self, error: int) -> list[str]:
        return ["hardware error (see Hardware Error Status)"] if error & ALERT else []

    def overload(self, error: int) -> bool:
        return False  # only Hardware Error Status (70) bit 5 says overload
