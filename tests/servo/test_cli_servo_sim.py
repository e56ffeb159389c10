"""`armtool servo-sim` as a process: prints its pty paths, serves real clients, stops cleanly."""

from __future__ import annotations

import signal
import subprocess
import sys
import time

from dynamixel_sdk import COMM_SUCCESS, PacketHandler, PortHandler

from tests.servo.conftest import FIXTURES


def _start(*args: str) -> tuple[subprocess.Popen[str], str, str]:
    proc = subprocess.Popen(
        [sys.executable, "-m", "armtool", "servo-sim", *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert proc.stdout is not None
    port = proc.stdout.readline().strip()
    encoder = proc.stdout.readline().strip()
    return proc, port, encoder


def _ping(ph: PacketHandler, port: PortHandler, sid: int, tries: int = 3) -> tuple[int, int]:
    """(model number, result) of a PING, retried as `ServoBus.ping` does: on a loaded machine the
    simulator's first reply can miss the SDK's ~20 ms timeout (seen: COMM_RX_TIMEOUT, then fine)."""
    for _ in range(tries):
        model, result, _err = ph.ping(port, sid)
        if result == COMM_SUCCESS:
            break
    return int(model), int(result)


def test_prints_ports_serves_sdk_and_stops_after_duration(tmp_path) -> None:  # type: ignore[no-untyped-def]
    port_file = tmp_path / "port"
    proc, path, encoder = _start(str(FIXTURES / "ax12_arm.yaml"), "--duration", "3", "--port-file", str(port_file))
    try:
        assert path.startswith("/dev/") and encoder.startswith("/dev/") and path != encoder
        assert port_file.read_text().strip() == path
        port = PortHandler(path)
        assert port.openPort()
        ph = PacketHandler(1.0)
        assert [_ping(ph, port, i) for i in (1, 5)] == [(12, COMM_SUCCESS), (12, COMM_SUCCESS)]
        port.closePort()
        assert proc.wait(timeout=10) == 0
        assert not port_file.exists()
    finally:
        proc.kill()


def test_sigterm_stops_it() -> None:
    proc, _path, _ = _start(str(FIXTURES / "so101_arm.yaml"))
    try:
        time.sleep(0.3)
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=5) == 0
    finally:
        proc.kill()


def test_bad_config_exits_2(tmp_path) -> None:  # type: ignore[no-untyped-def]
    bad = tmp_path / "bad.yaml"
    bad.write_text("protocol: dxl1\njoints:\n  - {id: 1, model: AX-12A, stops: [900, 100]}\n")
    result = subprocess.run(
        [sys.executable, "-m", "armtool", "servo-sim", str(bad)], capture_output=True, text=True, timeout=30
    )
    assert result.returncode == 2
    assert "stops must be [low, high]" in result.stderr and "joints[0]" in result.stderr
