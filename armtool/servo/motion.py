"""Driving a servo to a goal and watching it, shared by every routine that moves one (limits'
seek to a stop and its back-off, servo-lut's `Driver.goto`): one definition of "arrived", of
"not moving", of "pushing hard" and of the overload alarm.

A joint is still when, over a full window, its position spans at most `ticks`; it pushes when
|present load| is at least `stall_load` of the torque limit that was set. Still and pushing,
short of its goal, it is stalled against something (a stop, a cable, a hand).
`move_and_settle` only reports what happened; the caller decides what an outcome means (a
stall is a found stop for limits, an obstacle for servo-lut) and, for an abort, raises inside
its `TorqueGuard` so torque goes off.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from enum import Enum
from typing import Protocol

from armtool.servo.models import ServoModel


class MotionBus(Protocol):
    """What moving one servo needs of a bus (`armtool.servo.bus.ServoBus` is one)."""

    def model(self, sid: int) -> ServoModel: ...

    def read_many(self, sid: int, names: Iterable[str]) -> dict[str, int]: ...

    def write(self, sid: int, name: str, value: int, *, retry: bool = False) -> None: ...

    def overload_alarm(self, sid: int) -> bool: ...


def load_fraction(model: ServoModel, present_load: int, torque_cap: float) -> float:
    """|present load| as a fraction of the torque limit set (`torque_cap`: fraction of full output)."""
    return abs(present_load) / model.load_full_scale / max(torque_cap, 1e-6)


class StallDetector:
    """Feed it (time, position) at every poll; `still` says the joint has not moved for a window."""

    def __init__(self, window_s: float, ticks: int, start: float | None = None) -> None:
        self.window_s = window_s
        self.ticks = ticks
        self.start = start  # None: the first sample's time
        self._history: deque[tuple[float, int]] = deque()

    def add(self, now: float, position: int) -> bool:
        """Record one sample; True when the joint has been still for a full window."""
        if self.start is None:
            self.start = now
        self._history.append((now, position))
        while self._history and self._history[0][0] < now - self.window_s:
            self._history.popleft()
        return self.still(now)

    def still(self, now: float) -> bool:
        if self.start is None or now - self.start < self.window_s or not self._history:
            return False
        positions = [p for _, p in self._history]
        return max(positions) - min(positions) <= self.ticks


class Arrival(str, Enum):
    """When a joint within the tolerance of its goal counts as arrived."""

    STOPPED = "stopped"  # Moving = 0 and the position unchanged (within 1 tick) since the last poll
    STILL = "still"  # no motion over the stall window (Moving stays 1 while pushing a stop)
    NEAR = "near"  # at the first poll within the tolerance


class Outcome(str, Enum):
    SETTLED = "settled"  # arrived within the tolerance (the load may still be high: a stop at the goal)
    STALLED = "stalled"  # still, short of the goal, pushing with at least `stall_load`
    OVERLOAD = "overload"  # the servo's overload alarm
    TIMEOUT = "timeout"  # none of those within `timeout_s`


@dataclass(frozen=True)
class Settle:
    """How to watch one move: when it has arrived, when it is stalled, how long to wait."""

    timeout_s: float
    tolerance_ticks: int  # present within this of the goal counts as there (ServoModel.settle_ticks)
    arrival: Arrival = Arrival.STOPPED
    poll_s: float = 0.005
    torque_cap: float = 1.0  # the RAM torque limit set, as a fraction of full output
    stall_load: float | None = 0.7  # |load| at this fraction of the torque limit ... (None: no stall check)
    stall_window_s: float = 0.15  # ... with no motion over this window = pushing something
    stall_ticks: int = 1
    window_from_command: bool = True  # the stall window counts from the command (else from the first poll)
    telemetry: tuple[str, ...] = ()  # more registers to read at every poll (returned with the outcome)


@dataclass(frozen=True)
class MoveResult:
    outcome: Outcome
    position: int  # present position at the last poll
    load: float  # |load| as a fraction of the torque limit at the last poll
    max_load: float  # the largest of those during the move
    telemetry: Mapping[str, int]  # the registers read at the last poll


Poll = Callable[[int, float], None]  # (present position, load fraction) at every poll


def _registers(s: Settle) -> tuple[str, ...]:
    needed = ("present_position", "present_load") + (("moving",) if s.arrival is Arrival.STOPPED else ())
    return tuple(dict.fromkeys(s.telemetry + needed))


def move_and_settle(
    bus: MotionBus,
    sid: int,
    goal: int,
    settle: Settle,
    on_poll: Poll | None = None,
    sleep: Callable[[float], None] = time.sleep,
) -> MoveResult:
    """Command `goal`, then poll until the servo arrives, stalls, raises its overload alarm or
    the timeout passes; the outcome says which (nothing is raised, nothing switched off)."""
    s = settle
    model = bus.model(sid)
    registers = _registers(s)
    bus.write(sid, "goal_position", int(goal), retry=True)
    start = time.monotonic()
    stall = StallDetector(s.stall_window_s, s.stall_ticks, start=start if s.window_from_command else None)
    previous: int | None = None
    max_load = 0.0
    while True:
        tel = bus.read_many(sid, registers)
        now = time.monotonic()
        here = tel["present_position"]
        load = load_fraction(model, tel["present_load"], s.torque_cap)
        max_load = max(max_load, load)
        if on_poll is not None:
            on_poll(here, load)
        near = abs(here - goal) <= s.tolerance_ticks
        still = stall.add(now, here)
        outcome: Outcome | None = None
        if bus.overload_alarm(sid):
            outcome = Outcome.OVERLOAD
        elif near and (
            s.arrival is Arrival.NEAR
            or (s.arrival is Arrival.STILL and still)
            or (
                s.arrival is Arrival.STOPPED
                and tel["moving"] == 0
                and previous is not None
                and abs(here - previous) <= 1
            )
        ):
            outcome = Outcome.SETTLED
        elif still and not near and s.stall_load is not None and load >= s.stall_load:
            outcome = Outcome.STALLED
        elif now - start > s.timeout_s:
            outcome = Outcome.TIMEOUT
        if outcome is not None:
            return MoveResult(outcome, here, load, max_load, tel)
        previous = here
        sleep(s.poll_s)
