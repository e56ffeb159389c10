"""The safety guard: goal := present before torque on; torque off and RAM restored on every exit."""

from __future__ import annotations

import time

import pytest

from armtool.servo.bus import open_bus
from armtool.servo.guard import Terminated, TorqueGuard
from armtool.servo.sim import SimBus
from tests.servo.conftest import sim_config


def test_torque_on_holds_present_pose_not_stale_goal() -> None:
    with SimBus.start(sim_config("dxl1", (1,))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1])
        sim.servo(1).set("goal_position", 900)  # stale goal left in RAM
        before = sim.true_angle_deg(1)
        with TorqueGuard(bus) as guard:
            guard.torque_on(1)
            time.sleep(0.2)
            assert sim.peek(1, "torque_enable") == 1
            assert abs(sim.true_angle_deg(1) - before) < 0.5  # did not jump toward 900
        assert sim.peek(1, "torque_enable") == 0


@pytest.mark.parametrize("exc", [RuntimeError("boom"), KeyboardInterrupt(), Terminated()])
def test_exit_paths_turn_torque_off_and_restore_ram(exc: BaseException) -> None:
    with SimBus.start(sim_config("dxl1", (1, 2))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1, 2])
        with pytest.raises(type(exc)):
            with TorqueGuard(bus) as guard:
                guard.set_ram(1, "torque_limit", 300)
                guard.set_ram(2, "moving_speed", 50)
                guard.torque_on(1)
                guard.torque_on(2)
                raise exc
        assert [sim.peek(i, "torque_enable") for i in (1, 2)] == [0, 0]
        assert sim.peek(1, "torque_limit") == 1023 and sim.peek(2, "moving_speed") == 0


def test_torque_off_is_retried_through_dropped_replies() -> None:
    with SimBus.start(sim_config("dxl1", (1,))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1])
        with TorqueGuard(bus) as guard:
            guard.torque_on(1)
            sim.faults.drop_next = 4
        assert sim.peek(1, "torque_enable") == 0 and guard.failed_off == []


def test_sigterm_raises_terminated_inside_the_guard() -> None:
    import os
    import signal

    with SimBus.start(sim_config("dxl1", (1,))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1])
        with pytest.raises(Terminated):
            with TorqueGuard(bus) as guard:
                guard.torque_on(1)
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(1.0)
        assert sim.peek(1, "torque_enable") == 0
        assert signal.getsignal(signal.SIGTERM) in (signal.SIG_DFL, None) or callable(signal.getsignal(signal.SIGTERM))
