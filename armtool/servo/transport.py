"""What a protocol implements: one transaction at a time over an opened port (`Transport`), and
the errors a transaction raises. `armtool.servo.protocols` subclass `Transport`; `ServoBus`
(armtool.servo.bus) builds on it; the protocol registry names the subclasses."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Literal, Protocol

from armtool.errors import ArmtoolError

CommErrorKind = Literal["timeout", "corrupt"]


class CommError(ArmtoolError):
    """No valid reply: `kind` is "timeout" (nothing came back) or "corrupt" (bad checksum/frame)."""

    def __init__(
        self, what: str, kind: CommErrorKind, sid: int, where: str | None = None, hint: str | None = None
    ) -> None:
        super().__init__(what, where, hint)
        self.kind = kind
        self.sid = sid


class Port(Protocol):
    """What a Transport uses of an opened port: dynamixel-sdk's PortHandler surface (`SerialPort`)."""

    is_using: bool
    tx_time_per_byte: float
    timeout_ms: float

    def clearPort(self) -> None: ...

    def writePort(self, packet: bytes) -> int | None: ...

    def readPort(self, length: int) -> bytes: ...

    def closePort(self) -> None: ...


class Transport:
    """One protocol's transactions. Subclasses live in armtool/servo/protocols/."""

    name = ""
    label = ""
    # -- the protocol's facts, read by limits, eeprom, servo-lut, lerobot and the simulator
    default_model = ""  # the model a simulated joint gets when its config names none
    rearm: Literal["torque_limit", "torque_enable"] | None = None  # written after an overload cut the output
    wheel_mode_when_limits_zero = False  # both angle limits 0 = wheel (endless turn) mode
    position_mode: int | None = None  # Operating Mode value for position control, checked before moving
    eeprom_lock = False  # EEPROM writes need the `lock` register at 0 first
    homing_sign = 1  # present position = encoder + homing_sign * Homing Offset
    framing: Literal[1, 2] = 1  # packet layout: Protocol 1.0 (FF FF id len) or 2.0 (FF FF FD 00 id len16)
    sync_read = True  # the servos answer SYNC_READ
    # why a servo refused an instruction -> the status error byte it answers with (no key: no bit;
    # no "checksum" key: a packet with a bad checksum gets no reply). The simulator answers so.
    refusal_bits: Mapping[str, int] = {}
    # -- how the servo behaves, as the simulator plays it (research/servo.md 3.1)
    alarm_register: str | None = None  # register holding the alarm bits (None: only the error byte carries them)
    alert_bit: int | None = None  # the error byte flags a non-zero alarm register with this bit (None: its bits)
    alarm_needs_shutdown = False  # the alarm register latches only when Alarm Shutdown selects the alarm
    status_read_level = 1  # Status Return Level from which READ is answered (PING always is)
    status_all_level = 2  # ... from which every instruction is
    eeprom_needs_torque_off = False  # EEPROM writes are refused while torque is on
    goal_outside_limits: Literal["clamp", "refuse"] = "clamp"  # a goal outside the angle limits
    goal_torque_on_bit: tuple[str, int] | None = None  # a goal write turns torque on only with this register bit
    torque_enable_calibrate: int | None = None  # Torque Enable value that calibrates the midpoint instead
    position_mode_offset_limit: int | None = None  # |Homing Offset| above this is ignored in position mode

    def __init__(self, port: Port) -> None:
        self.port = port

    # -- transactions: raise CommError(kind) when no valid reply; return the error byte otherwise
    def ping(self, sid: int) -> tuple[int, int]:  # (model number, error byte)
        raise NotImplementedError

    def read(self, sid: int, addr: int, n: int) -> tuple[bytes, int]:
        raise NotImplementedError

    def write(self, sid: int, addr: int, data: bytes) -> int:
        raise NotImplementedError

    def sync_write(self, addr: int, n: int, data: Mapping[int, bytes]) -> None:
        raise NotImplementedError

    def ping_packet(self, sid: int) -> bytes:
        raise NotImplementedError

    # -- error byte meaning
    def rejected(self, error: int) -> str | None:
        """Why the servo refused the instruction, or None if it carried it out."""
        raise NotImplementedError

    def alarms(self, error: int) -> list[str]:
        """State alarms in the error byte (overload, overheat, voltage...)."""
        raise NotImplementedError

    def overload(self, error: int) -> bool:
        raise NotImplementedError

    def comm_error(self, sid: int, kind: CommErrorKind, what: str) -> CommError:
        return CommError(f"ID {sid}: {what}: " + ("no reply" if kind == "timeout" else "corrupt reply"), kind, sid)
