"""Manual mode: torque off, a person moves each joint to both ends; the recorder samples positions
and unwraps 4096-tick seam crossings."""

from __future__ import annotations

import math
import time

from armtool.errors import ArmtoolError
from armtool.servo.bus import ServoBus
from armtool.servo.limits.arm_file import Joint, JointRange


class ManualRecorder:
    """Samples present positions with torque off; unwraps 4096-tick seam crossings."""

    def __init__(
        self,
        bus: ServoBus,
        joints: list[Joint],
        settle_ticks: int = 2,
        min_dwell_s: float = 0.3,
        max_silence_s: float = 1.0,
    ) -> None:
        self.bus = bus
        self.joints = joints
        self.settle_ticks = settle_ticks
        self.min_dwell_s = min_dwell_s
        self.max_silence_s = max_silence_s
        self.traces: dict[int, list[tuple[float, int]]] = {j.id: [] for j in joints}
        self.present: dict[int, int] = {}
        self.missed: dict[int, int] = {j.id: 0 for j in joints}
        self._t0 = time.monotonic()
        self._last_reply: dict[int, float] = {j.id: 0.0 for j in joints}

    def sample(self) -> None:
        """One reading per joint. A person records for minutes: a reply lost now and then (noise,
        a loaded machine) skips that joint until the next sample; only an ID silent for more than
        `max_silence_s` ends the session. A lost port ends it at once."""
        from armtool.servo.transport import CommError

        t = time.monotonic() - self._t0
        for j in self.joints:
            try:
                raw = self.bus.read(j.id, "present_position")
            except CommError as exc:
                self.missed[j.id] += 1
                silent = t - self._last_reply[j.id]
                if silent > self.max_silence_s:
                    raise ArmtoolError(
                        f"ID {j.id} ('{j.name}') has not answered for {silent:.1f} s: {exc.what}",
                        hint="check the cable and power of that servo",
                    ) from None
                continue
            self._last_reply[j.id] = t
            model = self.bus.model(j.id)
            trace = self.traces[j.id]
            if model.wraps and trace:
                last = trace[-1][1]
                delta = (raw - last) % model.ticks
                if delta > model.ticks // 2:
                    delta -= model.ticks
                value = last + delta
            else:
                value = raw
            trace.append((t, value))
            self.present[j.id] = raw

    def extent(self, sid: int) -> tuple[int, int] | None:
        trace = self.traces[sid]
        if not trace:
            return None
        values = [v for _, v in trace]
        return min(values), max(values)

    def _dwell(self, trace: list[tuple[float, int]], extreme: int) -> float:
        best = 0.0
        start: float | None = None
        for t, v in trace:
            if abs(v - extreme) <= self.settle_ticks:
                start = t if start is None else start
                best = max(best, t - start)
            else:
                start = None
        return best

    def results(self) -> list[JointRange]:
        out: list[JointRange] = []
        for j in self.joints:
            model = self.bus.model(j.id)
            trace = self.traces[j.id]
            if len(trace) < 2:
                raise ArmtoolError(f"joint '{j.name}' (ID {j.id}): no samples were recorded")
            lo, hi = self.extent(j.id)  # type: ignore[misc]
            if lo == hi:
                raise ArmtoolError(
                    f"joint '{j.name}' (ID {j.id}) did not move (always {lo} ticks)",
                    hint="move every joint to both ends before pressing Enter",
                )
            shift = 0
            if model.wraps and lo < 0:
                shift = model.ticks * math.ceil(-lo / model.ticks)
            dmin, dmax = self._dwell(trace, lo), self._dwell(trace, hi)
            out.append(
                JointRange(
                    j,
                    model,
                    lo + shift,
                    hi + shift,
                    "manual",
                    {
                        "confirmed_min": dmin >= self.min_dwell_s,
                        "confirmed_max": dmax >= self.min_dwell_s,
                        "dwell_min_s": round(dmin, 3),
                        "dwell_max_s": round(dmax, 3),
                        "samples": len(trace),
                    },
                )
            )
        return out
