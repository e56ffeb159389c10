"""armtool's bus layer against the simulator: identify, retries, refusals, echo, port errors."""

from __future__ import annotations

import time
from pathlib import Path

import pytest

from armtool.errors import ArmtoolError
from armtool.servo import bus as bus_mod
from armtool.servo.bus import StatusError, open_bus
from armtool.servo.models import by_name
from armtool.servo.sim import SimBus
from armtool.servo.transport import CommError
from tests.servo.conftest import sim_config


@pytest.mark.parametrize("protocol, model", [("dxl1", "AX-12A"), ("dxl2", "XL430-W250"), ("feetech", "STS3215")])
def test_identify_read_write_sync_write(protocol: str, model: str) -> None:
    with (
        SimBus.start(sim_config(protocol, (1, 2))) as sim,
        open_bus(sim.port_path, protocol, 1000000, echo_check_id=1) as bus,
    ):
        servos = bus.identify([1, 2])
        assert {s.model.name for s in servos.values()} == {model}
        assert bus.read(1, "present_position") == sim.present_ticks(1)
        bus.write(1, "moving_speed", 100)
        assert sim.peek(1, "moving_speed") == 100
        bus.sync_write("goal_position", {1: 1000, 2: 1010})
        time.sleep(0.03)
        assert (sim.peek(1, "goal_position"), sim.peek(2, "goal_position")) == (1000, 1010)
        many = bus.read_many(2, ["present_position", "present_load", "moving"])
        assert set(many) == {"present_position", "present_load", "moving"}


def test_feetech_sign_magnitude_load_and_speed() -> None:
    with SimBus.start(sim_config("feetech", (1,))) as sim, open_bus(sim.port_path, "feetech", 1000000) as bus:
        bus.identify([1])
        bus.write(1, "moving_speed", 3000)
        bus.write(1, "goal_position", 600)  # below the 800 stop: pushes toward lower ticks
        time.sleep(0.9)
        load = bus.read(1, "present_load")
        assert load < -300  # sign-magnitude bit 10 decoded as negative
        raw = sim.servo(1).mem[60] | sim.servo(1).mem[61] << 8
        assert raw & 0x400 and (raw & 0x3FF) == -load
        assert bus.read(1, "present_position") == sim.stop_ticks(1)[0]
        bus.write(1, "torque_enable", 0)


def test_reads_retry_on_drop_and_corrupt() -> None:
    with SimBus.start(sim_config("dxl1", (1,))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1])
        sim.faults.drop_next, sim.faults.corrupt_next = 1, 1
        assert bus.read(1, "present_position") == sim.present_ticks(1)
        assert bus.stats.retries == 2
        sim.faults.p_drop = 0.05
        for _ in range(100):
            bus.read(1, "present_position")
        assert bus.stats.failures == 0


def test_read_gives_up_with_a_clear_error() -> None:
    with SimBus.start(sim_config("dxl1", (1,))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1])
        sim.faults.corrupt_next = 10
        with pytest.raises(CommError, match="failed 3 times .corrupt reply"):
            bus.read(1, "present_position")


def test_rejected_write_is_not_retried() -> None:
    with SimBus.start(sim_config("dxl1", (1,))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1])
        bus.write(1, "max_limit", 800)
        bus.write(1, "torque_enable", 1)
        before = sim.stats["rx_packets"]
        with pytest.raises(StatusError, match="refused min_limit = 100: value out of range"):
            bus.write(1, "min_limit", 100, retry=True)  # EEPROM write with torque on
        assert sim.stats["rx_packets"] == before + 1
        with pytest.raises(StatusError, match="angle limits"):
            bus.write(1, "goal_position", 900, retry=True)
        bus.write(1, "torque_enable", 0)


def test_timed_out_write_says_it_may_have_happened() -> None:
    with SimBus.start(sim_config("dxl1", (1,))) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1])
        sim.faults.drop_next = 1
        with pytest.raises(CommError, match="may or may not have happened"):
            bus.write(1, "led", 1)
        sim.faults.drop_next = 1
        bus.write(1, "led", 0, retry=True)  # idempotent: resent


def test_missing_id_and_unknown_model_and_wrong_model() -> None:
    cfg = sim_config("dxl1", (1, 2))
    cfg["joints"][1]["model"] = "AX-18A"
    with SimBus.start(cfg) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        with pytest.raises(ArmtoolError, match=r"ID 3 did not answer .*") as exc:
            bus.identify([1, 2, 3])
        assert "answering: ID 1-2" in (exc.value.hint or "")
        with pytest.raises(ArmtoolError, match="ID 2 is a AX-18A .model number 18., not the AX-12A expected"):
            bus.identify([1, 2], expected={1: by_name("AX-12A"), 2: by_name("AX-12A")})
        sim.servo(1).set("model_number", 999)
        with pytest.raises(ArmtoolError, match="model number 999, which armtool does not know"):
            bus.identify([1])


def test_wrong_baud_says_what_was_tried() -> None:
    with SimBus.start(sim_config("dxl1", (1, 2))) as sim, open_bus(sim.port_path, "dxl1", 57600) as bus:
        with pytest.raises(
            ArmtoolError, match=r"no servo answered .* at 57600 baud with protocol dxl1 \(tried ID 1-2\)"
        ):
            bus.identify([1, 2])


def test_echo_is_detected_at_connect() -> None:
    cfg = sim_config("dxl1", (1,), faults={"echo": True})
    with SimBus.start(cfg) as sim:
        with pytest.raises(ArmtoolError, match="echoes what it sends"):
            open_bus(sim.port_path, "dxl1", 1000000, echo_check_id=1)
        sim.faults.echo = False
        open_bus(sim.port_path, "dxl1", 1000000, echo_check_id=1).close()


def test_port_missing_and_busy(tmp_path: Path) -> None:
    import serial

    with pytest.raises(ArmtoolError, match="does not exist"):
        open_bus(str(tmp_path / "ttyUSB9"), "dxl1", 1000000)
    with SimBus.start(sim_config("dxl1", (1,))) as sim:
        holder = serial.Serial(sim.port_path, 1000000, exclusive=True)
        with pytest.raises(ArmtoolError, match="is busy"):
            open_bus(sim.port_path, "dxl1", 1000000)
        holder.close()
    with pytest.raises(ArmtoolError, match="unknown protocol"):
        open_bus("/dev/null", "canopen", 1000000)


def test_ftdi_latency_timer_warning(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    with SimBus.start(sim_config("dxl1", (1,))) as sim:
        name = Path(sim.port_path).name
        (tmp_path / name).mkdir()
        (tmp_path / name / "latency_timer").write_text("16\n")
        monkeypatch.setattr(bus_mod, "SYSFS_USB_SERIAL", tmp_path)
        with open_bus(sim.port_path, "dxl1", 1000000) as bus:
            assert len(bus.warnings) == 1 and "latency timer is 16 ms" in bus.warnings[0]
        (tmp_path / name / "latency_timer").write_text("1\n")
        with open_bus(sim.port_path, "dxl1", 1000000) as bus:
            assert bus.warnings == []


@pytest.mark.parametrize("protocol", ["dxl1", "dxl2", "feetech"])
def test_overload_alarm_is_seen_through_the_error_byte_of_every_protocol(protocol: str) -> None:
    """move_and_settle polls `overload_alarm`: it must see the alarm wherever the protocol keeps it."""
    with SimBus.start(sim_config(protocol, (1,))) as sim, open_bus(sim.port_path, protocol, 1000000) as bus:
        bus.identify([1])
        bus.read(1, "present_position")
        assert not bus.overload_alarm(1)
        with sim.lock:
            servo = sim.servo(1)
            servo.set("alarm_shutdown", servo.get("alarm_shutdown") | servo.model.overload_bit)
            servo._trip()
        bus.read_many(1, ["present_position", "present_load"])  # the poll's read carries the error byte
        assert bus.overload_alarm(1) and bus.overloaded(1)
