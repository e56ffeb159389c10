"""The safety guard every command that can energise a servo runs inside.

    with TorqueGuard(bus) as guard:
        guard.set_ram(1, "torque_limit", 300)    # remembered, restored on exit
        guard.torque_on(1)                       # goal := present first, so nothing jumps
        ...

On leaving the block for any reason (normal exit, exception, Ctrl-C, SIGTERM) every touched ID
whose torque is on first gets goal := present (a stale goal makes the next tool that turns torque
on drive the joint into its stop; lerobot PR #3913), then Torque Enable = 0 (retried), then the RAM
settings changed through the guard are restored. Each ID is handled on its own: a servo that does
not answer, or a port that is gone, does not stop the others from being tried. SIGINT/SIGTERM are
blocked and deferred while that runs so a second Ctrl-C cannot cut it short. IDs whose torque-off
was not confirmed are always reported (TorqueOffFailed), also when another error is in flight:
the person must switch the power off. The goal is never written after torque off: on STS (and
maybe AX) a goal write turns torque back on.
"""

from __future__ import annotations

import logging
import signal
import threading
import time
from collections.abc import Callable
from types import FrameType, TracebackType
from typing import Any

from armtool.errors import ArmtoolError
from armtool.servo.bus import ServoBus

Handler = Callable[[int, FrameType | None], Any] | int | None  # what signal.getsignal returns

log = logging.getLogger(__name__)

_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread like Ctrl-C so that cleanup runs the same way."""

    exit_code = 128 + signal.SIGTERM  # 143, as shells report a process ended by SIGTERM


class TorqueOffFailed(ArmtoolError):
    """Torque-off was not confirmed on some IDs: they may still be energised."""

    def __init__(self, ids: list[int], after: BaseException | None = None) -> None:
        what = f"could not confirm torque off on ID {', '.join(map(str, ids))}: it may still be energised"
        if after is not None:
            first = (getattr(after, "what", None) or str(after) or type(after).__name__).splitlines()[0]
            what += f" (after: {first})"
        hint = "switch the servo power off before touching the arm"
        other = getattr(after, "hint", None)
        if other:
            hint += f"; {other}"
        super().__init__(what, None, hint)
        self.ids = ids
        self.after = after


def _block_signals() -> None:
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_BLOCK, _SIGNALS)


def _unblock_signals() -> None:
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, _SIGNALS)


class TorqueGuard:
    def __init__(self, bus: ServoBus, off_retries: int = 5) -> None:
        self.bus = bus
        self.off_retries = off_retries
        self.touched: set[int] = set()
        self.saved: dict[tuple[int, str], int] = {}
        self.failed_off: list[int] = []
        self._old_term: Handler = None
        self._old_int: Handler = None
        self._late: BaseException | None = None
        self._in_main = False
        self._deferred: list[int] = []

    def __enter__(self) -> TorqueGuard:
        if threading.current_thread() is threading.main_thread():
            self._old_int = signal.getsignal(signal.SIGINT)
            self._old_term = signal.signal(signal.SIGTERM, self._on_term)
        return self

    @staticmethod
    def _on_term(signum: int, frame: FrameType | None) -> None:
        raise Terminated()

    def _defer(self, signum: int, frame: FrameType | None) -> None:
        self._deferred.append(signum)

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
        """Goal := present (what the servo reads now); returns it. Refuses when the reading lies
        outside the goal register's range (e.g. an X servo with a homing offset): a clamped goal
        would not be where the joint is, and it would jump there."""
        present = self.bus.read(sid, "present_position")
        model = self.bus.model(sid)
        reg = model.reg("goal_position")
        if (reg.lo, reg.hi) != (0, 0) and not reg.lo <= present <= reg.hi:
            raise ArmtoolError(
                f"ID {sid} reads position {present}, outside the goal range {reg.lo}..{reg.hi} of a "
                f"{model.name}: holding it there is impossible, torque on would make the joint jump",
                hint="clear the homing offset (or move the joint into the range by hand) and retry",
            )
        self.touched.add(sid)
        self.bus.write(sid, "goal_position", present, retry=True)
        return present

    def torque_on(self, sid: int) -> None:
        self.touched.add(sid)
        self.hold_here(sid)
        self.bus.write(sid, "torque_enable", 1, retry=True)

    def torque_off(self, sid: int) -> bool:
        """Torque Enable = 0 with retries; True when the servo confirmed it. Never raises."""
        for _ in range(self.off_retries):
            try:
                self.bus.write(sid, "torque_enable", 0, retry=True)
                if self.bus.read(sid, "torque_enable") == 0:
                    return True
            except Exception as exc:
                log.debug("torque off ID %d: %s", sid, exc)
            time.sleep(0.005)
        return False

    def _settle_goal(self, sid: int) -> None:
        """Before torque off: goal := present on a servo whose torque is on (best effort)."""
        try:
            if self.bus.read(sid, "torque_enable") != 0:
                self.hold_here(sid)
        except Exception as exc:
            log.debug("goal := present on ID %d before torque off: %s", sid, exc)

    def release(self) -> None:
        """Per touched ID: goal := present, torque off; then restore saved RAM settings (every ID
        tried, whatever the others did). IDs not confirmed off end up in `failed_off`."""
        self.failed_off = []
        for sid in sorted(self.touched):
            self._settle_goal(sid)
            if not self.torque_off(sid):
                self.failed_off.append(sid)
        for (sid, name), value in self.saved.items():
            try:
                self.bus.write(sid, name, value, retry=True)
            except Exception as exc:
                log.warning("could not restore ID %d %s = %d: %s", sid, name, value, exc)
        self.saved.clear()

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        while True:
            try:  # first statement: from here on a Ctrl-C/SIGTERM waits until the servos are safe
                _block_signals()
                self._in_main = threading.current_thread() is threading.main_thread()
                if self._in_main:  # a signal that came just before the mask still runs its handler: defer it
                    signal.signal(signal.SIGINT, self._defer)
                    signal.signal(signal.SIGTERM, self._defer)
                break
            except KeyboardInterrupt as interrupt:  # it landed before the handlers were swapped: clean up first
                self._late = self._late or interrupt
        late, in_main = self._late, self._in_main
        try:
            self.release()
        finally:
            _unblock_signals()  # signals held back by the mask now reach the deferring handlers
            if in_main:
                signal.signal(signal.SIGINT, self._old_int if self._old_int is not None else signal.default_int_handler)
                signal.signal(signal.SIGTERM, self._old_term if self._old_term is not None else signal.SIG_DFL)
        if self.failed_off:
            raise TorqueOffFailed(self.failed_off, exc if exc is not None else late)
        if exc_type is None and late is None and self._deferred:
            late = Terminated() if self._deferred[0] == signal.SIGTERM else KeyboardInterrupt()
        if exc_type is None and late is not None:
            raise late
