"""A scripted person for manual-mode tests: moves every torque-off joint to both stops and back.

Each joint's hand goes from where the joint is to a little past the low stop, rests there
`dwell_s`, goes past the high stop, rests, then returns to the middle. The joint follows the
hand (only while its torque is off) and rests on each stop for about dwell_s + 2·overshoot/speed.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Protocol

from armtool.servo.sim.config import PersonSpec
from armtool.servo.sim.servo import SimServo


class Arm(Protocol):
    """What a person needs of the simulated bus (SimBus): its clock, its servos, and hands on them."""

    @property
    def servos(self) -> Mapping[int, SimServo]: ...

    def now(self) -> float: ...

    def servo(self, sid: int) -> SimServo: ...

    def true_angle_deg(self, sid: int) -> float: ...

    def set_hand(self, sid: int, fn: Callable[[float], float] | None) -> None: ...


def _path(waypoints: list[tuple[float, float]]) -> Callable[[float], float]:
    def hand(t: float) -> float:
        if t <= waypoints[0][0]:
            return waypoints[0][1]
        for (t0, p0), (t1, p1) in zip(waypoints, waypoints[1:]):
            if t <= t1:
                return p0 + (p1 - p0) * (t - t0) / (t1 - t0) if t1 > t0 else p1
        return waypoints[-1][1]

    return hand


class Person:
    def __init__(self, sim: Arm, spec: PersonSpec | None = None) -> None:
        self.sim = sim
        self.spec = spec or PersonSpec()
        self.done_at = 0.0  # sim time when every joint is back in the middle

    def start(self) -> Person:
        spec = self.spec
        t0 = self.sim.now() + spec.start_s
        ids = spec.ids if spec.ids is not None else sorted(self.sim.servos)
        for sid in ids:
            s = self.sim.servo(sid)
            lo, hi = s.spec.stop_lo_deg - spec.overshoot_deg, s.spec.stop_hi_deg + spec.overshoot_deg
            mid = 0.5 * (s.spec.stop_lo_deg + s.spec.stop_hi_deg)
            here = self.sim.true_angle_deg(sid)
            v = spec.speed_deg_s
            t1 = t0 + abs(here - lo) / v
            t2 = t1 + spec.dwell_s
            t3 = t2 + (hi - lo) / v
            t4 = t3 + spec.dwell_s
            t5 = t4 + abs(hi - mid) / v
            self.done_at = max(self.done_at, t5)
            self.sim.set_hand(sid, _path([(t0, here), (t1, lo), (t2, lo), (t3, hi), (t4, hi), (t5, mid)]))
        return self

    def remaining_s(self) -> float:
        return max(0.0, self.done_at - self.sim.now())
