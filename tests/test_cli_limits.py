"""`armtool limits` end to end: a real CLI process against the simulator started in the test."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest
import yaml

from armtool.servo.sim import Person, PersonSpec, SimBus, load_sim_config

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "servo"
AX_ARM = FIXTURES / "ax12_arm.yaml"
KEYS = [
    "name",
    "id",
    "model",
    "zero_ticks",
    "direction",
    "raw_min_ticks",
    "raw_max_ticks",
    "safe_min_ticks",
    "safe_max_ticks",
    "lower_rad",
    "upper_rad",
    "method",
    "evidence",
]

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="the simulator needs a pty")


def armtool(*args: str, timeout: float = 60) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "NO_COLOR": "1", "COLUMNS": "120"}
    return subprocess.run(
        [sys.executable, "-m", "armtool", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        stdin=subprocess.DEVNULL,
        env=env,
    )


def sub_arm(tmp_path: Path, ids: list[int]) -> Path:
    doc = yaml.safe_load(AX_ARM.read_text())
    doc["joints"] = [j for j in doc["joints"] if j["id"] in ids]
    path = tmp_path / "arm.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


def all_off(sim: SimBus) -> bool:
    return all(sim.peek(i, "torque_enable") == 0 for i in sim.servos)


def test_auto_writes_yaml_and_a_urdf_that_passes_lint(tmp_path: Path) -> None:
    arm = sub_arm(tmp_path, [4, 5])
    out, urdf_out = tmp_path / "limits.yaml", tmp_path / "arm.limited.urdf"
    with SimBus.start(AX_ARM) as sim:
        r = armtool(
            "limits",
            "--port",
            sim.port_path,
            "--arm",
            str(arm),
            "--mode",
            "auto",
            "--yes",
            "--speed",
            "300",
            "-o",
            str(out),
            "--urdf",
            str(FIXTURES / "ax12_arm.urdf"),
            "--urdf-out",
            str(urdf_out),
        )
        assert r.returncode == 0, r.stderr
        assert all_off(sim)
        doc = yaml.safe_load(out.read_text())
        assert doc["schema"] == "armtool.limits/1" and doc["version"] == 1
        assert doc["bus"] == {"port": sim.port_path, "protocol": "dxl1", "baud": 1000000}
        for row in doc["joints"]:
            assert all(k in row for k in KEYS)
            lo, hi = sim.stop_ticks(row["id"])
            assert abs(row["raw_min_ticks"] - lo) <= 2 and abs(row["raw_max_ticks"] - hi) <= 2
            assert sim.servo(row["id"]).overload_trips == 0
    text = urdf_out.read_text()
    gripper = next(j for j in doc["joints"] if j["name"] == "gripper")
    assert f'lower="{gripper["lower_rad"]:.6g}" upper="{gripper["upper_rad"]:.6g}"' in text
    assert "<!-- AX-12A: 1.5 N m, 59 rpm -->" in text  # comments kept
    lint = armtool("lint", str(urdf_out))
    assert lint.returncode == 0, lint.stdout + lint.stderr


def test_manual_with_the_simulated_person(tmp_path: Path) -> None:
    """The person starts once the CLI says it is recording (start-up of a loaded machine is not
    part of the test), and --duration leaves slack for a slow scheduler; the stops must still be
    found within 2 ticks and both ends confirmed."""
    arm = sub_arm(tmp_path, [1, 2])
    spec = PersonSpec(start_s=0.2, speed_deg_s=200, dwell_s=0.5, ids=[1, 2])
    with SimBus.start(AX_ARM) as sim:
        moves = []
        for i in spec.ids or []:
            s = sim.servo(i).spec
            lo, hi, here = s.stop_lo_deg - spec.overshoot_deg, s.stop_hi_deg + spec.overshoot_deg, sim.true_angle_deg(i)
            moves.append((abs(here - lo) + (hi - lo) + abs(hi - (lo + hi) / 2)) / spec.speed_deg_s + 2 * spec.dwell_s)
        duration = spec.start_s + max(moves) + 2.0
        env = {**os.environ, "NO_COLOR": "1", "COLUMNS": "120"}
        proc = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "armtool",
                "limits",
                "--port",
                sim.port_path,
                "--arm",
                str(arm),
                "--mode",
                "manual",
                "--duration",
                f"{duration:.1f}",
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            stdin=subprocess.DEVNULL,
            text=True,
            env=env,
        )
        try:
            assert proc.stderr is not None
            first = ""
            while "torque is off" not in first:  # "torque is off: move every joint ..." printed just before recording
                line = proc.stderr.readline()
                assert line, "the CLI ended before recording"
                first += line
            Person(sim, spec).start()
            out, err = proc.communicate(timeout=duration + 30)
        finally:
            proc.kill()
        assert proc.returncode == 0, first + err
        doc = yaml.safe_load(out)
        for row in doc["joints"]:
            lo, hi = sim.stop_ticks(row["id"])
            assert abs(row["raw_min_ticks"] - lo) <= 2 and abs(row["raw_max_ticks"] - hi) <= 2
            assert row["method"] == "manual" and row["evidence"]["confirmed_min"] and row["evidence"]["confirmed_max"]
        assert "joint ranges" in err  # the live table


@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_signal_during_auto_leaves_every_servo_torque_off(tmp_path: Path, signum: int, code: int) -> None:
    out = tmp_path / "limits.yaml"
    with SimBus.start(AX_ARM) as sim:
        proc = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "armtool",
                "limits",
                "--port",
                sim.port_path,
                "--arm",
                str(AX_ARM),
                "--mode",
                "auto",
                "--yes",
                "--speed",
                "30",
                "-o",
                str(out),
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            stdin=subprocess.DEVNULL,
            text=True,
            # Ctrl-C reaches it as at a terminal, even when the test run itself was started in the
            # background (`cmd &` in a script starts it with SIGINT ignored, and a child inherits that)
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )
        try:
            deadline = time.monotonic() + 20
            while sim.peek(1, "torque_enable") == 0 and time.monotonic() < deadline:
                time.sleep(0.02)
            assert sim.peek(1, "torque_enable") == 1
            time.sleep(0.4)  # joint 1 is driving toward its stop
            assert sim.peek(1, "moving") == 1
            proc.send_signal(signum)
            _, err = proc.communicate(timeout=10)
        finally:
            proc.kill()
        assert proc.returncode == code, err
        assert all_off(sim)
        assert sim.peek(1, "torque_limit") == 1023 and sim.peek(1, "moving_speed") == 0  # RAM restored
        assert not out.exists()


@pytest.mark.parametrize(
    "fault, message",
    [
        ({"missing_ids": [3]}, "ID 3 did not answer"),
        ({"p_corrupt": 1.0}, "corrupt packets"),
        ({"echo": True}, "echoes what it sends"),
    ],
)
def test_bus_faults_give_clear_errors(tmp_path: Path, fault: dict[str, Any], message: str) -> None:
    cfg = load_sim_config(AX_ARM)
    for k, v in fault.items():
        setattr(cfg.faults, k, set(v) if k == "missing_ids" else v)
    out = tmp_path / "limits.yaml"
    with SimBus.start(cfg) as sim:
        r = armtool("limits", "--port", sim.port_path, "--arm", str(AX_ARM), "--mode", "auto", "--yes", "-o", str(out))
        assert r.returncode == 2 and message in r.stderr, r.stderr
        assert "Traceback" not in r.stderr and not out.exists()
        sim.faults.echo, sim.faults.p_corrupt = False, 0.0
        assert all_off(sim)


def test_bad_port_busy_port_wrong_baud_wrong_model(tmp_path: Path) -> None:
    import serial

    r = armtool("limits", "--port", str(tmp_path / "ttyUSB7"), "--ids", "1", "--mode", "auto", "--yes")
    assert r.returncode == 2 and "does not exist" in r.stderr
    with SimBus.start(AX_ARM) as sim:
        holder = serial.Serial(sim.port_path, 1000000, exclusive=True)
        r = armtool("limits", "--port", sim.port_path, "--ids", "1", "--mode", "auto", "--yes")
        holder.close()
        assert r.returncode == 2 and "busy" in r.stderr
        r = armtool("limits", "--port", sim.port_path, "--ids", "1,2", "--baud", "57600", "--mode", "auto", "--yes")
        assert (
            r.returncode == 2
            and "no servo answered" in r.stderr
            and "57600 baud" in r.stderr
            and "tried ID 1-2" in r.stderr
        )
        r = armtool("limits", "--port", sim.port_path, "--ids", "1", "--model", "AX-18A", "--mode", "auto", "--yes")
        assert r.returncode == 2 and "ID 1 is a AX-12A (model number 12), not the AX-18A expected" in r.stderr
        assert all_off(sim)


def test_limits_outside_the_urdf_exit_2_and_write_nothing(tmp_path: Path) -> None:
    arm = sub_arm(tmp_path, [5])
    narrow = tmp_path / "narrow.urdf"
    original = (FIXTURES / "ax12_arm.urdf").read_text().replace('lower="-1.0" upper="1.0"', 'lower="-0.2" upper="0.2"')
    narrow.write_text(original)
    out = tmp_path / "limits.yaml"
    with SimBus.start(AX_ARM) as sim:
        r = armtool(
            "limits",
            "--port",
            sim.port_path,
            "--arm",
            str(arm),
            "--mode",
            "auto",
            "--yes",
            "--speed",
            "300",
            "-o",
            str(out),
            "--urdf",
            str(narrow),
            "--in-place",
        )
        assert r.returncode == 2 and "outside the URDF's: gripper" in r.stderr, r.stderr
        assert all_off(sim)
    assert not out.exists() and narrow.read_text() == original and not (tmp_path / "narrow.urdf.bak").exists()


def test_in_place_leaves_a_bak_and_eeprom_dry_run_then_write(tmp_path: Path) -> None:
    arm = sub_arm(tmp_path, [5])
    urdf = tmp_path / "arm.urdf"
    urdf.write_text((FIXTURES / "ax12_arm.urdf").read_text())
    with SimBus.start(AX_ARM) as sim:
        base = ["limits", "--port", sim.port_path, "--arm", str(arm), "--mode", "auto", "--yes", "--speed", "300"]
        r = armtool(*base, "--write-eeprom", "--dry-run")
        assert r.returncode == 0, r.stderr
        assert "would write ID 5: min_limit 0 ->" in r.stderr and sim.peek(5, "min_limit") == 0
        r = armtool(*base, "--write-eeprom", "--urdf", str(urdf), "--in-place")
        assert r.returncode == 0, r.stderr
        row = yaml.safe_load(r.stdout)["joints"][0]
        assert (sim.peek(5, "min_limit"), sim.peek(5, "max_limit")) == (row["safe_min_ticks"], row["safe_max_ticks"])
        assert "verified by reading back" in r.stderr and all_off(sim)
    assert (tmp_path / "arm.urdf.bak").read_text() == (FIXTURES / "ax12_arm.urdf").read_text()
    assert f'lower="{row["lower_rad"]:.6g}"' in urdf.read_text()


def test_usage_errors_before_touching_the_bus() -> None:
    r = armtool("limits", "--port", "/dev/null", "--mode", "auto")
    assert r.returncode == 2 and "exactly one of --ids or --arm" in r.stderr
    r = armtool("limits", "--port", "/dev/null", "--ids", "1", "--mode", "auto")
    assert r.returncode == 2 and "--yes" in r.stderr
    r = armtool("limits", "--port", "/dev/null", "--ids", "1", "--mode", "manual")
    assert r.returncode == 2 and "--duration" in r.stderr


def test_write_eeprom_refuses_a_range_end_but_keeps_the_yaml(tmp_path: Path) -> None:
    so101 = FIXTURES / "so101_arm.yaml"
    doc = yaml.safe_load(so101.read_text())
    doc["joints"] = [j for j in doc["joints"] if j["id"] == 5]  # wrist_roll: travel across the seam
    arm = tmp_path / "arm.yaml"
    arm.write_text(yaml.safe_dump(doc))
    out = tmp_path / "limits.yaml"
    with SimBus.start(so101) as sim:
        before = (sim.peek(5, "min_limit"), sim.peek(5, "max_limit"))
        r = armtool(
            "limits",
            "--port",
            sim.port_path,
            "--arm",
            str(arm),
            "--mode",
            "auto",
            "--yes",
            "--speed",
            "300",
            "-o",
            str(out),
            "--write-eeprom",
        )
        assert r.returncode == 2 and "not writing EEPROM limits: unconfirmed ends on wrist_roll" in r.stderr, r.stderr
        assert (sim.peek(5, "min_limit"), sim.peek(5, "max_limit")) == before and all_off(sim)
    row = yaml.safe_load(out.read_text())["joints"][0]  # the recording is kept
    assert row["name"] == "wrist_roll" and False in (row["evidence"]["confirmed_min"], row["evidence"]["confirmed_max"])


def test_in_place_twice_keeps_the_original_in_bak(tmp_path: Path) -> None:
    """Issue 14: a second --in-place run rewrote .bak and lost the original URDF."""
    arm = sub_arm(tmp_path, [5])
    urdf = tmp_path / "arm.urdf"
    original = (FIXTURES / "ax12_arm.urdf").read_text()
    urdf.write_text(original)
    with SimBus.start(AX_ARM) as sim:
        base = [
            "limits",
            "--port",
            sim.port_path,
            "--arm",
            str(arm),
            "--mode",
            "auto",
            "--yes",
            "--speed",
            "300",
            "--urdf",
            str(urdf),
            "--in-place",
        ]
        first = armtool(*base)
        assert first.returncode == 0, first.stderr
        after_first = urdf.read_text()
        second = armtool(*base, "--margin", "3")
        assert second.returncode == 0, second.stderr
        assert "arm.urdf.bak.1" in second.stderr
    assert (tmp_path / "arm.urdf.bak").read_text() == original
    assert (tmp_path / "arm.urdf.bak.1").read_text() == after_first


def test_unwritable_output_is_found_before_anything_moves(tmp_path: Path) -> None:
    """Issue 14: -o into a missing directory (or one that is a file) failed after the recording."""
    arm = sub_arm(tmp_path, [5])
    blocker = tmp_path / "file"
    blocker.write_text("")
    with SimBus.start(AX_ARM) as sim:
        goal = sim.peek(5, "goal_position")
        for out in (tmp_path / "missing" / "limits.yaml", blocker / "limits.yaml"):
            r = armtool(
                "limits",
                "--port",
                sim.port_path,
                "--arm",
                str(arm),
                "--mode",
                "auto",
                "--yes",
                "--speed",
                "300",
                "-o",
                str(out),
            )
            assert r.returncode == 2 and "(for -o" in r.stderr, r.stderr
            assert sim.peek(5, "goal_position") == goal and all_off(sim)
            assert sim.servo(5).overload_trips == 0


# ---------------------------------------------------------------- LeRobot calibration files
SO101 = FIXTURES / "so101_arm.yaml"


def so_arm(tmp_path: Path, ids: list[int]) -> Path:
    doc = yaml.safe_load(SO101.read_text())
    doc["joints"] = [j for j in doc["joints"] if j["id"] in ids]
    path = tmp_path / "so_arm.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


def record_manual(sim: SimBus, args: list[str], spec: PersonSpec) -> tuple[int, str, str]:
    """Run `armtool limits --mode manual` with the simulated person moving the joints."""
    moves = []
    for i in spec.ids or []:
        s = sim.servo(i).spec
        lo, hi, here = s.stop_lo_deg - spec.overshoot_deg, s.stop_hi_deg + spec.overshoot_deg, sim.true_angle_deg(i)
        moves.append((abs(here - lo) + (hi - lo) + abs(hi - (lo + hi) / 2)) / spec.speed_deg_s + 2 * spec.dwell_s)
    duration = spec.start_s + max(moves) + 2.0
    env = {**os.environ, "NO_COLOR": "1", "COLUMNS": "160"}
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "armtool",
            "limits",
            "--port",
            sim.port_path,
            "--mode",
            "manual",
            "--duration",
            f"{duration:.1f}",
            *args,
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        stdin=subprocess.DEVNULL,
        text=True,
        env=env,
    )
    try:
        assert proc.stderr is not None
        first = ""
        while "torque is off" not in first:
            line = proc.stderr.readline()
            if not line:
                break
            first += line
        Person(sim, spec).start()
        out, err = proc.communicate(timeout=duration + 30)
    finally:
        proc.kill()
    return proc.returncode, out, first + err


def test_lerobot_calibration_keeps_a_seam_crossing_range_off_the_seam(tmp_path: Path) -> None:
    """lerobot #3586/#3587: wrist_roll's travel crosses 4095 -> 0. The written offsets make the
    servo read both stops inside 0..4095, the middle near 2047, and the file's range inside them."""
    arm = so_arm(tmp_path, [1, 5])
    out = tmp_path / "so101_follower.json"
    spec = PersonSpec(start_s=0.2, speed_deg_s=200, dwell_s=0.5, ids=[1, 5])
    with SimBus.start(SO101) as sim:
        code, _, err = record_manual(sim, ["--arm", str(arm), "--lerobot-calibration", str(out)], spec)
        assert code == 0, err
        assert "wrote" in err and "LeRobot calibration" in err
        cal = json.loads(out.read_text())
        assert list(cal) == ["shoulder_pan", "wrist_roll"]
        assert all(list(v) == ["id", "drive_mode", "homing_offset", "range_min", "range_max"] for v in cal.values())
        for name, entry in cal.items():
            sid = entry["id"]
            assert -2047 <= entry["homing_offset"] <= 2047
            sim.poke(sid, "homing_offset", entry["homing_offset"])  # what LeRobot writes at connect
            lo, hi = sim.stop_ticks(sid)
            assert lo < hi, f"{name}: stops {lo}..{hi} still straddle the seam"
            margin = math.ceil(2.0 / (360 / 4096))  # the default --margin, in ticks
            assert abs(entry["range_min"] - (lo + margin)) <= 3 and abs(entry["range_max"] - (hi - margin)) <= 3
            assert abs((lo + hi) / 2 - 2047) <= 3
        assert all_off(sim)


def test_lerobot_calibration_refuses_before_moving(tmp_path: Path) -> None:
    """An AX-12A has no homing offset: refused after identifying, before any joint moves; a bad
    output directory is refused before the bus opens."""
    arm = sub_arm(tmp_path, [5])
    with SimBus.start(AX_ARM) as sim:
        goal = sim.peek(5, "goal_position")
        r = armtool(
            "limits",
            "--port",
            sim.port_path,
            "--arm",
            str(arm),
            "--mode",
            "auto",
            "--yes",
            "--speed",
            "300",
            "--lerobot-calibration",
            str(tmp_path / "cal.json"),
        )
        assert r.returncode == 2 and "AX-12A has no homing offset register" in r.stderr, r.stderr
        assert sim.peek(5, "goal_position") == goal and all_off(sim) and not (tmp_path / "cal.json").exists()
        r = armtool(
            "limits",
            "--port",
            sim.port_path,
            "--arm",
            str(arm),
            "--mode",
            "auto",
            "--yes",
            "--lerobot-calibration",
            str(tmp_path / "missing" / "cal.json"),
        )
        assert r.returncode == 2 and "(for --lerobot-calibration" in r.stderr, r.stderr
    r = armtool("limits", "--port", "/dev/null", "--ids", "1", "--mode", "auto", "--lerobot-calibration", "x.json")
    assert r.returncode == 2 and "need --arm" in r.stderr


def test_lerobot_calibration_refuses_an_unconfirmed_end_but_keeps_the_yaml(tmp_path: Path) -> None:
    """Auto mode cannot find a stop for wrist_roll (the seam): no LeRobot file unless it is
    declared full-turn, which gives it LeRobot's 0..4095."""
    arm = so_arm(tmp_path, [5])
    out, cal = tmp_path / "limits.yaml", tmp_path / "cal.json"
    with SimBus.start(SO101) as sim:
        base = [
            "limits",
            "--port",
            sim.port_path,
            "--arm",
            str(arm),
            "--mode",
            "auto",
            "--yes",
            "--speed",
            "300",
            "-o",
            str(out),
            "--lerobot-calibration",
            str(cal),
        ]
        r = armtool(*base)
        assert (
            r.returncode == 2 and "unconfirmed ends on wrist_roll" in r.stderr and "limits YAML was written" in r.stderr
        )
        assert out.exists() and not cal.exists()
        r = armtool(*base, "--lerobot-full-turn", "wrist_roll")
        assert r.returncode == 0, r.stderr
        entry = json.loads(cal.read_text())["wrist_roll"]
        assert (entry["range_min"], entry["range_max"]) == (0, 4095) and abs(entry["homing_offset"]) <= 2047
        r = armtool(*base, "--lerobot-full-turn", "elbow")
        assert r.returncode == 2 and "--lerobot-full-turn: elbow not in the arm file" in r.stderr


def test_from_lerobot_converts_and_checks_against_the_arm(tmp_path: Path) -> None:
    arm = so_arm(tmp_path, [1, 4])
    cal = tmp_path / "cal.json"
    with SimBus.start(SO101) as sim:
        base = ["limits", "--port", sim.port_path, "--arm", str(arm), "--mode", "auto", "--yes", "--speed", "300"]
        r = armtool(*base, "--lerobot-calibration", str(cal))
        assert r.returncode == 0, r.stderr
        doc = json.loads(cal.read_text())
        # the file against the same arm: every motor within the recording
        r = armtool(*base, "--from-lerobot", str(cal))
        assert r.returncode == 0, r.stderr
        assert "against the recorded ranges" in r.stderr and r.stderr.count(" ok") >= 2
        assert "LeRobot will offer to write the file" in r.stderr  # the servos still hold offset 0
        # a file whose wrist_flex range reaches 100 ticks past the real stop
        doc["wrist_flex"]["range_max"] += 100
        wide = tmp_path / "wide.json"
        wide.write_text(json.dumps(doc, indent=4))
        r = armtool(*base, "--from-lerobot", str(wide))
        assert r.returncode == 1, r.stderr
        assert "file reaches past the recorded stop" in r.stderr
        assert all_off(sim)
    # without a bus: the file's ranges as limits, in radians of the arm file's zero/direction
    out = tmp_path / "limits.yaml"
    r = armtool("limits", "--from-lerobot", str(cal), "--arm", str(arm), "--margin", "0", "-o", str(out))
    assert r.returncode == 0, r.stderr
    rows = {row["name"]: row for row in yaml.safe_load(out.read_text())["joints"]}
    for name, entry in json.loads(cal.read_text()).items():
        row = rows[name]
        assert (row["raw_min_ticks"], row["raw_max_ticks"]) == (entry["range_min"], entry["range_max"])
        assert row["method"] == "lerobot" and row["homing_offset"] == entry["homing_offset"]
        assert math.isclose(row["lower_rad"], (entry["range_min"] - 2048) * 2 * math.pi / 4096, abs_tol=1e-5)


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda d: d.pop("wrist_flex"), "motor(s) wrist_flex of the arm file are missing"),
        (lambda d: d["wrist_flex"].update(range_min=12.5), "wrist_flex.range_min must be a whole number of ticks"),
        (lambda d: d["wrist_flex"].update(range_min=4000), "range_min 4000 is not below range_max"),
        (
            lambda d: d["wrist_flex"].update(homing_offset=-2100),
            "wrist_flex.homing_offset -2100 does not fit the register",
        ),
    ],
)
def test_from_lerobot_bad_files_exit_2_and_write_nothing(tmp_path: Path, edit: Any, message: str) -> None:
    arm = so_arm(tmp_path, [1, 4])
    doc = {
        "shoulder_pan": {"id": 1, "drive_mode": 0, "homing_offset": 0, "range_min": 800, "range_max": 3300},
        "wrist_flex": {"id": 4, "drive_mode": 0, "homing_offset": 0, "range_min": 850, "range_max": 3250},
    }
    edit(doc)
    cal = tmp_path / "cal.json"
    cal.write_text(json.dumps(doc, indent=4))
    out = tmp_path / "limits.yaml"
    r = armtool("limits", "--from-lerobot", str(cal), "--arm", str(arm), "-o", str(out))
    assert r.returncode == 2 and message in r.stderr and str(cal) in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and not out.exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (["--ids", "1", "--mode", "auto"], "--port is required"),
        (["--port", "/dev/null", "--ids", "1"], "--mode is required"),
        (["--from-lerobot", "cal.json", "--ids", "1"], "need --arm"),
        (
            ["--from-lerobot", "cal.json", "--arm", "a.yaml", "--mode", "auto"],
            "--mode records the arm: it needs --port",
        ),
        (["--from-lerobot", "cal.json", "--arm", "a.yaml", "--port", "/dev/null"], "--mode is required with --port"),
        (
            ["--from-lerobot", "c.json", "--arm", "a.yaml", "--lerobot-calibration", "o.json"],
            "give one of --lerobot-calibration",
        ),
        (["--arm", "a.yaml", "--lerobot-calibration", "o.json"], "needs --port and --mode"),
        (
            ["--port", "/dev/null", "--mode", "auto", "--arm", "a.yaml", "--lerobot-full-turn", "x"],
            "applies to --lerobot-calibration",
        ),
    ],
)
def test_lerobot_usage_errors_before_touching_anything(args: list[str], message: str) -> None:
    r = armtool("limits", *args)
    assert r.returncode == 2 and message in r.stderr, r.stderr


def test_lerobot_on_dynamixel_recorded_under_an_offset(tmp_path: Path) -> None:
    """An XL430 that already holds Homing_Offset 500 (present = encoder + offset): the file's offset
    and range must describe the same physical stops, and --from-lerobot must agree with the arm."""
    cfg = yaml.safe_load((FIXTURES / "xl430_arm.yaml").read_text())
    cfg["joints"] = [dict(j, homing_offset=500) for j in cfg["joints"] if j["id"] == 11]
    arm = tmp_path / "x_arm.yaml"
    arm.write_text(yaml.safe_dump(cfg))
    cal = tmp_path / "koch_follower.json"
    with SimBus.start(arm) as sim:
        lo, hi = sim.stop_ticks(11)
        assert (lo, hi) == (1200, 3900)  # encoder stops 700..3400, read + 500
        base = ["limits", "--port", sim.port_path, "--arm", str(arm), "--mode", "auto", "--yes", "--speed", "300"]
        r = armtool(*base, "--lerobot-calibration", str(cal), "--margin", "0")
        assert r.returncode == 0, r.stderr
        entry = json.loads(cal.read_text())["base"]
        assert -1024 <= entry["homing_offset"] <= 1024  # Position Control Mode ignores anything else
        sim.poke(11, "homing_offset", entry["homing_offset"])
        lo, hi = sim.stop_ticks(11)
        assert (
            abs(entry["range_min"] - lo) <= 2 and abs(entry["range_max"] - hi) <= 2 and abs((lo + hi) / 2 - 2047) <= 2
        )
        sim.poke(11, "homing_offset", 500)  # the servo back at its old offset: the file must still fit the arm
        r = armtool(*base, "--from-lerobot", str(cal))
        assert r.returncode == 0 and "differ from the file on base (offset 500" in r.stderr, r.stderr


def test_from_lerobot_offset_ignored_in_position_mode_is_refused_before_recording(tmp_path: Path) -> None:
    """A Dynamixel X in Position Control Mode ignores an offset outside ±1024 (e-manual): such a file
    cannot describe this arm, found once the bus is read, before anything moves."""
    cfg = yaml.safe_load((FIXTURES / "xl430_arm.yaml").read_text())
    cfg["joints"] = [j for j in cfg["joints"] if j["id"] == 11]
    arm = tmp_path / "x_arm.yaml"
    arm.write_text(yaml.safe_dump(cfg))
    cal = tmp_path / "koch.json"
    cal.write_text(
        json.dumps({"base": {"id": 11, "drive_mode": 0, "homing_offset": 1500, "range_min": 700, "range_max": 3400}})
    )
    with SimBus.start(arm) as sim:
        goal = sim.peek(11, "goal_position")
        r = armtool(
            "limits", "--port", sim.port_path, "--arm", str(arm), "--mode", "auto", "--yes", "--from-lerobot", str(cal)
        )
        assert r.returncode == 2 and "base.homing_offset 1500 does not fit the register (-1024..1024)" in r.stderr, (
            r.stderr
        )
        assert sim.peek(11, "goal_position") == goal and all_off(sim)


def test_in_place_urdf_keeps_crlf_and_its_backup_is_the_original_bytes(tmp_path: Path) -> None:
    arm = sub_arm(tmp_path, [5])
    urdf = tmp_path / "crlf.urdf"
    original = "\ufeff".encode() + (FIXTURES / "ax12_arm.urdf").read_bytes().replace(b"\r\n", b"\n").replace(
        b"\n", b"\r\n"
    )
    urdf.write_bytes(original)
    with SimBus.start(AX_ARM) as sim:
        r = armtool(
            "limits",
            "--port",
            sim.port_path,
            "--arm",
            str(arm),
            "--mode",
            "auto",
            "--yes",
            "--speed",
            "300",
            "-o",
            str(tmp_path / "limits.yaml"),
            "--urdf",
            str(urdf),
            "--in-place",
            "--allow-widen",
        )
        assert r.returncode == 0, r.stderr
        assert all_off(sim)
    assert (tmp_path / "crlf.urdf.bak").read_bytes() == original
    new = urdf.read_bytes()
    assert new != original and new.startswith("\ufeff".encode())
    assert new.count(b"\n") == new.count(b"\r\n") == original.count(b"\r\n")


def test_urdf_xacro_takes_the_robot_options(tmp_path: Path) -> None:
    """A xacro --urdf is expanded with --xacro-arg and written whole with --urdf-out; --in-place refuses it."""
    arm = so_arm(tmp_path, [1, 4])
    doc = {
        "shoulder_pan": {"id": 1, "drive_mode": 0, "homing_offset": 0, "range_min": 800, "range_max": 3300},
        "wrist_flex": {"id": 4, "drive_mode": 0, "homing_offset": 0, "range_min": 850, "range_max": 3250},
    }
    cal = tmp_path / "cal.json"
    cal.write_text(json.dumps(doc))
    joint = (
        '<joint name="${{prefix}}{0}" type="revolute"><parent link="${{prefix}}{1}"/><child link="${{prefix}}{2}"/>'
        '<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>'
    )
    xacro = tmp_path / "so.urdf.xacro"
    xacro.write_text(
        '<robot name="so" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:property name="prefix" value="$(arg prefix)"/>\n'
        '<link name="${prefix}a"/><link name="${prefix}b"/><link name="${prefix}c"/>\n'
        + joint.format("shoulder_pan", "a", "b")
        + joint.format("wrist_flex", "b", "c")
        + "\n</robot>\n"
    )
    out = tmp_path / "so.urdf"
    base = (
        "limits",
        "--from-lerobot",
        str(cal),
        "--arm",
        str(arm),
        "-o",
        str(tmp_path / "l.yaml"),
        "--urdf",
        str(xacro),
    )
    r = armtool(*base, "--urdf-out", str(out))
    assert r.returncode == 2 and "--xacro-arg" in r.stderr, r.stderr  # prefix has no value
    r = armtool(*base, "--urdf-out", str(out), "--xacro-arg", "prefix:=")
    assert r.returncode == 0, r.stderr
    assert '<joint name="shoulder_pan"' in out.read_text() and "${" not in out.read_text()
    r = armtool(*base, "--in-place", "--xacro-arg", "prefix:=")
    assert r.returncode == 2 and "--in-place cannot edit a xacro" in r.stderr, r.stderr
