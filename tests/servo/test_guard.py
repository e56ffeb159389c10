"""The safety guard: goal := present before torque on; torque off and RAM restored on every exit."""

from __future__ import annotations

import time

import pytest

from armtool.errors import ArmtoolError
from armtool.servo.bus import PortLost, open_bus
from armtool.servo.guard import Terminated, TorqueGuard, TorqueOffFailed
from armtool.servo.sim import SimBus
from armtool.servo.transport import CommError
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


def test_signal_handlers_are_the_originals_after_the_guard() -> None:
    import signal

    def mine(signum: int, frame: object) -> None:
        pass

    old_term = signal.signal(signal.SIGTERM, mine)
    try:
        with SimBus.start(sim_config("dxl1", (1,))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
            bus.identify([1])
            original_int = signal.getsignal(signal.SIGINT)
            with TorqueGuard(bus) as guard:
                assert signal.getsignal(signal.SIGTERM) is not mine
                guard.torque_on(1)
            assert signal.getsignal(signal.SIGTERM) is mine
            assert signal.getsignal(signal.SIGINT) is original_int
    finally:
        signal.signal(signal.SIGTERM, old_term)


def test_lost_port_mid_operation_every_id_tried_and_reported() -> None:
    """The adapter vanishes mid-run: the I/O error becomes a clear PortLost, cleanup still tries
    every ID, and the IDs that may still be energised are reported with the power-off hint."""
    with SimBus.start(sim_config("dxl1", (1, 2))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1, 2])
        with pytest.raises(TorqueOffFailed) as info:
            with TorqueGuard(bus) as guard:
                guard.set_ram(1, "torque_limit", 300)
                guard.torque_on(1)
                guard.torque_on(2)
                sim.hang_up()
                bus.read(1, "present_position")
        assert guard.failed_off == [1, 2] and info.value.ids == [1, 2]
        assert "lost the serial port" in info.value.what and "switch the servo power off" in (info.value.hint or "")
        assert isinstance(info.value.__context__, PortLost)
        assert sim.peek(1, "torque_enable") == 1 and sim.peek(2, "torque_enable") == 1  # what the person must know


def test_a_non_armtool_error_on_one_id_does_not_stop_the_others(monkeypatch: pytest.MonkeyPatch) -> None:
    with SimBus.start(sim_config("dxl1", (1, 2))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1, 2])
        with pytest.raises(TorqueOffFailed, match="ID 1:"):
            with TorqueGuard(bus) as guard:
                guard.set_ram(2, "moving_speed", 50)
                guard.torque_on(1)
                guard.torque_on(2)
                real = bus.transport.write

                def write(sid: int, addr: int, data: bytes) -> int:
                    if sid == 1:
                        raise ValueError("SDK bug")
                    return real(sid, addr, data)

                monkeypatch.setattr(bus.transport, "write", write)
        assert guard.failed_off == [1]
        assert sim.peek(2, "torque_enable") == 0 and sim.peek(2, "moving_speed") == 0  # off and restored


def test_failed_torque_off_is_reported_while_another_error_is_in_flight() -> None:
    with SimBus.start(sim_config("dxl1", (1, 2))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1, 2])
        with pytest.raises(TorqueOffFailed) as info:
            with TorqueGuard(bus) as guard:
                guard.torque_on(1)
                guard.torque_on(2)
                sim.faults.missing_ids = {1}  # ID 1 stops answering mid-run
                bus.read(1, "present_position")
        assert info.value.ids == [1] and isinstance(info.value.__context__, CommError)
        assert "after: ID 1: read present_position failed 3 times" in info.value.what
        assert sim.peek(1, "torque_enable") == 1 and sim.peek(2, "torque_enable") == 0


@pytest.mark.parametrize("protocol", ["dxl1", "feetech"])
def test_abort_leaves_goal_at_present_and_torque_off(protocol: str) -> None:
    """A stale goal after an abort drives the next tool's torque-on into the stop."""
    with SimBus.start(sim_config(protocol, (1,))) as sim, open_bus(sim.port_path, protocol, 1000000) as bus:
        bus.identify([1])
        far = 900 if protocol == "dxl1" else 3200
        with pytest.raises(RuntimeError):
            with TorqueGuard(bus) as guard:
                guard.set_ram(1, "moving_speed", 40)
                guard.torque_on(1)
                bus.write(1, "goal_position", far, retry=True)
                time.sleep(0.3)
                assert sim.peek(1, "moving") == 1
                raise RuntimeError("abort mid-move")
        time.sleep(0.1)
        present, goal = sim.peek(1, "present_position"), sim.peek(1, "goal_position")
        assert sim.peek(1, "torque_enable") == 0  # and the goal write did not turn it back on
        assert abs(goal - present) <= 3 and abs(goal - far) > 50, (goal, present)


def test_torque_on_refuses_a_position_outside_the_goal_range(monkeypatch: pytest.MonkeyPatch) -> None:
    with SimBus.start(sim_config("dxl2", (1,))) as sim, open_bus(sim.port_path, "dxl2", 1000000) as bus:
        bus.identify([1])
        real = bus.read
        monkeypatch.setattr(bus, "read", lambda sid, name: 4300 if name == "present_position" else real(sid, name))
        with TorqueGuard(bus) as guard:  # as with a homing offset: the reading is past 4095
            with pytest.raises(ArmtoolError, match="outside the goal range 0..4095"):
                guard.torque_on(1)
        assert sim.peek(1, "torque_enable") == 0 and sim.peek(1, "goal_position") != 4095


def test_sigint_landing_as_the_guard_exits_still_releases(monkeypatch: pytest.MonkeyPatch) -> None:
    """A Ctrl-C that arrived just before the mask was set runs its handler at the first check
    inside __exit__ (after the first call returns): cleanup must still run, the interrupt after it."""
    import armtool.servo.guard as guard_module

    real = guard_module._block_signals
    fired: list[int] = []

    def block_then_pending_handler() -> None:
        real()
        if not fired:
            fired.append(1)
            raise KeyboardInterrupt()

    with SimBus.start(sim_config("dxl1", (1,))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1])
        monkeypatch.setattr(guard_module, "_block_signals", block_then_pending_handler)
        with pytest.raises(KeyboardInterrupt):
            with TorqueGuard(bus) as guard:
                guard.torque_on(1)
        assert fired and sim.peek(1, "torque_enable") == 0
