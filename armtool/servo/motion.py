"""Stall detection shared by every routine that drives a servo and watches it (limits' seek,
servo-lut's `Driver.goto`): one definition of "not moving" and of "pushing hard".

A joint is still when, over a full window, its position spans at most `ticks`; it pushes when
|present load| is at least `stall_load` of the torque limit that was set. Still and pushing,
short of its goal, it is stalled against something (a stop, a cable, a hand).
"""

from __future__ import annotations

from collections import deque

from armtool.servo.models import ServoModel


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
