"""A servo bus: open a serial port, identify servos, read and write named registers.

Layering: `SerialPort` (dynamixel-sdk's PortHandler, opened exclusively and with our own
reply timeout) carries bytes; a `Transport` from `armtool.servo.protocols` frames one
transaction (PING/READ/WRITE/SYNC_WRITE) and reports the servo's error byte; `ServoBus` adds
what every command needs on top: model identification, named registers with the model's
encoding, read retries on timeout/corrupt replies, writes that are never retried after the
servo rejected them, echo detection at connect and the FTDI latency-timer warning.
"""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import cast

from armtool.errors import ArmtoolError
from armtool.servo.models import ServoModel, by_number, decode, encode, models_for
from armtool.servo.transport import CommError, Port, Transport

log = logging.getLogger(__name__)

DEFAULT_TIMEOUT_MS = 25.0
SYSFS_USB_SERIAL = Path("/sys/bus/usb-serial/devices")


class PortLost(ArmtoolError):
    """The serial port itself failed (adapter unplugged, device gone): nothing more can be sent."""


try:  # tcflush/tcgetattr on a vanished pty or USB adapter raise termios.error, not OSError
    from termios import error as _TermiosError

    _PORT_ERRORS: tuple[type[BaseException], ...] = (OSError, _TermiosError)
except ImportError:  # pragma: no cover - Windows
    _PORT_ERRORS = (OSError,)


class StatusError(ArmtoolError):
    """The servo answered but refused the instruction (range, angle limit, instruction, access...)."""

    def __init__(self, what: str, sid: int, error: int, hint: str | None = None) -> None:
        super().__init__(what, None, hint)
        self.sid = sid
        self.error = error


def ftdi_latency_ms(port_path: str) -> int | None:
    """The USB latency timer of an FTDI adapter (sysfs), None when the port is not one."""
    try:
        name = Path(os.path.realpath(port_path)).name
        text = (SYSFS_USB_SERIAL / name / "latency_timer").read_text().strip()
        return int(text)
    except (OSError, ValueError):
        return None


def _open_serial_error(path: str, exc: Exception) -> ArmtoolError:
    text = str(exc)
    if not os.path.exists(path):
        return ArmtoolError(
            f"serial port {path} does not exist",
            hint="plug the adapter in, or pass --port (e.g. /dev/ttyUSB0, /dev/ttyACM0)",
        )
    if "lock" in text.lower() or "busy" in text.lower() or "Errno 16" in text or "Errno 11" in text:
        return ArmtoolError(
            f"serial port {path} is busy (another program has it open)",
            hint="close the other program (another armtool, lerobot, Dynamixel Wizard) and retry",
        )
    if "Errno 13" in text or "ermission" in text:
        return ArmtoolError(
            f"no permission to open {path}", hint="add yourself to the 'dialout' group, then log in again"
        )
    return ArmtoolError(f"cannot open serial port {path}: {text}")


def _make_port_class() -> type:
    import serial
    from dynamixel_sdk import PortHandler

    class _SerialPort(PortHandler):  # type: ignore[misc]
        """PortHandler opened with an exclusive lock and an explicit reply timeout."""

        timeout_ms = DEFAULT_TIMEOUT_MS
        is_open: bool  # set by PortHandler.__init__ (untyped)

        def setupPort(self, cflag_baud: int) -> bool:
            if self.is_open:
                self.closePort()
            self.ser = serial.Serial(
                port=self.port_name, baudrate=self.baudrate, bytesize=serial.EIGHTBITS, timeout=0, exclusive=True
            )
            self.is_open = True
            self.ser.reset_input_buffer()
            self.tx_time_per_byte = (1000.0 / self.baudrate) * 10.0
            return True

        def setPacketTimeout(self, packet_length: int) -> None:
            self.packet_start_time = self.getCurrentTime()
            self.packet_timeout = self.tx_time_per_byte * packet_length + self.timeout_ms

    return _SerialPort


_PORT_CLASS: type | None = None


class SerialPort:
    """Factory: an opened PortHandler (`.ser` is the pyserial object). Raises ArmtoolError."""

    # A factory: __new__ returns the PortHandler subclass, not a SerialPort, hence the ignore.
    def __new__(cls, path: str, baud: int, timeout_ms: float = DEFAULT_TIMEOUT_MS) -> Port:  # type: ignore[misc]
        global _PORT_CLASS
        if _PORT_CLASS is None:
            _PORT_CLASS = _make_port_class()
        port = _PORT_CLASS(path)
        port.timeout_ms = timeout_ms
        if port.getCFlagBaud(baud) <= 0:
            raise ArmtoolError(
                f"baud rate {baud} is not supported",
                hint="use one of 9600, 57600, 115200, 1000000, 2000000, 3000000, 4000000",
            )
        try:
            port.setBaudRate(baud)
        except Exception as exc:  # serial.SerialException, OSError
            raise _open_serial_error(path, exc) from None
        return cast(Port, port)  # PortHandler (dynamixel-sdk) is untyped: an instance of it is Any


@dataclass
class Servo:
    """An identified servo on the bus."""

    id: int
    model: ServoModel
    firmware: int | None = None


@dataclass
class BusStats:
    reads: int = 0
    writes: int = 0
    retries: int = 0
    failures: int = 0


class ServoBus:
    """Named-register access to the servos on one port. Use `open_bus()` to make one."""

    def __init__(self, transport: Transport, path: str, baud: int, retries: int = 3) -> None:
        self.transport = transport
        self.path = path
        self.baud = baud
        self.retries = retries
        self.servos: dict[int, Servo] = {}
        self.last_error: dict[int, int] = {}
        self.warnings: list[str] = []
        self.stats = BusStats()

    @property
    def protocol(self) -> str:
        return self.transport.name

    def _lost(self, exc: BaseException) -> PortLost:
        return PortLost(
            f"lost the serial port {self.path}: {exc}",
            hint="the adapter was unplugged or lost power; switch the servo power off before touching "
            "the arm (torque may still be on), then reconnect and retry",
        )

    def close(self) -> None:
        try:
            self.transport.port.closePort()
        except Exception:
            pass

    def __enter__(self) -> ServoBus:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- connect-time checks
    def check_latency_timer(self) -> None:
        ms = ftdi_latency_ms(self.path)
        if ms is not None and ms > 1:
            name = Path(os.path.realpath(self.path)).name
            self.warnings.append(
                f"{name}: FTDI USB latency timer is {ms} ms (every reply waits up to that long); "
                f"set it to 1: echo 1 | sudo tee {SYSFS_USB_SERIAL / name / 'latency_timer'}"
            )

    def check_echo(self, sid: int, wait_s: float = 0.03) -> None:
        """Send a PING and look at what comes back: an adapter that echoes its own TX
        (missing half-duplex direction control) makes every read parse its own request."""
        packet = self.transport.ping_packet(sid)
        port = self.transport.port
        got = bytearray()
        try:
            port.clearPort()
            port.writePort(packet)
            deadline = time.monotonic() + wait_s
            while time.monotonic() < deadline and len(got) < 2 * len(packet):
                chunk = port.readPort(64)
                if chunk:
                    got.extend(chunk)
                else:
                    time.sleep(0.0005)
            port.clearPort()
        except _PORT_ERRORS as exc:
            raise self._lost(exc) from None
        if got.startswith(packet):
            raise ArmtoolError(
                f"the adapter on {self.path} echoes what it sends (half-duplex echo): every reply would be misread",
                hint="use a Dynamixel/Feetech adapter with direction control (U2D2, URT-1, Waveshare bus servo board), "
                "or check the TX/RX wiring of a DIY half-duplex circuit",
            )

    # -- identification
    def ping(self, sid: int, tries: int = 2) -> int:
        last: CommError | None = None
        for _ in range(tries):
            try:
                model_number, _err = self.transport.ping(sid)
                return model_number
            except _PORT_ERRORS as exc:
                raise self._lost(exc) from None
            except CommError as exc:
                last = exc
                self.stats.retries += 1
        assert last is not None
        raise last

    def identify(self, ids: Iterable[int], expected: Mapping[int, ServoModel] | None = None) -> dict[int, Servo]:
        """Ping every ID and look its model number up; refuse missing IDs, unknown and unexpected models."""
        ids = list(ids)
        found: dict[int, int] = {}
        missing: list[int] = []
        corrupt: list[int] = []
        for sid in ids:
            try:
                found[sid] = self.ping(sid)
            except CommError as exc:
                (corrupt if exc.kind == "corrupt" else missing).append(sid)
        if corrupt:
            raise ArmtoolError(
                f"ID {', '.join(map(str, corrupt))} answered with corrupt packets (bad checksum) on {self.path}",
                hint="two servos with the same ID, a wrong --protocol, noise on the bus, or a baud rate mismatch",
            )
        if not found:
            raise ArmtoolError(
                f"no servo answered on {self.path} at {self.baud} baud with protocol {self.protocol} "
                f"(tried ID {_ranges(ids)})",
                hint=f"check power and cable; try another --baud (AX: 1000000, X series: 57600, STS: 1000000) "
                f"or --protocol ({', '.join(p for p in ('dxl1', 'dxl2', 'feetech') if p != self.protocol)})",
            )
        if missing:
            raise ArmtoolError(
                f"ID {', '.join(map(str, missing))} did not answer on {self.path} ({self.baud} baud, {self.protocol})",
                hint=f"answering: ID {_ranges(sorted(found))}; check the cable to the missing servo, its ID and its baud rate",
            )
        for sid, number in found.items():
            model = by_number(self.protocol, number)
            if model is None:
                known = ", ".join(f"{m.name} ({m.model_number})" for m in models_for(self.protocol))
                raise ArmtoolError(
                    f"ID {sid} answered with model number {number}, which armtool does not know "
                    f"for protocol {self.protocol}",
                    hint=f"known models: {known}",
                )
            want = (expected or {}).get(sid)
            if want is not None and want.model_number != number:
                raise ArmtoolError(
                    f"ID {sid} is a {model.name} (model number {number}), not the {want.name} expected",
                    hint="check which servo has this ID, and the model named for it",
                )
            self.servos[sid] = Servo(sid, model)
        return {sid: self.servos[sid] for sid in ids}

    def model(self, sid: int) -> ServoModel:
        try:
            return self.servos[sid].model
        except KeyError:
            raise ArmtoolError(f"ID {sid} has not been identified on this bus") from None

    # -- registers
    def read_raw(self, sid: int, addr: int, n: int, what: str = "read") -> bytes:
        last: CommError | None = None
        for attempt in range(self.retries):
            try:
                data, err = self.transport.read(sid, addr, n)
                self.stats.reads += 1
                self.last_error[sid] = err
                if len(data) != n:
                    raise self.transport.comm_error(sid, "corrupt", what)
                why = self.transport.rejected(err)
                if why:
                    raise StatusError(f"ID {sid} refused to {what}: {why}", sid, err)
                return data
            except _PORT_ERRORS as exc:
                raise self._lost(exc) from None
            except CommError as exc:
                last = exc
                if attempt + 1 < self.retries:
                    self.stats.retries += 1
        self.stats.failures += 1
        assert last is not None
        raise CommError(
            f"ID {sid}: {what} failed {self.retries} times ({'no reply' if last.kind == 'timeout' else 'corrupt reply'})",
            last.kind,
            sid,
            hint="check the cable and power; a corrupt reply can mean two servos share this ID",
        )

    def read(self, sid: int, name: str) -> int:
        model = self.model(sid)
        reg = model.reg(name)
        return decode(reg, self.read_raw(sid, reg.addr, reg.size, f"read {name}"), model.big_endian)

    def read_many(self, sid: int, names: Iterable[str]) -> dict[str, int]:
        """Several registers in one READ spanning them (AX has no SYNC_READ: one packet per servo)."""
        model = self.model(sid)
        regs = {n: model.reg(n) for n in names}
        lo = min(r.addr for r in regs.values())
        hi = max(r.addr + r.size for r in regs.values())
        data = self.read_raw(sid, lo, hi - lo, "read " + ",".join(regs))
        return {n: decode(r, data[r.addr - lo :], model.big_endian) for n, r in regs.items()}

    def write(self, sid: int, name: str, value: int, *, retry: bool = False) -> None:
        """Write a register. `retry=True` only for idempotent writes (goal, torque off): a timed-out
        write is resent; a write the servo rejected is never resent."""
        model = self.model(sid)
        reg = model.reg(name)
        if not reg.writable:
            raise ArmtoolError(f"{model.name} register '{name}' is read-only")
        lo, hi = (reg.lo, reg.hi) if (reg.lo, reg.hi) != (0, 0) else (0, (1 << (8 * reg.size)) - 1)
        if not lo <= value <= hi:
            raise ArmtoolError(f"ID {sid}: {name} = {value} is outside {lo}..{hi} for {model.name}")
        data = encode(reg, value, model.big_endian)
        tries = self.retries if retry else 1
        last: CommError | None = None
        for attempt in range(tries):
            try:
                err = self.transport.write(sid, reg.addr, data)
                self.stats.writes += 1
                self.last_error[sid] = err
            except _PORT_ERRORS as exc:
                raise self._lost(exc) from None
            except CommError as exc:
                last = exc
                if attempt + 1 < tries:
                    self.stats.retries += 1
                continue
            why = self.transport.rejected(err)
            if why:
                raise StatusError(f"ID {sid} refused {name} = {value}: {why}", sid, err)
            return
        self.stats.failures += 1
        assert last is not None
        raise CommError(
            f"ID {sid}: write {name} = {value} got {'no reply' if last.kind == 'timeout' else 'a corrupt reply'}"
            + (f" ({tries} tries)" if tries > 1 else " (not retried: the write may or may not have happened)"),
            last.kind,
            sid,
        )

    def sync_write(self, name: str, values: Mapping[int, int]) -> None:
        """One SYNC_WRITE to several servos of the same register layout (no replies)."""
        if not values:
            return
        models = {self.model(sid).name for sid in values}
        first = self.model(next(iter(values)))
        reg = first.reg(name)
        if len({(self.model(s).reg(name).addr, self.model(s).reg(name).size) for s in values}) != 1:
            raise ArmtoolError(
                f"sync write of {name} across models with different layouts: {', '.join(sorted(models))}"
            )
        try:
            self.transport.sync_write(
                reg.addr, reg.size, {sid: encode(reg, v, self.model(sid).big_endian) for sid, v in values.items()}
            )
        except _PORT_ERRORS as exc:
            raise self._lost(exc) from None
        self.stats.writes += 1

    def overloaded(self, sid: int) -> bool:
        """The overload alarm: in the last error byte (AX, STS) or Hardware Error Status (X)."""
        model = self.model(sid)
        if model.has("hardware_error"):
            return bool(self.read(sid, "hardware_error") & model.overload_bit)
        if model.has("status"):
            return bool(self.read(sid, "status") & model.overload_bit) or self.transport.overload(
                self.last_error.get(sid, 0)
            )
        return self.transport.overload(self.last_error.get(sid, 0))

    def overload_alarm(self, sid: int) -> bool:
        """`overloaded`, asked only when the last reply's error byte carries an alarm (every
        protocol flags one there), so a poll loop pays no extra read for it."""
        error = self.last_error.get(sid, 0)
        return bool(self.transport.overload(error) or self.transport.alarms(error)) and self.overloaded(sid)


def _ranges(ids: Iterable[int]) -> str:
    ids = sorted(set(ids))
    out: list[str] = []
    i = 0
    while i < len(ids):
        j = i
        while j + 1 < len(ids) and ids[j + 1] == ids[j] + 1:
            j += 1
        out.append(str(ids[i]) if i == j else f"{ids[i]}-{ids[j]}")
        i = j + 1
    return ",".join(out)


def open_bus(
    path: str,
    protocol: str,
    baud: int,
    *,
    echo_check_id: int | None = None,
    timeout_ms: float = DEFAULT_TIMEOUT_MS,
    retries: int = 3,
) -> ServoBus:
    """Open `path`, build the protocol's transport, warn on FTDI latency, detect TX echo."""
    from armtool.servo.registry import transport_class

    cls = transport_class(protocol)
    port = SerialPort(path, baud, timeout_ms)
    bus = ServoBus(cls(port), path, baud, retries)
    try:
        bus.check_latency_timer()
        if echo_check_id is not None:
            bus.check_echo(echo_check_id)
    except BaseException:
        bus.close()
        raise
    return bus
