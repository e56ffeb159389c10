"""The safety guard every command that can energise a servo runs inside.

    with TorqueGuard(bus) as guard:
        guard.set_ram(1, "torque_limit", 300)    # remembered, restored on exit
        guard.torque_on(1)                       # goal := present first, so nothing jumps
        ...

On leaving the block for any reason (normal exit, exception, Ctrl-C, SIGTERM) every touched
ID gets Torque Enable = 0 (retried), then the RAM settings changed through the guard are
restored; SIGINT/SIGTERM are blocked while that runs so a second Ctrl-C cannot cut it short.
Stale goals make servos jump when torque comes on (lerobot PR #3913), hence goal := present.
"""

from __future__ import annotations

import logging
import signal
import threading
import time
from types import FrameType, TracebackType
from typing import Any

from armtool.errors import ArmtoolError
from armtool.servo.bus import ServoBus

log = logging.getLogger(__name__)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread like Ctrl-C so that cleanup runs the same way."""


class TorqueGuard:
    def __init__(self, bus: ServoBus, off_retries: int = 5) -> None:
        self.bus = bus
        self.off_retries = off_retries
        self.touched: set[int] = set()
        self.saved: dict[tuple[int, str], int] = {}
        self.failed_off: list[int] = []
        self._old_term: Any = None

    def __enter__(self) -> TorqueGuard:
        if threading.current_thread() is threading.main_thread():
            self._old_term = signal.signal(signal.SIGTERM, self._on_term)
        return self

    @staticmethod
    def _on_term(signum: int, frame: FrameType | None) -> None:
        raise Terminated()

    def touch(self, sid: int) -> None:
        self.touched.add(sid)

    def set_ram(self, sid: int, name: str, value: int) -> None:
        """Write a RAM register, remembering its value from before the first change."""
        model = self.bus.model(sid)
        if model.reg(name).eeprom:
            raise ArmtoolError(f"{name} is an EEPROM register; use eeprom.write_eeprom")
        self.touched.add(sid)
        if (sid, name) not in self.saved:
            self.saved[(sid, name)] = self.bus.read(sid, name)
        self.bus.write(sid, name, value, retry=True)

    def hold_here(self, sid: int) -> int:
        """Goal := present (what the servo reads now); returns it."""
        present = self.bus.read(sid, "present_position")
        model = self.bus.model(sid)
        reg = model.reg("goal_position")
        goal = min(max(present, reg.lo), reg.hi) if (reg.lo, reg.hi) != (0, 0) else present
        self.touched.add(sid)
        self.bus.write(sid, "goal_position", goal, retry=True)
        return goal

    def torque_on(self, sid: int) -> None:
        self.touched.add(sid)
        self.hold_here(sid)
        self.bus.write(sid, "torque_enable", 1, retry=True)

    def torque_off(self, sid: int) -> bool:
        """Torque Enable = 0 with retries; True when the servo confirmed it."""
        for _ in range(self.off_retries):
            try:
                self.bus.write(sid, "torque_enable", 0, retry=True)
                if self.bus.read(sid, "torque_enable") == 0:
                    return True
            except ArmtoolError as exc:  # a servo in overload may refuse; keep trying
                log.debug("torque off ID %d: %s", sid, exc)
            time.sleep(0.005)
        return False

    def release(self) -> None:
        """Torque off on every touched ID, then restore saved RAM settings (best effort, all IDs)."""
        self.failed_off = [sid for sid in sorted(self.touched) if not self.torque_off(sid)]
        for (sid, name), value in self.saved.items():
            try:
                self.bus.write(sid, name, value, retry=True)
            except ArmtoolError as exc:
                log.warning("could not restore ID %d %s = %d: %s", sid, name, value, exc)
        self.saved.clear()

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        in_main = threading.current_thread() is threading.main_thread()
        blocked = {signal.SIGINT, signal.SIGTERM}
        if in_main:
            signal.pthread_sigmask(signal.SIG_BLOCK, blocked)
        try:
            self.release()
        finally:
            if in_main:
                signal.signal(signal.SIGTERM, self._old_term if self._old_term is not None else signal.SIG_DFL)
                signal.pthread_sigmask(signal.SIG_UNBLOCK, blocked)
        if self.failed_off and exc_type is None:
            raise ArmtoolError(f"could not confirm torque off on ID {', '.join(map(str, self.failed_off))}",
                               hint="switch the servo power off before touching the arm")
