"""Stall detection shared by limits' seek and servo-lut's Driver.goto."""

from __future__ import annotations

import pytest

from armtool.servo.models import by_name
from armtool.servo.motion import StallDetector, load_fraction


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
