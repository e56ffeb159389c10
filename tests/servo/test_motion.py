"""Stall detection and move_and_settle, shared by limits' seek and servo-lut's Driver.goto."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import pytest

from armtool.servo.models import ServoModel, by_name
from armtool.servo.motion import Arrival, Outcome, Settle, StallDetector, load_fraction, move_and_settle


def test_still_only_after_a_full_window_without_motion() -> None:
    d = StallDetector(window_s=0.1, ticks=1)
    assert not d.add(0.00, 500)  # one sample is no window
    assert not d.add(0.05, 500)
    assert d.add(0.10, 501)  # a full window spanning 1 tick
    assert not d.add(0.12, 505)  # moved 5 ticks inside the window
    assert not d.add(0.20, 505)  # 501 (at 0.10) is still inside the window 0.10..0.20
    assert d.add(0.23, 505)  # window 0.13..0.23 holds only 505


def test_start_counts_the_window_from_the_command_not_the_first_sample() -> None:
    d = StallDetector(window_s=0.1, ticks=0, start=0.0)
    assert d.add(0.1, 7)  # the first sample, but the window since the command has passed
    assert not StallDetector(window_s=0.1, ticks=0).add(0.1, 7)


def test_load_fraction_is_of_the_torque_limit_set() -> None:
    ax, xm = by_name("AX-12A"), by_name("XM430-W350")
    assert load_fraction(ax, -1023, 1.0) == pytest.approx(1.0)
    assert load_fraction(ax, 307, 0.3) == pytest.approx(307 / 1023 / 0.3)
    assert load_fraction(xm, 1193 // 2, 0.5) == pytest.approx(1.0, abs=1e-3)


class FakeBus:
    """One AX-12A whose position walks toward the goal `step` ticks per read, stopped by a wall."""

    def __init__(self, start: int = 500, step: int = 20, wall: int | None = None, wall_load: int = 0) -> None:
        self.pos, self.goal, self.step, self.wall, self.wall_load = start, start, step, wall, wall_load
        self.alarm_after: int | None = None
        self.reads = 0

    def model(self, sid: int) -> ServoModel:
        return by_name("AX-12A")

    def write(self, sid: int, name: str, value: int, *, retry: bool = False) -> None:
        assert name == "goal_position"
        self.goal = value

    def read_many(self, sid: int, names: Iterable[str]) -> dict[str, int]:
        self.reads += 1
        delta = max(-self.step, min(self.step, self.goal - self.pos))
        pushing = self.wall is not None and (self.pos + delta - self.wall) * (self.goal - self.wall) > 0
        self.pos = self.wall if pushing and self.wall is not None else self.pos + delta
        blocked = pushing or (self.wall is not None and self.pos == self.wall and self.goal != self.wall)
        values = {
            "present_position": self.pos,
            "present_load": self.wall_load if blocked or self.pos == self.wall else 40,
            "moving": int(self.pos != self.goal or blocked),
        }
        return {n: values.get(n, 0) for n in names}

    def overload_alarm(self, sid: int) -> bool:
        return self.alarm_after is not None and self.reads >= self.alarm_after


FAST: dict[str, Any] = {"poll_s": 0.001, "stall_window_s": 0.02}


def test_a_free_move_settles_when_stopped_at_the_goal() -> None:
    bus = FakeBus()
    moved = move_and_settle(bus, 1, 600, Settle(timeout_s=2.0, tolerance_ticks=2, **FAST), sleep=_no_sleep)
    assert moved.outcome is Outcome.SETTLED and moved.position == 600
    assert bus.reads == 6  # 5 reads of 20-tick steps reach it, one more sees it hold


def test_a_wall_short_of_the_goal_is_a_stall_only_with_high_load() -> None:
    settle = Settle(timeout_s=0.5, tolerance_ticks=2, **FAST)
    moved = move_and_settle(FakeBus(wall=560, wall_load=900), 1, 600, settle)
    assert moved.outcome is Outcome.STALLED and moved.position == 560 and moved.load > 0.7
    soft = move_and_settle(FakeBus(wall=560, wall_load=100), 1, 600, settle)
    assert soft.outcome is Outcome.TIMEOUT and soft.position == 560  # not pushing: no stall


def test_still_arrival_reports_the_load_of_a_stop_at_the_goal() -> None:
    """limits' seek: Moving stays 1 against a stop; still at the goal is arrival, load tells a stop."""
    settle = Settle(timeout_s=0.5, tolerance_ticks=2, arrival=Arrival.STILL, window_from_command=False, **FAST)
    moved = move_and_settle(FakeBus(wall=600, wall_load=900), 1, 600, settle)
    assert moved.outcome is Outcome.SETTLED and moved.load > 0.7
    stopped = Settle(timeout_s=0.2, tolerance_ticks=2, **FAST)
    assert move_and_settle(FakeBus(wall=600, wall_load=900), 1, 601, stopped).outcome is Outcome.TIMEOUT


def test_overload_alarm_and_near_arrival() -> None:
    bus = FakeBus()
    bus.alarm_after = 2
    moved = move_and_settle(bus, 1, 900, Settle(timeout_s=1.0, tolerance_ticks=2, **FAST))
    assert moved.outcome is Outcome.OVERLOAD and bus.reads == 2
    near = Settle(timeout_s=1.0, tolerance_ticks=2, arrival=Arrival.NEAR, stall_load=None, **FAST)
    bus = FakeBus()
    assert move_and_settle(bus, 1, 540, near).outcome is Outcome.SETTLED and bus.reads == 2


def _no_sleep(seconds: float) -> None:
    pass
