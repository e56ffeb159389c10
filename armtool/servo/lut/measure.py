"""Driving a servo for `servo-lut measure` and `check`: plan the points, approach each from one
side, wait until settled, read the reference, and stop at once when something pushes back.

Why one side: gears and the position loop leave a dead band, so the angle reached depends on
the direction of the last move (hysteresis). Approaching every point from below (or above)
measures one consistent curve; `both` measures the two and the fit reports their gap.
Why inside recorded limits only: the range comes from `armtool limits` (or --min/--max), never
from pushing a stop, and a point the servo cannot reach (stall: no motion with the load near the
torque limit, checked at every poll so it ends well before the overload alarm, or the alarm
itself) ends the run with torque off instead of being logged as a measurement.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from armtool.errors import ArmtoolError
from armtool.servo.bus import ServoBus
from armtool.servo.guard import TorqueGuard
from armtool.servo.lut.choices import MeasureApproach, Side
from armtool.servo.lut.csv_format import Sample
from armtool.servo.lut.table import LutTable, nominal_command_ticks
from armtool.servo.models import ServoModel
from armtool.servo.motion import Arrival, Outcome, Settle, move_and_settle
from armtool.servo.reference import Reference

log = logging.getLogger(__name__)

ApproachMode = MeasureApproach | Literal["up", "down", "both"]  # the enum, or its value
TELEMETRY = ("present_position", "present_load", "present_voltage", "present_temperature", "moving")


@dataclass(frozen=True)
class Motion:
    """How to move and when a point counts as reached."""

    backoff_ticks: int = 10
    settle_timeout_s: float = 3.0
    dwell_s: float = 0.15
    poll_s: float = 0.005
    tolerance_ticks: int = 2  # present within this of the goal counts as arrived
    torque_cap: float = 1.0  # the RAM torque limit set, as a fraction of full output
    stall_load: float = 0.7  # |load| at this fraction of the torque limit ...
    stall_window_s: float = 0.15  # ... with no motion over this window, short of the goal = pushing something
    stall_ticks: int = 1

    def settle(self) -> Settle:
        """A point is reached when Moving = 0 and the position holds, within `tolerance_ticks`."""
        return Settle(
            timeout_s=self.settle_timeout_s,
            tolerance_ticks=self.tolerance_ticks,
            arrival=Arrival.STOPPED,
            poll_s=self.poll_s,
            torque_cap=self.torque_cap,
            stall_load=self.stall_load,
            stall_window_s=self.stall_window_s,
            stall_ticks=self.stall_ticks,
            window_from_command=True,
            telemetry=TELEMETRY,
        )


def read_limits(path: Path, sid: int) -> tuple[int, int, str | None]:
    """(safe_min_ticks, safe_max_ticks, model) for `sid` from an `armtool limits` YAML file."""
    from armtool.fileio import read_yaml

    doc = read_yaml(path, "limits")
    joints = doc.get("joints") if isinstance(doc, dict) else None
    if not isinstance(joints, list):
        raise ArmtoolError("no 'joints' list", str(path), hint="write one with `armtool limits -o limits.yaml`")
    for k, joint in enumerate(joints):
        if isinstance(joint, dict) and joint.get("id") == sid:
            where = f"{path}: joints[{k}]"
            values = []
            for key in ("safe_min_ticks", "safe_max_ticks"):
                value = joint.get(key)
                if not isinstance(value, (int, float)) or isinstance(value, bool):
                    raise ArmtoolError(f"'{key}' is missing or not a number", where)
                if not (math.isfinite(value) and float(value).is_integer() and 0 <= value <= 4095):
                    raise ArmtoolError(f"'{key}' must be a whole number of ticks 0..4095, got {value!r}", where)
                values.append(int(value))
            if values[0] >= values[1]:
                raise ArmtoolError(f"safe_min_ticks {values[0]} is not below safe_max_ticks {values[1]}", where)
            model = joint.get("model")
            return values[0], values[1], str(model) if model is not None else None
    ids = [j.get("id") for j in joints if isinstance(j, dict)]
    raise ArmtoolError(f"ID {sid} is not in the limits file", str(path), hint=f"IDs there: {ids}")


def plan_commands(
    lo: int, hi: int, approach: ApproachMode, backoff: int, points: int | None = None, step: int | None = None
) -> list[int]:
    """Commands to measure, inside [lo, hi] with room to approach from the chosen side(s)."""
    if backoff < 0:
        raise ArmtoolError(f"--backoff must be at least 0 ticks, got {backoff}")
    first = lo + (backoff if approach in ("up", "both") else 0)
    last = hi - (backoff if approach in ("down", "both") else 0)
    if last - first < 3:
        raise ArmtoolError(
            f"the range {lo}..{hi} ticks leaves no room to measure with a back-off of {backoff} ticks",
            hint="widen --min/--max (inside the recorded limits) or lower --backoff",
        )
    if step is not None:
        if step < 1:
            raise ArmtoolError(f"--step must be at least 1 tick, got {step}")
        commands = list(range(first, last + 1, step))
    else:
        n = points if points is not None else 32
        if n < 2:
            raise ArmtoolError(f"--points must be at least 2, got {n}")
        commands = sorted({int(round(v)) for v in np.linspace(first, last, min(n, last - first + 1))})
    assert_in_range(commands, lo, hi)
    return commands


def assert_in_range(commands: list[int], lo: int, hi: int) -> None:
    """Refuse any command outside the range the user gave (the motion layer's own guard)."""
    outside = [c for c in commands if not lo <= c <= hi]
    if outside:
        raise ArmtoolError(
            f"refusing to command {outside[:5]}: outside the range {lo}..{hi} ticks",
            hint="check the command range (--min/--max or the limits file) and the back-off",
        )


@dataclass
class Driver:
    """One servo on a guarded bus, moved point by point."""

    bus: ServoBus
    guard: TorqueGuard
    sid: int
    motion: Motion = field(default_factory=Motion)
    sleep: Callable[[float], None] = time.sleep
    last_goal: int | None = None
    bounds: tuple[int, int] | None = None  # (lo, hi): no goal outside it is ever written

    def _telemetry(self) -> dict[str, int]:
        return dict(self.bus.read_many(self.sid, TELEMETRY))

    def goto(self, goal: int) -> tuple[bool, dict[str, int]]:
        """Command `goal` and wait until the servo has settled there; (settled, telemetry)."""
        m = self.motion
        if self.bounds is not None:
            assert_in_range([int(goal)], *self.bounds)
        self.last_goal = int(goal)
        moved = move_and_settle(self.bus, self.sid, goal, m.settle(), sleep=self.sleep)
        here = moved.position
        if moved.outcome is Outcome.OVERLOAD:
            raise ArmtoolError(
                f"ID {self.sid} raised its overload alarm going to {goal} (present {here})",
                hint="something blocks the joint inside the range: re-record the limits "
                "(armtool limits) and measure inside them",
            )
        if moved.outcome is Outcome.STALLED:
            raise ArmtoolError(
                f"ID {self.sid} stopped at {here} short of {goal} with {moved.load:.0%} of its torque "
                "limit: pushing against something",
                hint="measure inside the recorded limits (--limits limits.yaml) or re-record them",
            )
        if moved.outcome is Outcome.TIMEOUT:
            log.warning(
                "ID %d did not settle at %d within %.1f s (present %d)", self.sid, goal, m.settle_timeout_s, here
            )
            return False, dict(moved.telemetry)
        if m.dwell_s > 0:
            self.sleep(m.dwell_s)
            return True, self._telemetry()
        return True, dict(moved.telemetry)

    def approach(self, goal: int, side: Side, lo: int, hi: int) -> tuple[bool, dict[str, int]]:
        """Reach `goal` moving up (`side` = "up") or down, backing off first when needed."""
        b = self.motion.backoff_ticks
        last = self.last_goal
        if side == "up" and (last is None or last > goal - b):
            self.goto(max(lo, goal - b))
        elif side == "down" and (last is None or last < goal + b):
            self.goto(min(hi, goal + b))
        return self.goto(goal)


def align_reference(driver: Driver, reference: Reference, lo: int, hi: int, side: Side) -> str | None:
    """Put a frame-less reference (a camera) into the servo's frame: read it at two commands
    either side of the middle of the range; the sense of turning gives the sign, the second
    reading is set to the datasheet angle there (the middle is where a potentiometer is most
    linear). Returns a note for the CSV metadata, or None for references that need no alignment."""
    raw = getattr(reference, "raw_deg", None)
    align = getattr(reference, "align", None)
    if raw is None or align is None:
        return None
    model = driver.bus.model(driver.sid)
    k = max(2, min((hi - lo) // 4, round(10.0 / model.deg_per_tick)))
    c1, c2 = (lo + hi) // 2 - k, (lo + hi) // 2 + k
    driver.approach(c1, side, lo, hi)
    a1 = float(raw())
    driver.approach(c2, side, lo, hi)
    a2 = float(raw())
    expected = (c2 - c1) * model.deg_per_tick
    if not 0.5 * expected <= abs(a2 - a1) <= 2.0 * expected:
        raise ArmtoolError(
            f"{reference.spec} saw {abs(a2 - a1):.2f}° for a move of about {expected:.2f}°",
            hint="is the tag fixed flat on the horn? Without camera intrinsics the camera must look "
            "along the servo axis (camera:DEV,intrinsics=cam.yaml relaxes that)",
        )
    sign = 1.0 if a2 > a1 else -1.0
    offset = c2 * model.deg_per_tick - sign * a2
    align(sign, offset)
    return f"sign {sign:+.0f}, offset {offset:.3f} deg, datasheet angle at tick {c2}"


def _sample(
    command: int, reading: float, tel: dict[str, int], side: Side, repeat: int, settled: bool, load_full: int = 1000
) -> Sample:
    return Sample(
        line=0,
        command_ticks=command,
        reference_deg=reading,
        present_ticks=float(tel["present_position"]),
        load_pct=round(100.0 * tel["present_load"] / load_full, 2),
        temperature_c=float(tel["present_temperature"]),
        voltage_v=tel["present_voltage"] / 10.0,
        approach=side,
        repeat=repeat,
        settled=settled,
    )


def measure(
    driver: Driver,
    reference: Reference,
    commands: list[int],
    approach: ApproachMode,
    lo: int,
    hi: int,
    reads: int = 3,
    sweeps: int = 1,
    on_sample: Callable[[Sample], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> list[Sample]:
    """Step through `commands` (sweeps x sides), reading the reference `reads` times per point."""
    sides: list[Side] = ["up", "down"] if approach == "both" else ["down" if approach == "down" else "up"]
    samples: list[Sample] = []
    total = len(commands) * len(sides) * sweeps
    done = 0
    full = driver.bus.model(driver.sid).load_full_scale
    for sweep in range(sweeps):
        for side in sides:
            order = commands if side == "up" else list(reversed(commands))
            for command in order:
                settled, tel = driver.approach(command, side, lo, hi)
                for r in range(reads):
                    s = _sample(
                        command, reference.read_deg(driver.sid, command), tel, side, sweep * reads + r, settled, full
                    )
                    samples.append(s)
                    if on_sample is not None:
                        on_sample(s)
                done += 1
                if progress is not None:
                    progress(done, total)
    return samples


# --------------------------------------------------------------------------------------------
# check


@dataclass(frozen=True)
class CheckPoint:
    angle_deg: float
    lut_command: int
    lut_measured_deg: float
    nominal_command: int
    nominal_measured_deg: float

    @property
    def lut_error_deg(self) -> float:
        return self.lut_measured_deg - self.angle_deg

    @property
    def nominal_error_deg(self) -> float:
        return self.nominal_measured_deg - self.angle_deg


@dataclass(frozen=True)
class CheckResult:
    points: tuple[CheckPoint, ...]

    @staticmethod
    def _stats(errors: list[float]) -> dict[str, float]:
        e = np.asarray(errors)
        return {"rms_deg": float(np.sqrt(np.mean(e**2))), "max_deg": float(np.max(np.abs(e)))}

    @property
    def lut(self) -> dict[str, float]:
        return self._stats([p.lut_error_deg for p in self.points])

    @property
    def nominal(self) -> dict[str, float]:
        return self._stats([p.nominal_error_deg for p in self.points])

    def to_dict(self) -> dict[str, Any]:
        return {
            "schema_version": 1,
            "nominal": self.nominal,
            "lut": self.lut,
            "points": [
                {
                    "angle_deg": p.angle_deg,
                    "lut_command_ticks": p.lut_command,
                    "lut_measured_deg": p.lut_measured_deg,
                    "lut_error_deg": p.lut_error_deg,
                    "nominal_command_ticks": p.nominal_command,
                    "nominal_measured_deg": p.nominal_measured_deg,
                    "nominal_error_deg": p.nominal_error_deg,
                }
                for p in self.points
            ],
        }

    def text(self) -> str:
        """The plain-text report: RMS and largest error through the nominal map and the table."""
        nominal, lut = self.nominal, self.lut
        return "\n".join(
            [
                f"{'':8} {'RMS (°)':>8} {'max (°)':>8}",
                f"{'nominal':8} {nominal['rms_deg']:8.3f} {nominal['max_deg']:8.3f}",
                f"{'table':8} {lut['rms_deg']:8.3f} {lut['max_deg']:8.3f}",
                f"({len(self.points)} random angles, not knots; error = measured - wanted)",
            ]
        )


def check_angles(table: LutTable, n: int, seed: int, lo: int, hi: int) -> list[float]:
    """`n` random angles inside the table's range whose table and nominal commands both lie in
    [lo, hi], each at least a quarter of the knot spacing away from every knot."""
    if n < 1:
        raise ArmtoolError(f"--n must be at least 1, got {n}")
    knots = np.asarray(table.knots_deg)
    gap = 0.25 * float(np.min(np.diff(knots))) if knots.size > 1 else 0.0
    a_lo, a_hi = table.valid_range_deg
    rng = np.random.default_rng(seed)
    chosen: list[float] = []
    for _ in range(200 * n):
        a = float(rng.uniform(a_lo, a_hi))
        if np.min(np.abs(knots - a)) < gap:
            continue
        c_lut = int(table.command_ticks([a])[0])
        c_nom = int(nominal_command_ticks(table.model, np.array([a]))[0])
        if lo <= c_lut <= hi and lo <= c_nom <= hi:
            chosen.append(round(a, 3))
        if len(chosen) == n:
            return chosen
    raise ArmtoolError(
        f"could not place {n} check angles inside {lo}..{hi} ticks away from the table's knots",
        hint="check a servo whose limits cover the table's range, or lower --n",
    )


def check(
    driver: Driver,
    reference: Reference,
    table: LutTable,
    angles: list[float],
    lo: int,
    hi: int,
    reads: int = 3,
    progress: Callable[[int, int], None] | None = None,
) -> CheckResult:
    """Command each angle through the table and through the nominal map; measure both."""
    side: Side = "down" if table.approach == "down" else "up"
    points = []
    # in travel order: short moves, and every point still approached from `side` (back-off)
    for k, angle in enumerate(sorted(angles, reverse=side == "down")):
        measured = []
        commands = (int(table.command_ticks([angle])[0]), int(nominal_command_ticks(table.model, np.array([angle]))[0]))
        for command in commands:
            driver.approach(command, side, lo, hi)
            measured.append(float(np.mean([reference.read_deg(driver.sid, command) for _ in range(reads)])))
        points.append(CheckPoint(angle, commands[0], measured[0], commands[1], measured[1]))
        if progress is not None:
            progress(k + 1, len(angles))
    return CheckResult(tuple(points))


def speed_register(model: ServoModel, deg_per_s: float) -> int:
    """The moving-speed register value nearest `deg_per_s` (`ServoModel.speed_register`), checked > 0."""
    if not deg_per_s > 0:
        raise ArmtoolError(f"--speed must be > 0 degrees per second, got {deg_per_s:g}")
    return model.speed_register(deg_per_s)


def torque_register(model: ServoModel, percent: float) -> int:
    """The RAM torque-limit register value for `percent` of the maximum."""
    if not 0 < percent <= 100:
        raise ArmtoolError(f"--torque-limit must be in (0, 100] percent, got {percent:g}")
    reg = model.reg("torque_limit")
    value = int(round(reg.hi * percent / 100.0))
    if value < 1:
        raise ArmtoolError(
            f"--torque-limit {percent:g}% is less than one step of the {model.name}'s torque limit "
            f"register (1/{reg.hi} = {100.0 / reg.hi:.3f}%): the servo would not move",
            hint="the default is 50%; a few percent is the least that moves a horn",
        )
    return value
