"""Auto mode: a torque-limited seek to each mechanical stop.

Stall = the position moved at most `stall_ticks` over `stall_window_s` AND |load| >= `stall_load`
of the torque limit (`servo.motion`), or the overload alarm (research/servo.md 5.2). Moving = 0
alone is not used (it stays 1 while pushing a stop), nor load alone (STS load is a PWM duty).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

from armtool.errors import ArmtoolError
from armtool.servo.bus import ServoBus
from armtool.servo.guard import TorqueGuard
from armtool.servo.limits.arm_file import Joint, JointRange
from armtool.servo.models import ServoModel
from armtool.servo.motion import Arrival, MoveResult, Outcome, Settle, move_and_settle
from armtool.servo.registry import transport_class


@dataclass
class AutoParams:
    torque_limit: float = 0.30  # fraction of full torque/PWM
    speed_deg_s: float = 30.0
    stall_window_s: float = 0.12
    stall_ticks: int = 1
    stall_load: float = 0.70  # fraction of the torque limit
    back_off_deg: float = 3.0
    max_seek_s: float | None = None  # per direction; default range/speed*1.5 + 2 s
    first_dir: int = -1


def _full_torque(model: ServoModel) -> int:
    reg = model.reg("torque_limit")
    return reg.hi


Progress = Callable[[Joint, str, int, float], None]
RANGE_END = "servo range end"


def seek_joint(
    bus: ServoBus, guard: TorqueGuard, joint: Joint, p: AutoParams, progress: Progress | None = None
) -> JointRange:
    """Find both mechanical stops of one joint; leaves it holding just inside the last stop."""
    sid = joint.id
    model = bus.model(sid)
    mode = transport_class(model.protocol).position_mode
    if model.has("operating_mode") and mode is not None and bus.read(sid, "operating_mode") != mode:
        raise ArmtoolError(
            f"ID {sid} is not in position control mode (Operating Mode {mode})",
            hint=f"set Operating Mode to {mode} (e.g. in Dynamixel Wizard) before `armtool limits --mode auto`",
        )
    cap = max(1, round(p.torque_limit * _full_torque(model)))
    speed = model.speed_register(p.speed_deg_s)
    guard.set_ram(sid, "torque_limit", cap)
    guard.set_ram(sid, "moving_speed", speed)
    guard.torque_on(sid)
    lo_lim, hi_lim = bus.read(sid, "min_limit"), bus.read(sid, "max_limit")
    if lo_lim == hi_lim == 0:
        lo_lim, hi_lim = 0, model.max_tick
    span_deg = (hi_lim - lo_lim) * model.deg_per_tick
    max_seek = p.max_seek_s or span_deg / p.speed_deg_s * 1.5 + 2.0
    back_off = max(2, math.ceil(p.back_off_deg / model.deg_per_tick))
    seek = Settle(
        timeout_s=max_seek,
        tolerance_ticks=model.settle_ticks,
        arrival=Arrival.STILL,  # Moving stays 1 while pushing a stop: only the window tells
        torque_cap=cap / _full_torque(model),
        stall_load=p.stall_load,
        stall_window_s=p.stall_window_s,
        stall_ticks=p.stall_ticks,
        window_from_command=False,
    )
    back = Settle(timeout_s=2.0, tolerance_ticks=model.settle_ticks, arrival=Arrival.NEAR, poll_s=0.01, stall_load=None)
    ends: dict[int, tuple[int, str]] = {}
    max_load = 0.0
    for direction in (p.first_dir, -p.first_dir):
        label = "min" if direction < 0 else "max"
        target = lo_lim if direction < 0 else hi_lim
        on_poll = None if progress is None else partial(progress, joint, label)
        moved = move_and_settle(bus, sid, target, seek, on_poll)
        max_load = max(max_load, moved.max_load)
        if moved.outcome is Outcome.TIMEOUT:
            guard.hold_here(sid)
            raise ArmtoolError(
                f"joint '{joint.name}' (ID {sid}): no stop found toward {label} within {max_seek:.1f} s",
                hint="raise --max-seek or --speed, or check that the joint can move",
            )
        ends[direction] = (moved.position, _reason(moved, p.stall_load))
        held = guard.hold_here(sid)  # stop pushing at once
        if moved.outcome is Outcome.OVERLOAD:
            _rearm(bus, sid, model, cap)
        goal = held - direction * back_off
        goal = min(max(goal, lo_lim), hi_lim)
        move_and_settle(bus, sid, goal, back)  # best effort: the next seek starts from wherever it is
    (lo, rlo), (hi, rhi) = ends[-1], ends[1]
    # the servo's own range end is not a mechanical stop (no stop, or the seam): never confirmed,
    # so --write-eeprom refuses it (SO-101 wrist_roll recorded 0..604 with 0 being the seam)
    return JointRange(
        joint,
        model,
        lo,
        hi,
        "auto",
        {
            "confirmed_min": not rlo.startswith(RANGE_END),
            "confirmed_max": not rhi.startswith(RANGE_END),
            "reason_min": rlo,
            "reason_max": rhi,
            "torque_limit": cap,
            "torque_limit_percent": round(100 * p.torque_limit, 1),
            "speed": speed,
            "speed_deg_s": p.speed_deg_s,
            "max_load_fraction_of_limit": round(max_load, 3),
        },
    )


def _reason(moved: MoveResult, stall_load: float) -> str:
    """Why the seek ended: a stall (also one right at the servo's range end), the alarm, or the end."""
    if moved.outcome is Outcome.OVERLOAD:
        return "overload alarm"
    if moved.load >= stall_load:  # STALLED, or SETTLED at the range end while pushing a stop there
        return f"stall (|load| {moved.load:.0%} of limit)"
    return f"{RANGE_END} (no stop before it)"


def _rearm(bus: ServoBus, sid: int, model: ServoModel, cap: int) -> None:
    rearm = transport_class(model.protocol).rearm
    if rearm is not None:
        bus.write(sid, rearm, cap if rearm == "torque_limit" else 1, retry=True)
    else:
        raise ArmtoolError(
            f"ID {sid} reports an overload hardware error and turned its torque off",
            hint="lower --torque-limit; reboot the servo (power cycle) to clear the error",
        )
