"""The simulator driven by the real dynamixel-sdk client over the pty (Protocol 1.0 and 2.0)."""

from __future__ import annotations

import time

import pytest
from dynamixel_sdk import (
    COMM_RX_CORRUPT,
    COMM_RX_TIMEOUT,
    COMM_SUCCESS,
    GroupSyncRead,
    GroupSyncWrite,
    PacketHandler,
    PortHandler,
)

from armtool.servo.sim import SimBus
from tests.servo.conftest import sim_config


def _open(sim: SimBus) -> PortHandler:
    port = PortHandler(sim.port_path)
    assert port.openPort() and port.setBaudRate(1000000)
    return port


def test_protocol1_ping_read_write_sync_write() -> None:
    with SimBus.start(sim_config("dxl1", (1, 2))) as sim:
        port, ph = _open(sim), PacketHandler(1.0)
        assert ph.ping(port, 1) == (12, COMM_SUCCESS, 0)
        assert ph.ping(port, 7)[1] == COMM_RX_TIMEOUT
        pos, result, err = ph.read2ByteTxRx(port, 2, 36)
        assert result == COMM_SUCCESS and err == 0 and pos == sim.present_ticks(2)
        assert ph.write2ByteTxRx(port, 1, 32, 300) == (COMM_SUCCESS, 0)
        assert sim.peek(1, "moving_speed") == 300
        sync = GroupSyncWrite(port, ph, 30, 2)
        sync.addParam(1, [0x00, 0x02])  # 512
        sync.addParam(2, [0x58, 0x02])  # 600
        assert sync.txPacket() == COMM_SUCCESS
        time.sleep(0.05)
        assert (sim.peek(1, "goal_position"), sim.peek(2, "goal_position")) == (512, 600)
        assert ph.write2ByteTxRx(port, 1, 30, 2000) == (COMM_SUCCESS, 0x08)  # range error, not applied
        assert sim.peek(1, "goal_position") == 512
        port.closePort()


def test_protocol1_motion_stop_load_and_overload() -> None:
    cfg = sim_config("dxl1", (1,), overload_time_s=0.5)
    with SimBus.start(cfg) as sim:
        port, ph = _open(sim), PacketHandler(1.0)
        ph.write2ByteTxRx(port, 1, 32, 600)  # ~400 deg/s
        ph.write2ByteTxRx(port, 1, 30, 1000)  # goal past the high stop; torque comes on
        time.sleep(0.35)
        _lo, hi = sim.stop_ticks(1)
        pos, _, _ = ph.read2ByteTxRx(port, 1, 36)
        load, _, err = ph.read2ByteTxRx(port, 1, 40)
        assert pos == hi and err == 0
        assert load & 0x3FF > 700 and not load & 0x400  # pushing toward higher ticks (CCW)
        time.sleep(0.6)
        _, _, err = ph.read2ByteTxRx(port, 1, 36)
        assert err & 0x20  # overload alarm
        assert ph.read2ByteTxRx(port, 1, 34)[0] == 0  # alarm shutdown cut the torque limit
        assert ph.write2ByteTxRx(port, 1, 34, 1023)[1] & 0x20 == 0  # re-armed
        port.closePort()


def test_ax_potentiometer_nonlinearity_seen_only_by_the_encoder() -> None:
    import serial

    with SimBus.start(sim_config("dxl1", (1,))) as sim:
        port, ph = _open(sim), PacketHandler(1.0)
        ph.write2ByteTxRx(port, 1, 32, 0)
        ph.write2ByteTxRx(port, 1, 30, 150)  # near the low end: 44 deg nominal
        time.sleep(0.5)
        pos, _, _ = ph.read2ByteTxRx(port, 1, 36)
        nominal = pos * 300 / 1023
        enc = serial.Serial(sim.encoder_port_path, timeout=1)
        enc.write(b"A 1\n")
        true = float(enc.readline())
        enc.write(b"A 9\n")
        assert enc.readline().startswith(b"E")
        enc.close()
        assert abs(pos - 150) <= 1
        assert 1.5 < abs(true - nominal) < 4.0  # a few degrees off near the ends
        assert abs(true - sim.true_angle_deg(1)) < 0.01
        ph.write2ByteTxRx(port, 1, 30, 512)  # the middle is linear
        time.sleep(0.5)
        assert abs(sim.true_angle_deg(1) - 512 * 300 / 1023) < 0.5
        port.closePort()


def test_protocol2_ping_read_write_sync_read_write() -> None:
    with SimBus.start(sim_config("dxl2", (1, 2))) as sim:
        port, ph = _open(sim), PacketHandler(2.0)
        model, result, _ = ph.ping(port, 2)
        assert (model, result) == (1060, COMM_SUCCESS)
        pos, result, _err = ph.read4ByteTxRx(port, 1, 132)
        assert result == COMM_SUCCESS and pos == sim.present_ticks(1)
        assert ph.write1ByteTxRx(port, 1, 64, 1) == (COMM_SUCCESS, 0)
        assert ph.write4ByteTxRx(port, 1, 48, 3000)[1] == 7  # EEPROM with torque on: access error
        sync = GroupSyncWrite(port, ph, 116, 4)
        sync.addParam(1, list((1500).to_bytes(4, "little")))
        sync.addParam(2, list((2500).to_bytes(4, "little")))
        assert sync.txPacket() == COMM_SUCCESS
        time.sleep(0.05)
        assert (sim.peek(1, "goal_position"), sim.peek(2, "goal_position")) == (1500, 2500)
        reader = GroupSyncRead(port, ph, 132, 4)
        reader.addParam(1)
        reader.addParam(2)
        assert reader.txRxPacket() == COMM_SUCCESS
        assert reader.getData(2, 132, 4) == sim.present_ticks(2)
        port.closePort()


@pytest.mark.parametrize("protocol, version", [("dxl1", 1.0), ("dxl2", 2.0)])
def test_faults_missing_dropped_corrupt(protocol: str, version: float) -> None:
    with SimBus.start(sim_config(protocol, (1, 2))) as sim:
        port, ph = _open(sim), PacketHandler(version)
        sim.faults.missing_ids = {2}
        assert ph.ping(port, 2)[1] == COMM_RX_TIMEOUT
        sim.faults.drop_next = 1
        assert ph.read1ByteTxRx(port, 1, 3 if protocol == "dxl1" else 7)[1] == COMM_RX_TIMEOUT
        sim.faults.corrupt_next = 1
        assert ph.read1ByteTxRx(port, 1, 3 if protocol == "dxl1" else 7)[1] == COMM_RX_CORRUPT
        assert ph.read1ByteTxRx(port, 1, 3 if protocol == "dxl1" else 7)[:2] == (1, COMM_SUCCESS)
        port.closePort()


def test_delay_fault_times_out_then_recovers() -> None:
    with SimBus.start(sim_config("dxl1", (1,))) as sim:
        port, ph = _open(sim), PacketHandler(1.0)
        sim.faults.delay_s = 0.05  # later than the SDK's 34 ms timeout
        assert ph.read2ByteTxRx(port, 1, 36)[1] == COMM_RX_TIMEOUT
        sim.faults.delay_s = 0.0
        time.sleep(0.06)
        assert ph.read2ByteTxRx(port, 1, 36)[1] == COMM_SUCCESS
        port.closePort()


def test_bad_instruction_checksum_gets_checksum_error_bit() -> None:
    import serial

    with SimBus.start(sim_config("dxl1", (1,))) as sim:
        ser = serial.Serial(sim.port_path, 1000000, timeout=0.5)
        ser.write(bytes.fromhex("FF FF 01 02 01 FA"))  # ping with a wrong checksum
        assert ser.read(6) == bytes.fromhex("FF FF 01 02 10 EC")
        ser.close()
