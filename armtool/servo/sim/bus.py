"""The simulated bus: servos behind a pseudo-terminal, so real clients open a real device path.

`os.openpty()`; the slave path (`/dev/pts/N`) is what a client opens (dynamixel-sdk's
PortHandler, pyserial, `armtool limits --port`); the sim keeps the slave fd open so the master
never sees EIO when a client closes and reopens. One daemon thread `select()`s the master,
parses instruction packets, dispatches them to the servos, waits the Return Delay Time and
writes the status packets. Physics advances in 2 ms steps at every packet, every API call and
every 10 ms of silence. A second pty serves the external encoder (`A <id>\\n` -> `<deg>\\n`:
the TRUE joint angle in servo-frame degrees, Gaussian noise `encoder.noise_deg`).

    with SimBus.start(config) as sim:
        sim.port_path, sim.encoder_port_path, sim.true_angle_deg(1), sim.peek(1, "torque_enable")
"""

from __future__ import annotations

import copy
import os
import random
import select
import termios
import threading
import time
import tty
from collections import deque
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from armtool.errors import ArmtoolError
from armtool.servo import packets as pk
from armtool.servo.models import encode
from armtool.servo.registry import transport_class
from armtool.servo.sim.config import Faults, SimConfig, load_sim_config, sim_config_from_dict
from armtool.servo.sim.servo import E_ACCESS, E_ANGLE, E_INSTRUCTION, E_LENGTH, E_LIMIT, E_RANGE, OK, SimServo

if TYPE_CHECKING:
    from armtool.servo.sim.person import Person

STEP_S = 0.002
# the simulated servo's refusal codes by the names the protocol classes map to error bits
_REFUSAL = {
    E_RANGE: "range",
    E_ANGLE: "angle",
    E_ACCESS: "access",
    E_LENGTH: "length",
    E_LIMIT: "limit",
    E_INSTRUCTION: "instruction",
}
_BAUDS = {
    getattr(termios, f"B{b}"): b
    for b in (
        9600,
        19200,
        38400,
        57600,
        115200,
        230400,
        460800,
        500000,
        576000,
        921600,
        1000000,
        1152000,
        2000000,
        2500000,
        3000000,
        3500000,
        4000000,
    )
    if hasattr(termios, f"B{b}")
}


def _pty() -> tuple[int, int, str]:
    master, slave = os.openpty()
    tty.setraw(slave)
    return master, slave, os.ttyname(slave)


class SimBus:
    def __init__(self, config: SimConfig) -> None:
        self.config = config
        self.protocol = config.protocol
        self.proto = transport_class(config.protocol)  # framing, SYNC_READ, error bits
        self.faults: Faults = copy.deepcopy(config.faults)
        self.rng = random.Random(config.seed)
        self.servos: dict[int, SimServo] = {
            s.id: SimServo(s, config.overload_time_s, config.return_delay) for s in config.servos
        }
        self.lock = threading.RLock()
        self.stats = {
            "rx_packets": 0,
            "tx_packets": 0,
            "dropped": 0,
            "corrupted": 0,
            "bad_checksum": 0,
            "wrong_baud": 0,
        }
        self.log: deque[tuple[float, str, bytes]] | None = None
        self._master, self._slave, self.port_path = _pty()
        self._enc_master, self._enc_slave, self.encoder_port_path = _pty()
        self._buf = bytearray()
        self._enc_buf = bytearray()
        self._t0 = time.monotonic()
        self._t_sim = 0.0
        self._last_rx = 0.0
        self._baud_checked_at = -1.0
        self._baud_ok = True
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._serve, name="servo-sim", daemon=True)
        self.person: Person | None = None
        self.error: Exception | None = None  # set when the serving thread failed
        self.last_internal_error: str | None = None

    # -- lifecycle
    @classmethod
    def start(cls, config: SimConfig | dict[str, Any] | str | Path) -> SimBus:
        if isinstance(config, (str, Path)):
            config = load_sim_config(Path(config))
        elif isinstance(config, dict):
            config = sim_config_from_dict(config)
        sim = cls(config)
        sim._thread.start()
        if config.person is not None:
            from armtool.servo.sim.person import Person

            sim.person = Person(sim, config.person).start()
        return sim

    def __enter__(self) -> SimBus:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def stop(self) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=2.0)
        for name in ("_master", "_slave", "_enc_master", "_enc_slave"):
            fd = getattr(self, name)
            if fd < 0:
                continue
            try:
                os.close(fd)
            except OSError:
                pass
            setattr(self, name, -1)

    def hang_up(self) -> None:
        """Close the bus pty as an unplugged adapter would: the client's next read or write fails
        with an I/O error. The servos keep their state (peek still works); serving stops."""
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=2.0)
        for name in ("_master", "_slave"):
            fd = getattr(self, name)
            if fd >= 0:
                try:
                    os.close(fd)
                except OSError:
                    pass
                setattr(self, name, -1)

    def wait(self, seconds: float | None = None) -> None:
        """Serve until stop() or `seconds` elapse (the CLI's foreground loop); raises
        ArmtoolError if the serving thread failed."""
        self._stop.wait(seconds)
        if self.error is not None:
            what = (
                self.error.what
                if isinstance(self.error, ArmtoolError)
                else f"{type(self.error).__name__}: {self.error}"
            )
            raise ArmtoolError(f"the simulator stopped: {what}", self.config.source)

    # -- time and physics
    def now(self) -> float:
        return time.monotonic() - self._t0

    def advance(self) -> None:
        with self.lock:
            target = self.now()
            while self._t_sim < target:
                dt = min(STEP_S, target - self._t_sim)
                self._t_sim += dt
                for s in self.servos.values():
                    s.step(dt, self._t_sim)

    # -- API for tests and tools
    def servo(self, sid: int) -> SimServo:
        try:
            return self.servos[sid]
        except KeyError:
            raise ArmtoolError(f"the simulator has no servo with ID {sid}") from None

    def true_angle_deg(self, sid: int) -> float:
        self.advance()
        return self.servo(sid).theta

    def present_ticks(self, sid: int) -> int:
        self.advance()
        return self.servo(sid).reported_ticks()

    def stop_ticks(self, sid: int) -> tuple[int, int]:
        """What the servo reports when resting on its low and high mechanical stop."""
        return self.servo(sid).stop_ticks()

    def peek(self, sid: int, name: str) -> int:
        self.advance()
        with self.lock:
            s = self.servo(sid)
            s.refresh()
            return s.get(name)

    def poke(self, sid: int, name: str, value: int) -> None:
        with self.lock:
            s = self.servo(sid)
            reg = s.model.reg(name)
            s.write(reg.addr, encode(reg, value, s.model.big_endian))

    def set_hand(self, sid: int, fn: Callable[[float], float] | None) -> None:
        """With torque off the joint follows fn(sim_time_s) -> true degrees (clamped by the stops)."""
        self.advance()
        with self.lock:
            self.servo(sid).hand = fn

    def enable_log(self, maxlen: int = 5000) -> None:
        self.log = deque(maxlen=maxlen)

    # -- the serving thread
    def _serve(self) -> None:
        """The serving loop; an unexpected error stops the simulator and is raised by `wait()`
        instead of printing a thread traceback."""
        try:
            self._serve_loop()
        except Exception as exc:
            self.error = exc
            self._stop.set()

    def _serve_loop(self) -> None:
        fds = [self._master, self._enc_master]
        while not self._stop.is_set():
            try:
                ready, _, _ = select.select(fds, [], [], 0.01)
            except (OSError, ValueError):
                return
            self.advance()
            for fd in ready:
                try:
                    data = os.read(fd, 4096)
                except OSError:
                    continue
                if fd == self._master:
                    self._on_bus_bytes(data)
                else:
                    self._on_encoder_bytes(data)

    def _client_baud_ok(self) -> bool:
        now = self.now()
        if now - self._baud_checked_at > 0.2:
            self._baud_checked_at = now
            try:
                speed = termios.tcgetattr(self._slave)[4]
                baud = _BAUDS.get(speed)
                self._baud_ok = baud is None or baud == self.config.baud or speed == termios.B0
            except termios.error:
                self._baud_ok = True
        return self._baud_ok

    def _on_bus_bytes(self, data: bytes) -> None:
        if self.faults.echo:
            os.write(self._master, data)
        if self.log is not None:
            self.log.append((self.now(), "rx", data))
        if not self._client_baud_ok():
            self.stats["wrong_baud"] += 1
            return  # at the wrong baud rate the servos see only framing errors
        if self.now() - self._last_rx > 0.1:
            self._buf.clear()  # a stale partial packet is dropped
        self._last_rx = self.now()
        self._buf.extend(data)
        while True:
            try:
                pkt = pk.parse2(self._buf) if self.proto.framing == 2 else pk.parse1(self._buf)
            except pk.Corrupt as exc:
                self.stats["bad_checksum"] += 1
                self._on_bad_checksum(exc.frame)
                continue
            if pkt is None:
                return
            self.stats["rx_packets"] += 1
            try:
                with self.lock:
                    self._dispatch(pkt)
            except Exception as exc:
                self.stats["internal_errors"] = self.stats.get("internal_errors", 0) + 1
                self.last_internal_error = f"{type(exc).__name__}: {exc}"

    def _on_bad_checksum(self, frame: bytes) -> None:
        sid = frame[4] if self.proto.framing == 2 else frame[2]
        s = self.servos.get(sid)
        if s is None or sid in self.faults.missing_ids:
            return
        bit = self.proto.refusal_bits.get("checksum")
        if bit is not None:  # Feetech servos stay silent
            self._reply(s, bit | s.error_bits(), b"")

    def _on_encoder_bytes(self, data: bytes) -> None:
        self._enc_buf.extend(data)
        while b"\n" in self._enc_buf:
            line, _, rest = bytes(self._enc_buf).partition(b"\n")
            self._enc_buf[:] = rest
            parts = line.decode("ascii", "replace").split()
            out = "E bad request\n"
            if len(parts) == 2 and parts[0].upper() == "A" and parts[1].isdigit() and int(parts[1]) in self.servos:
                deg = self.true_angle_deg(int(parts[1]))
                if self.config.encoder_noise_deg > 0:
                    deg += self.rng.gauss(0.0, self.config.encoder_noise_deg)
                out = f"{deg:.4f}\n"
            os.write(self._enc_master, out.encode())

    # -- replies
    def _present(self, sid: int) -> SimServo | None:
        if sid in self.faults.missing_ids:
            return None
        return self.servos.get(sid)

    def _reply(self, s: SimServo, error: int, params: bytes) -> None:
        if self.faults.drop_next > 0:
            self.faults.drop_next -= 1
            self.stats["dropped"] += 1
            return
        if self.faults.p_drop and self.rng.random() < self.faults.p_drop:
            self.stats["dropped"] += 1
            return
        status = pk.status2 if self.proto.framing == 2 else pk.status1
        frame = bytearray(status(s.id, error, params))
        corrupt = self.faults.corrupt_next > 0 or (self.faults.p_corrupt and self.rng.random() < self.faults.p_corrupt)
        if corrupt:
            if self.faults.corrupt_next > 0:
                self.faults.corrupt_next -= 1
            frame[-1] ^= 0x5A
            self.stats["corrupted"] += 1
        delay = s.return_delay_s() + self.faults.delay_s
        if delay > 0:
            time.sleep(delay)
        os.write(self._master, bytes(frame))
        self.stats["tx_packets"] += 1
        if self.log is not None:
            self.log.append((self.now(), "tx", bytes(frame)))

    def _err(self, s: SimServo, code: int) -> int:
        return self.proto.refusal_bits.get(_REFUSAL.get(code, ""), 0) | s.error_bits()

    def _dispatch(self, pkt: pk.Packet) -> None:
        p2 = self.proto.framing == 2
        inst, params, sid = pkt.code, pkt.params, pkt.id
        broadcast = sid == pk.BROADCAST
        if inst == pk.SYNC_WRITE:
            self._sync_write(params, p2)
            return
        if inst == pk.SYNC_READ and self.proto.sync_read:
            self._sync_read(params, p2)
            return
        if inst == pk.ACTION:
            for s in self._targets(sid):
                if s.registered is not None:
                    addr, data = s.registered
                    s.registered = None
                    code = s.write(addr, data)
                    if not broadcast and s.answers(False, False):
                        self._reply(s, self._err(s, code), b"")
            return
        if inst == pk.PING and broadcast and p2:
            for s in sorted(self._targets(sid), key=lambda x: x.id):
                self._reply(s, self._err(s, OK), self._ping_params(s))
            return
        for s in self._targets(sid):
            answer = not broadcast
            out = b""
            code = OK
            if inst == pk.PING:
                out = self._ping_params(s) if p2 else b""
            elif inst == pk.READ:
                addr, n = (params[0] | params[1] << 8, params[2] | params[3] << 8) if p2 else (params[0], params[1])
                out, code = s.read(addr, n) if len(params) >= (4 if p2 else 2) else (b"", E_LENGTH)
            elif inst in (pk.WRITE, pk.REG_WRITE):
                k = 2 if p2 else 1
                if len(params) <= k:
                    code = E_LENGTH
                else:
                    addr = params[0] | (params[1] << 8 if p2 else 0)
                    if inst == pk.WRITE:
                        code = s.write(addr, bytes(params[k:]))
                    else:
                        s.registered = (addr, bytes(params[k:]))
            elif inst == pk.FACTORY_RESET:
                s.factory_reset()
            elif inst == pk.REBOOT and p2:
                s.reboot()
            else:
                code = E_INSTRUCTION
            if answer and s.answers(inst in (pk.READ, pk.PING), inst == pk.PING):
                self._reply(s, self._err(s, code), out)

    def _targets(self, sid: int) -> list[SimServo]:
        if sid == pk.BROADCAST:
            return [s for i, s in self.servos.items() if i not in self.faults.missing_ids]
        s = self._present(sid)
        return [s] if s is not None else []

    @staticmethod
    def _ping_params(s: SimServo) -> bytes:
        n = s.model.model_number
        return bytes([n & 0xFF, n >> 8, s.get("firmware")])

    def _sync_write(self, params: bytes, p2: bool) -> None:
        if p2:
            addr, n, body = params[0] | params[1] << 8, params[2] | params[3] << 8, params[4:]
        else:
            addr, n, body = params[0], params[1], params[2:]
        step = n + 1
        for k in range(0, len(body) - n, step):
            s = self._present(body[k])
            if s is not None:
                s.write(addr, bytes(body[k + 1 : k + 1 + n]))

    def _sync_read(self, params: bytes, p2: bool) -> None:
        if p2:
            addr, n, ids = params[0] | params[1] << 8, params[2] | params[3] << 8, params[4:]
        else:
            addr, n, ids = params[0], params[1], params[2:]
        for sid in ids:
            s = self._present(sid)
            if s is None:
                continue
            data, code = s.read(addr, n)
            self._reply(s, self._err(s, code), data)
