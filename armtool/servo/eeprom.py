"""EEPROM writes: planned first (for --dry-run and the confirmation prompt), then written with
torque off, Feetech's Lock dance, never broadcast, and every value verified by reading it back."""

from __future__ import annotations

from dataclasses import dataclass

from armtool.errors import ArmtoolError
from armtool.servo.bus import ServoBus
from armtool.servo.registry import transport_class


@dataclass(frozen=True)
class EepromWrite:
    id: int
    register: str
    old: int
    new: int

    def describe(self) -> str:
        return f"ID {self.id}: {self.register} {self.old} -> {self.new}"


def plan_writes(bus: ServoBus, wanted: dict[int, dict[str, int]]) -> list[EepromWrite]:
    """The writes needed to reach `wanted` ({id: {register: value}}), skipping values already set."""
    plan: list[EepromWrite] = []
    for sid, regs in wanted.items():
        model = bus.model(sid)
        for name, value in regs.items():
            reg = model.reg(name)
            if not reg.eeprom or not reg.writable:
                raise ArmtoolError(f"{model.name} register '{name}' is not a writable EEPROM register")
            old = bus.read(sid, name)
            if old != value:
                plan.append(EepromWrite(sid, name, old, value))
    return plan


def apply_writes(bus: ServoBus, plan: list[EepromWrite]) -> None:
    """Write and verify. Raises ArmtoolError naming the first value that did not read back."""
    by_id: dict[int, list[EepromWrite]] = {}
    for w in plan:
        by_id.setdefault(w.id, []).append(w)
    for sid, writes in by_id.items():
        model = bus.model(sid)
        bus.write(sid, "torque_enable", 0, retry=True)  # AX/X refuse EEPROM writes with torque on
        unlock = transport_class(model.protocol).eeprom_lock and model.has("lock")
        if unlock:
            bus.write(sid, "lock", 0, retry=True)
        try:
            for w in writes:
                bus.write(sid, w.register, w.new)
                back = bus.read(sid, w.register)
                if back != w.new:
                    raise ArmtoolError(
                        f"ID {sid}: {w.register} reads back {back} after writing {w.new}",
                        hint="the EEPROM may be locked (AX Lock register needs a power cycle)",
                    )
        finally:
            if unlock:
                bus.write(sid, "lock", 1, retry=True)
