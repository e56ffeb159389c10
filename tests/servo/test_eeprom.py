"""EEPROM writes: planned, torque off first, Feetech Lock dance, verified by reading back."""

from __future__ import annotations

import pytest

from armtool.errors import ArmtoolError
from armtool.servo.bus import open_bus
from armtool.servo.eeprom import apply_writes, plan_writes
from armtool.servo.sim import SimBus
from tests.servo.conftest import sim_config


@pytest.mark.parametrize("protocol", ["dxl1", "dxl2", "feetech"])
def test_plan_apply_verify(protocol: str) -> None:
    with SimBus.start(sim_config(protocol, (1,))) as sim, open_bus(sim.port_path, protocol, 1000000) as bus:
        bus.identify([1])
        bus.write(1, "torque_enable", 1)
        plan = plan_writes(bus, {1: {"min_limit": 204, "max_limit": 678}})
        assert next(w.describe() for w in plan).startswith("ID 1: min_limit 0 -> 204")
        apply_writes(bus, plan)
        assert (sim.peek(1, "min_limit"), sim.peek(1, "max_limit")) == (204, 678)
        assert sim.peek(1, "torque_enable") == 0
        if protocol == "feetech":
            assert sim.peek(1, "lock") == 1
        assert plan_writes(bus, {1: {"min_limit": 204, "max_limit": 678}}) == []


def test_feetech_writes_survive_a_power_cycle() -> None:
    # An STS servo accepts EEPROM writes while Lock = 1 but forgets them at power-up: the write
    # only sticks because apply_writes unlocks first (and locks again after).
    with SimBus.start(sim_config("feetech", (1,))) as sim, open_bus(sim.port_path, "feetech", 1000000) as bus:
        bus.identify([1])
        assert sim.peek(1, "lock") == 1
        apply_writes(bus, plan_writes(bus, {1: {"min_limit": 204, "max_limit": 678}}))
        sim.servo(1).power_cycle()
        assert (sim.peek(1, "min_limit"), sim.peek(1, "max_limit")) == (204, 678)
        # The same write made without the unlock is lost at power-up.
        bus.write(1, "min_limit", 300)
        assert sim.peek(1, "min_limit") == 300
        sim.servo(1).power_cycle()
        assert sim.peek(1, "min_limit") == 204


def test_locked_ax_eeprom_fails_loudly() -> None:
    with SimBus.start(sim_config("dxl1", (1,))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1])
        sim.servo(1).set("lock", 1)
        with pytest.raises(ArmtoolError, match="refused min_limit = 204"):
            apply_writes(bus, plan_writes(bus, {1: {"min_limit": 204}}))
        assert sim.peek(1, "min_limit") == 0


def test_only_eeprom_registers() -> None:
    with SimBus.start(sim_config("dxl1", (1,))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1])
        with pytest.raises(ArmtoolError, match="not a writable EEPROM register"):
            plan_writes(bus, {1: {"goal_position": 3}})
