"""Dynamixel Protocol 1.0 (AX-12A, AX-18A, MX in 1.0 firmware), framed by dynamixel-sdk.

No SYNC_READ in 1.0, and the SDK's GroupBulkRead raises TypeError on 1.0 (research/servo.md
1.1), so reads are one READ per servo; several registers are read in one multi-byte READ.
"""

from __future__ import annotations

from collections.abc import Mapping

from armtool.servo.packets import PING, encode1
from armtool.servo.protocols._sdk import SdkTransport

# Status error byte bits (e-manual protocol1)
ERR_VOLTAGE, ERR_ANGLE, ERR_OVERHEAT, ERR_RANGE, ERR_CHECKSUM, ERR_OVERLOAD, ERR_INSTRUCTION = (
    1 << i for i in range(7)
)
_REJECT = {
    ERR_ANGLE: "goal outside the angle limits",
    ERR_RANGE: "value out of range (or EEPROM locked)",
    ERR_CHECKSUM: "instruction checksum error",
    ERR_INSTRUCTION: "undefined instruction",
}
_ALARM = {ERR_VOLTAGE: "input voltage", ERR_OVERHEAT: "overheating", ERR_OVERLOAD: "overload"}


class Dxl1(SdkTransport):
    name = "dxl1"
    label = "Dynamixel Protocol 1.0"
    version = 1.0
    default_model = "AX-12A"
    rearm = "torque_limit"  # alarm shutdown sets Torque Limit to 0; writing it back re-arms
    wheel_mode_when_limits_zero = True  # CW and CCW angle limits both 0
    sync_read = False
    eeprom_needs_torque_off = True  # and while Lock = 1 (no eeprom_lock: Lock refuses, it does not hold)
    refusal_bits: Mapping[str, int] = {
        "range": ERR_RANGE,
        "angle": ERR_ANGLE,
        "access": ERR_RANGE,
        "length": ERR_RANGE,
        "limit": ERR_ANGLE,
        "instruction": ERR_INSTRUCTION,
        "checksum": ERR_CHECKSUM,
    }

    def ping_packet(self, sid: int) -> bytes:
        return encode1(sid, PING)

    def rejected(self, error: int) -> str | None:
        why = [text for bit, text in _REJECT.items() if error & bit]
        return ", ".join(why) or None

    def alarms(self, error: int) -> list[str]:
        return [text for bit, text in _ALARM.items() if error & bit]

    def overload(self, error: int) -> bool:
        return bool(error & ERR_OVERLOAD)
