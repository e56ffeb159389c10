"""Limits core against the simulator: auto seek, manual with the scripted person, conversion, URDF edit."""

from __future__ import annotations

import math
import time
from pathlib import Path

import pytest

from armtool.errors import ArmtoolError
from armtool.servo import limits as L
from armtool.servo.bus import open_bus
from armtool.servo.guard import TorqueGuard
from armtool.servo.models import by_name
from armtool.servo.sim import Person, PersonSpec, SimBus, load_sim_config
from tests.servo.conftest import FIXTURES


def _auto(
    fixture: str, ids: list[int] | None = None, **params: float
) -> list[tuple[L.JointRange, tuple[int, int], int]]:
    arm = L.load_arm(FIXTURES / fixture)
    joints = [j for j in arm.joints if ids is None or j.id in ids]
    out = []
    with SimBus.start(FIXTURES / fixture) as sim, open_bus(sim.port_path, arm.protocol or "", arm.baud or 0) as bus:
        bus.identify([j.id for j in joints])
        with TorqueGuard(bus) as guard:
            for j in joints:
                r = L.seek_joint(bus, guard, j, L.AutoParams(speed_deg_s=300, **params))
                out.append((r, sim.stop_ticks(j.id), sim.servo(j.id).overload_trips))
        assert all(sim.peek(j.id, "torque_enable") == 0 for j in joints)
        assert all(sim.peek(j.id, "torque_limit") == sim.servo(j.id).model.reg("torque_limit").default for j in joints)
    return out


def test_auto_finds_every_ax12_stop_within_2_ticks_without_overload() -> None:
    for r, (lo, hi), trips in _auto("ax12_arm.yaml"):
        assert abs(r.raw_min - lo) <= 2 and abs(r.raw_max - hi) <= 2, (r.joint.name, r.raw_min, r.raw_max, lo, hi)
        assert trips == 0
        assert r.evidence["reason_min"].startswith("stall") and r.evidence["reason_max"].startswith("stall")


@pytest.mark.parametrize(
    "fixture, ids", [("so101_arm.yaml", [1, 3, 6]), ("xl430_arm.yaml", [11, 13]), ("koch_arm.yaml", [11, 12, 13])]
)
def test_auto_on_feetech_and_protocol2(fixture: str, ids: list[int]) -> None:
    for r, (lo, hi), trips in _auto(fixture, ids):
        assert abs(r.raw_min - lo) <= 2 and abs(r.raw_max - hi) <= 2 and trips == 0


def test_auto_handles_an_overload_trip_and_rearms() -> None:
    cfg = load_sim_config(FIXTURES / "ax12_arm.yaml")
    cfg.overload_time_s = 0.05  # trips (~0.17 s after contact) before the 0.4 s stall window ends
    cfg.servos = cfg.servos[4:]
    with SimBus.start(cfg) as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([5])
        with TorqueGuard(bus) as guard:
            r = L.seek_joint(bus, guard, L.Joint("gripper", 5), L.AutoParams(speed_deg_s=300, stall_window_s=0.4))
        lo, hi = sim.stop_ticks(5)
        assert sim.servo(5).overload_trips >= 1
        assert "overload" in r.evidence["reason_min"] + r.evidence["reason_max"]
        assert abs(r.raw_min - lo) <= 2 and abs(r.raw_max - hi) <= 2
        assert sim.peek(5, "torque_enable") == 0 and sim.peek(5, "torque_limit") == 1023


def _manual(
    fixture: str, ids: list[int], record_s: float | None, speed: float = 200.0
) -> tuple[list[L.JointRange], dict[int, tuple[int, int]]]:
    arm = L.load_arm(FIXTURES / fixture)
    joints = [j for j in arm.joints if j.id in ids]
    with SimBus.start(FIXTURES / fixture) as sim, open_bus(sim.port_path, arm.protocol or "", arm.baud or 0) as bus:
        bus.identify(ids)
        person = Person(sim, PersonSpec(start_s=0.1, speed_deg_s=speed, dwell_s=0.5, ids=ids)).start()
        rec = L.ManualRecorder(bus, joints)
        end = time.monotonic() + (record_s if record_s is not None else person.remaining_s() + 0.2)
        while time.monotonic() < end:
            rec.sample()
            time.sleep(0.01)
        return rec.results(), {i: sim.stop_ticks(i) for i in ids}


def test_manual_with_the_person_finds_stops_within_2_ticks() -> None:
    results, stops = _manual("ax12_arm.yaml", [1, 2, 3], None)
    for r in results:
        lo, hi = stops[r.joint.id]
        assert abs(r.raw_min - lo) <= 2 and abs(r.raw_max - hi) <= 2
        assert r.confirmed and r.evidence["dwell_min_s"] >= 0.3


def test_manual_stopped_early_marks_the_unreached_end_unconfirmed() -> None:
    results, stops = _manual("ax12_arm.yaml", [1], 0.9)
    (r,) = results
    assert not r.evidence["confirmed_max"]
    assert not r.confirmed
    assert r.raw_max < stops[1][1] - 50


def test_manual_tolerates_a_lost_reply_but_not_a_silent_id() -> None:
    arm = L.load_arm(FIXTURES / "ax12_arm.yaml")
    joints = [j for j in arm.joints if j.id in (1, 2)]
    with SimBus.start(FIXTURES / "ax12_arm.yaml") as sim, open_bus(sim.port_path, "dxl1", 1000000) as bus:
        bus.identify([1, 2])
        rec = L.ManualRecorder(bus, joints, max_silence_s=0.3)
        rec.sample()
        sim.faults.drop_next = bus.retries  # every try of the next read is lost: one whole sample of ID 1
        rec.sample()
        rec.sample()
        assert rec.missed == {1: 1, 2: 0} and [len(rec.traces[i]) for i in (1, 2)] == [2, 3]
        sim.faults.missing_ids = {2}
        with pytest.raises(ArmtoolError, match=r"ID 2 \('shoulder_lift'\) has not answered for 0\.[3-9]"):
            deadline = time.monotonic() + 5
            while time.monotonic() < deadline:
                rec.sample()
                time.sleep(0.01)


def test_manual_unwraps_the_4096_tick_seam() -> None:
    results, stops = _manual("so101_arm.yaml", [5], None, speed=300.0)
    (r,) = results
    lo, hi = stops[5]  # reported ticks: hi wrapped past 4095
    assert hi < lo and r.crosses_seam
    assert abs(r.raw_min - lo) <= 2 and abs(r.raw_max - (hi + 4096)) <= 2
    row = L.convert(r, 2.0)
    assert row["zero_ticks"] == 4 + 4096 and row["evidence"]["crosses_seam"]
    span = row["upper_rad"] - row["lower_rad"]
    assert abs(span - (row["safe_max_ticks"] - row["safe_min_ticks"]) * 2 * math.pi / 4096) < 1e-5


def test_convert_margin_zero_and_direction() -> None:
    model = by_name("AX-12A")
    r = L.JointRange(L.Joint("j", 1, model, 512, -1), model, 92, 914, "auto")
    row = L.convert(r, 2.0)
    assert (row["safe_min_ticks"], row["safe_max_ticks"]) == (99, 907)  # 2 deg = 6.8 -> 7 ticks
    rad = math.radians(300 / 1023)
    assert row["lower_rad"] == pytest.approx(-(907 - 512) * rad, abs=1e-6)
    assert row["upper_rad"] == pytest.approx((512 - 99) * rad, abs=1e-6)
    with pytest.raises(ArmtoolError, match="too small"):
        L.convert(L.JointRange(r.joint, model, 500, 510, "auto"), 2.0)


URDF = """<robot name="r">
  <!-- keep me -->
  <joint name="a" type="revolute">
    <limit lower="-2.6" upper="2.6" effort="1.5" velocity="5.9"/>  <!-- nominal -->
  </joint>
  <joint name="b" type="revolute">
    <axis xyz="0 0 1"/>
  </joint>
  <!-- <joint name="a" type="revolute"><limit lower="9" upper="9"/></joint> -->
  <joint name="c" type="continuous"/>
</robot>
"""


def test_patch_urdf_keeps_text_and_comments() -> None:
    out = L.patch_urdf(URDF, {"a": (-1.25, 2.0), "b": (-0.5, 0.5)})
    assert '<limit lower="-1.25" upper="2" effort="1.5" velocity="5.9"/>  <!-- nominal -->' in out
    assert '    <limit lower="-0.5" upper="0.5" effort="1.0" velocity="1.0"/>\n  </joint>' in out
    assert '<limit lower="9" upper="9"/>' in out and "<!-- keep me -->" in out
    assert len(out.splitlines()) == len(URDF.splitlines()) + 1


def test_patch_urdf_refusals() -> None:
    with pytest.raises(ArmtoolError, match="outside the URDF's: a: measured -3.0000..2.0000"):
        L.patch_urdf(URDF, {"a": (-3.0, 2.0)})
    assert 'lower="-3"' in L.patch_urdf(URDF, {"a": (-3.0, 2.0)}, allow_widen=True)
    with pytest.raises(ArmtoolError, match="joint.s. zz not in"):
        L.patch_urdf(URDF, {"zz": (0, 1)})
    with pytest.raises(ArmtoolError, match="not revolute"):
        L.patch_urdf(URDF, {"c": (0, 1)})


def test_load_arm_errors(tmp_path: Path) -> None:
    bad = tmp_path / "arm.yaml"
    bad.write_text("joints:\n  - {id: 1, direction: 2}\n")
    with pytest.raises(ArmtoolError, match="direction must be 1 or -1"):
        L.load_arm(bad)
    bad.write_text("joints: [\n")
    with pytest.raises(ArmtoolError, match="not valid YAML"):
        L.load_arm(bad)
    assert L.parse_ids("1-3,7") == [1, 2, 3, 7]
    with pytest.raises(ArmtoolError):
        L.parse_ids("1,1")


def test_auto_marks_a_servo_range_end_unconfirmed() -> None:
    """SO-101 wrist_roll: its travel crosses the seam, the low seek ends at tick 0, which is no stop."""
    [(r, _stops, trips)] = _auto("so101_arm.yaml", [5])
    ends = {k: r.evidence[f"reason_{k}"] for k in ("min", "max")}
    assert any(v.startswith(L.RANGE_END) for v in ends.values()), ends
    for k, reason in ends.items():
        assert r.evidence[f"confirmed_{k}"] == (not reason.startswith(L.RANGE_END))
    assert not r.confirmed and trips == 0


TRANSMISSION = """<transmission name="t_{j}">
    <type>transmission_interface/SimpleTransmission</type>
    <joint name="{j}"><hardwareInterface>hardware_interface/PositionJointInterface</hardwareInterface></joint>
    <actuator name="m_{j}"><mechanicalReduction>1</mechanicalReduction></actuator>
  </transmission>"""


@pytest.mark.parametrize("where", ["before", "after"])
def test_patch_urdf_with_transmissions(where: str) -> None:
    """<joint name> inside a <transmission> (no type) is a reference, not the joint: the limit goes
    into the top-level joint, and the transmission is kept byte for byte."""
    from lxml import etree

    blocks = "\n  ".join(TRANSMISSION.format(j=j) for j in ("a", "b"))
    text = URDF.replace("<robot", "<robot", 1)
    if where == "before":
        text = text.replace('  <joint name="a"', f'  {blocks}\n  <joint name="a"', 1)
    else:
        text = text.replace("</robot>", f"  {blocks}\n</robot>")
    assert text.count("<transmission") == 2
    out = L.patch_urdf(text, {"a": (-1.25, 2.0), "b": (-0.5, 0.5)})
    root = etree.fromstring(out.encode())
    for name, (lo, hi) in {"a": (-1.25, 2.0), "b": (-0.5, 0.5)}.items():
        (joint,) = root.xpath(f"/robot/joint[@name='{name}']")
        assert (float(joint.find("limit").get("lower")), float(joint.find("limit").get("upper"))) == (lo, hi)
    assert not root.xpath("//transmission//limit")
    for j in ("a", "b"):
        assert TRANSMISSION.format(j=j) in out
