"""One simulated servo: its control table (model defaults, write checks, side effects) and a joint.

Joint model (research/servo.md 3.1; behaviours the manuals leave open are ASSUMPTIONS):
* the true angle `theta` (servo-frame degrees, nominal 0° at tick 0) moves toward the goal at the
  set speed and is clamped by mechanical stops inside the servo's range;
* the servo reports and regulates its potentiometer reading: on the AX-12A `pot(u) = u +
  A·[b(1−u) − b(u)]`, `b(x) = (x/w)e^(1−x/w)`, u = theta/300°, so near both ends the true
  angle differs from the reported one by up to A·300° (≈3° with A = 0.010);
* pushing against a stop, the load rises (40 ms lag) toward punch + error/slope, capped by the
  torque limit; after `overload_time_s` at the cap the overload alarm latches and, when the
  alarm-shutdown register selects overload, the output is cut (AX: Torque Limit := 0, re-armed by
  writing it; X: torque off + Hardware Error Status bit 5 until REBOOT; STS: torque off + Status bit 5);
* with torque off a "hand" function (the person driver) may move the joint, clamped by the stops;
* writing Goal Position turns torque on (STS measured; AX ASSUMPTION; X only with Drive Mode bit 3);
* Homing Offset (STS3215, X series) shifts what the servo reports and takes as a goal, modulo one
  turn: STS present = encoder - offset (feetech-cli measured), X present = encoder + offset; an X
  servo in Position Control Mode ignores an offset outside -1024..1024 (e-manual homing offset).
"""

from __future__ import annotations

import math
from collections.abc import Callable

from armtool.servo.models import Register, ServoModel, decode, encode
from armtool.servo.registry import transport_class
from armtool.servo.sim.config import ServoSpec

LOAD_TAU_S = 0.04
HAND_SPEED_DEG_S = 400.0
POT_WIDTH = 0.10

# error codes returned by write/read checks, mapped to each protocol's error byte by the bus
OK, E_RANGE, E_ANGLE, E_ACCESS, E_LENGTH, E_LIMIT, E_INSTRUCTION = 0, 1, 2, 3, 4, 5, 6


def _b(x: float) -> float:
    return (x / POT_WIDTH) * math.exp(1.0 - x / POT_WIDTH)


class SimServo:
    def __init__(
        self,
        spec: ServoSpec,
        overload_time_s: float = 1.0,
        return_delay: int | None = None,
        goal_enables_torque: bool = True,
    ) -> None:
        self.spec = spec
        self.id = spec.id
        self.model: ServoModel = spec.model
        self.proto = transport_class(self.model.protocol)  # the protocol's behaviour, as data
        self.overload_time_s = overload_time_s
        self.return_delay_override = return_delay
        self.goal_enables_torque = goal_enables_torque
        self.hand: Callable[[float], float] | None = None
        self.theta = spec.start_deg
        self.mem = bytearray(self.model.table_size)
        self.reset_table()
        if spec.homing_offset:
            self.set("homing_offset", spec.homing_offset)
        # What survives a power cycle. Feetech STS servos take EEPROM writes while Lock = 1 but
        # keep them in RAM only: they are lost at the next power-up (Feetech's memory table).
        self.flash = bytearray(self.mem)
        self.vel = 0.0
        self.load = 0.0
        self.at_cap_s = 0.0
        self.blocked = False
        self.overload = False
        self.overload_trips = 0
        self.max_load_frac = 0.0
        self.registered: tuple[int, bytes] | None = None
        self.theta_goal = self.theta
        self._sync_present()
        self.set("goal_position", self.get("present_position"))

    # -- control table
    def reset_table(self) -> None:
        self.mem[:] = bytes(len(self.mem))
        for _name, reg in self.model.table.items():
            self._put(reg, reg.default)
        self._put(self.model.reg("id"), self.id)
        if self.return_delay_override is not None:
            self._put(self.model.reg("return_delay"), self.return_delay_override)

    def _put(self, reg: Register, value: int) -> None:
        self.mem[reg.addr : reg.addr + reg.size] = encode(reg, value, self.model.big_endian)

    def get(self, name: str) -> int:
        reg = self.model.reg(name)
        return decode(reg, bytes(self.mem[reg.addr : reg.addr + reg.size]), self.model.big_endian)

    def set(self, name: str, value: int) -> None:
        self._put(self.model.reg(name), value)

    # -- angle <-> ticks
    @property
    def span_deg(self) -> float:
        return self.model.range_deg

    def ticks_of(self, theta: float) -> float:
        """Reported (potentiometer/encoder) position in fractional ticks for a true angle."""
        d = self.model.deg_per_tick
        a = self.spec.nonlinearity
        if a == 0.0:
            return theta / d
        u = theta / self.span_deg
        return (u + a * (_b(1.0 - u) - _b(u))) * self.span_deg / d

    def theta_of(self, ticks: float) -> float:
        """Inverse of ticks_of (monotone), by bisection over the servo's range."""
        d = self.model.deg_per_tick
        if self.spec.nonlinearity == 0.0:
            return ticks * d
        lo, hi = -0.2 * self.span_deg, 1.2 * self.span_deg
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if self.ticks_of(mid) < ticks:
                lo = mid
            else:
                hi = mid
        return 0.5 * (lo + hi)

    def offset_shift(self) -> int:
        """Ticks the homing offset adds to the encoder reading: present = encoder + shift."""
        if not self.model.has("homing_offset"):
            return 0
        offset, p = self.get("homing_offset"), self.proto
        limit, mode = p.position_mode_offset_limit, p.position_mode
        if limit is not None and mode is not None and self.get("operating_mode") == mode and abs(offset) > limit:
            return 0  # ignored in Position Control Mode
        return p.homing_sign * offset

    def reported_ticks(self, theta: float | None = None) -> int:
        t = int(round(self.ticks_of(self.theta if theta is None else theta)))
        if self.model.wraps:
            return (t + self.offset_shift()) % self.model.ticks
        return min(max(t, 0), self.model.max_tick)

    def stop_ticks(self) -> tuple[int, int]:
        return self.reported_ticks(self.spec.stop_lo_deg), self.reported_ticks(self.spec.stop_hi_deg)

    def _goal_theta(self, goal: int) -> float:
        if self.model.wraps:  # single-turn position control works in the reading's turn
            if self.offset_shift():  # ... of the offset reading: it moves by goal - present
                return self.theta + (goal - self.reported_ticks()) * self.model.deg_per_tick
            turn = math.floor(self.theta / 360.0)
            return 360.0 * turn + goal * self.model.deg_per_tick
        return self.theta_of(goal)

    # -- derived quantities
    def torque_cap(self) -> float:
        return self.get("torque_limit") / self.model.reg("torque_limit").hi

    def torque_on(self) -> bool:
        return self.get("torque_enable") >= 1 and self.torque_cap() > 0

    def speed_deg_s(self) -> float:
        v, unit, m = self.get("moving_speed"), self.model.speed_unit_deg_s, self.model
        if m.free_speed_deg_s is None or m.top_speed_deg_s is None:  # 0 = up to the Velocity Limit register
            limit = self.get("velocity_limit")
            return unit * (limit if v == 0 else min(v, limit))
        return m.free_speed_deg_s if v == 0 else min(v * unit, m.top_speed_deg_s)

    def return_delay_s(self) -> float:
        return 2e-6 * self.get("return_delay")

    def error_bits(self) -> int:
        """Alarm bits carried by every status packet (the protocol's own encoding)."""
        p = self.proto
        if p.alarm_register is None:
            return self.model.overload_bit if self.overload else 0
        alarms = self.get(p.alarm_register)
        if p.alert_bit is not None:
            return p.alert_bit if alarms else 0
        return alarms

    def _alarm_latched(self) -> bool:
        """An alarm that only a reboot clears (no re-arm): the servo refuses torque meanwhile."""
        p = self.proto
        return p.rearm is None and p.alarm_register is not None and bool(self.get(p.alarm_register))

    def answers(self, is_read_or_ping: bool, is_ping: bool) -> bool:
        level, p = self.get("status_return_level"), self.proto
        return is_ping or level >= p.status_all_level or (is_read_or_ping and level >= p.status_read_level)

    # -- physics
    def step(self, dt: float, t: float) -> None:
        lo, hi = self.spec.stop_lo_deg, self.spec.stop_hi_deg
        old = self.theta
        target_load = 0.0
        sign = 0.0
        self.blocked = False
        cap = self.torque_cap()
        if self.torque_on():
            err = self.theta_goal - self.theta
            vmax = self.speed_deg_s() * dt
            new = self.theta + max(-vmax, min(vmax, err))
            if new <= lo and err < 0:
                new, self.blocked = lo, True
            elif new >= hi and err > 0:
                new, self.blocked = hi, True
            self.theta = new
            sign = 1.0 if err > 0 else -1.0
            if self.blocked:
                push_ticks = abs(self.theta_goal - self.theta) / self.model.deg_per_tick
                slope = 32.0 if self.model.ticks == 1024 else 64.0
                target_load = min(cap, 0.03 + push_ticks / slope)
            elif abs(err) > 0.5 * self.model.deg_per_tick:
                target_load = min(cap, 0.04)
        elif self.hand is not None:
            want = self.hand(t)
            vmax = HAND_SPEED_DEG_S * dt
            self.theta = min(hi, max(lo, self.theta + max(-vmax, min(vmax, want - self.theta))))
        self.vel = (self.theta - old) / dt if dt > 0 else 0.0
        self.load += (sign * target_load - self.load) * (1.0 - math.exp(-dt / LOAD_TAU_S))
        if not self.torque_on():
            self.load *= math.exp(-dt / LOAD_TAU_S)
        self.max_load_frac = max(self.max_load_frac, abs(self.load))
        if self.blocked and cap > 0 and abs(self.load) >= 0.95 * cap:
            self.at_cap_s += dt
            if self.at_cap_s >= self.overload_time_s:
                self._trip()
        else:
            self.at_cap_s = max(0.0, self.at_cap_s - dt)

    def _trip(self) -> None:
        self.overload_trips += 1
        self.at_cap_s = 0.0
        p, bit = self.proto, self.model.overload_bit
        shutdown = self.get("alarm_shutdown") & bit
        self.overload = True
        if p.alarm_register is not None and (shutdown or not p.alarm_needs_shutdown):
            self.set(p.alarm_register, self.get(p.alarm_register) | bit)
        if shutdown:  # the output is cut where the re-arm write restores it
            self.set("torque_limit" if p.rearm == "torque_limit" else "torque_enable", 0)

    def _sync_present(self) -> None:
        d = self.model.deg_per_tick
        self.set("present_position", self.reported_ticks())
        speed = self.vel / self.model.speed_unit_deg_s
        top = self.model.reg("present_speed").magnitude_max
        speed = max(-top, min(top, speed))
        full = self.model.load_full_scale
        self.set("present_speed", int(round(speed)))
        self.set("present_load", int(round(max(-full, min(full, self.load * full)))))
        moving = (self.torque_on() and abs(self.theta_goal - self.theta) > 0.5 * d) or abs(self.vel) > 0.5
        self.set("moving", int(moving))

    def refresh(self) -> None:
        self._sync_present()

    # -- instructions
    def read(self, addr: int, n: int) -> tuple[bytes, int]:
        if n <= 0 or addr + n > len(self.mem):
            return b"", E_LENGTH
        self._sync_present()
        return bytes(self.mem[addr : addr + n]), OK

    def _registers_in(self, addr: int, n: int) -> list[tuple[str, Register]]:
        return [(name, r) for name, r in self.model.table.items() if r.addr < addr + n and addr < r.addr + r.size]

    def write(self, addr: int, data: bytes) -> int:
        """Check the whole packet, then apply it with side effects. Returns OK or an E_* code."""
        n = len(data)
        if n == 0 or addr + n > len(self.mem):
            return E_LENGTH
        regs = self._registers_in(addr, n)
        new = bytearray(self.mem)
        new[addr : addr + n] = data
        torque = self.get("torque_enable") >= 1
        for _name, r in regs:
            if not r.writable:
                return E_ACCESS
            if r.eeprom and self.proto.eeprom_needs_torque_off and (torque or self._locked()):
                return E_ACCESS
            value = decode(r, bytes(new[r.addr : r.addr + r.size]), self.model.big_endian)
            if (r.lo, r.hi) != (0, 0) and not r.lo <= value <= r.hi:
                return E_RANGE
        code = OK
        names = {name for name, _ in regs}
        if "goal_position" in names:
            reg = self.model.reg("goal_position")
            goal = decode(reg, bytes(new[reg.addr : reg.addr + reg.size]), self.model.big_endian)
            lo, hi = self.get("min_limit"), self.get("max_limit")
            if not (lo == 0 and hi == 0) and not lo <= goal <= hi:
                if self.proto.goal_outside_limits == "refuse":
                    return E_LIMIT
                goal = min(max(goal, lo), hi)
                new[reg.addr : reg.addr + reg.size] = encode(reg, goal, self.model.big_endian)
                code = E_ANGLE  # an error bit only where the protocol has one (refusal_bits)
        self.mem[:] = new
        for _name, r in regs:
            if r.eeprom and not (self.proto.eeprom_lock and self._locked()):
                self.flash[r.addr : r.addr + r.size] = new[r.addr : r.addr + r.size]
        for name in names:
            self._after_write(name)
        return code

    def power_cycle(self) -> None:
        """Power off and on: EEPROM comes back from flash, RAM from its defaults, torque off."""
        eeprom = [(r.addr, r.size) for r in self.model.table.values() if r.eeprom]
        self.reset_table()
        for addr, size in eeprom:
            self.mem[addr : addr + size] = self.flash[addr : addr + size]
        self._sync_present()
        self.set("goal_position", self.get("present_position"))

    def _after_write(self, name: str) -> None:
        if name == "goal_position":
            self.theta_goal = self._goal_theta(self.get("goal_position"))
            bit = self.proto.goal_torque_on_bit
            enables = bool(self.get(bit[0]) & bit[1]) if bit is not None else self.goal_enables_torque
            if enables and self.get("torque_enable") == 0 and not self._alarm_latched():
                self.set("torque_enable", 1)
        elif name == "torque_limit" and self.proto.rearm == "torque_limit":
            if self.get("torque_limit") > 0:
                self.overload = False  # re-armed by writing a non-zero Torque Limit
        elif name == "torque_enable":
            te, p = self.get("torque_enable"), self.proto
            if self._alarm_latched() and te:
                self.set("torque_enable", 0)  # refuses until REBOOT
            elif p.torque_enable_calibrate is not None and te == p.torque_enable_calibrate:
                self.set("torque_enable", 0)  # midpoint calibration: not modelled beyond not energising
            elif te and p.rearm == "torque_enable":
                if p.alarm_register is not None:
                    self.set(p.alarm_register, self.get(p.alarm_register) & ~self.model.overload_bit)
                self.overload = False
            if te == 1:
                self.theta_goal = self._goal_theta(self.get("goal_position"))

    def _locked(self) -> bool:
        return self.model.has("lock") and bool(self.get("lock"))

    def reboot(self) -> None:
        if self.model.has("hardware_error"):
            self.set("hardware_error", 0)
        self.overload = False
        self.set("torque_enable", 0)

    def factory_reset(self) -> None:
        self.reset_table()
        self.overload = False
