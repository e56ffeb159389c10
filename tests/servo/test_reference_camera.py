"""The camera reference: an AprilTag on the horn of the simulated servo, rendered by the calibrate
work's renderer and found by its detector, aligned to the servo's frame by two moves."""

from __future__ import annotations

import math
import sys
from typing import Any

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.servo.bus import open_bus
from armtool.servo.guard import TorqueGuard
from armtool.servo.lut.measure import Driver, Motion, align_reference, measure, plan_commands, speed_register
from armtool.servo.reference import CameraReference, open_reference
from armtool.servo.sim import SimBus

render = pytest.importorskip("armtool.calib.simulation.render")
camera_mod = pytest.importorskip("armtool.calib.model.camera")
pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="the simulator needs a pty")

CAM = camera_mod.CameraModel(np.array([[500.0, 0, 160], [0, 500.0, 120], [0, 0, 1]]), np.zeros(0), 320, 240)


def tag_pose(deg: float, tilt_deg: float = 0.0) -> Any:
    """The tag facing the camera 25 cm away, turned by `deg` about its normal, the axis tilted by `tilt_deg`."""
    t, a = math.radians(deg), math.radians(tilt_deg)
    rz = np.array([[math.cos(t), -math.sin(t), 0], [math.sin(t), math.cos(t), 0], [0, 0, 1]])
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    pose = np.eye(4)
    pose[:3, :3] = np.diag([1.0, -1.0, -1.0]) @ rx @ rz
    pose[:3, 3] = [0.01, 0.0, 0.25]
    return pose


class HornCamera:
    """cv2.VideoCapture stand-in: renders the tag at an angle that follows `angle_deg()`."""

    def __init__(self, angle_deg: Any, tilt_deg: float = 0.0) -> None:
        self.angle_deg = angle_deg
        self.tilt_deg = tilt_deg
        self.rng = np.random.default_rng(5)

    def read(self) -> tuple[bool, Any]:
        image = render.render_tag(CAM, tag_pose(self.angle_deg(), self.tilt_deg), 0.04, "tag36h11", 0, rng=self.rng)
        return image is not None, image


@pytest.mark.parametrize("intrinsics", [False, True])
def test_in_plane_and_pose_angles(intrinsics: bool) -> None:
    state = {"deg": 0.0}
    cam = HornCamera(lambda: state["deg"], tilt_deg=25.0 if intrinsics else 0.0)
    ref = CameraReference("fake", capture=cam, settle_frames=1, camera=CAM if intrinsics else None)
    got = []
    for deg in (0.0, 12.5, 90.0, 185.0, 270.0):
        state["deg"] = deg
        got.append(ref.raw_deg())
    assert np.allclose(np.array(got) - got[0], [0.0, 12.5, 90.0, 185.0, 270.0], atol=0.3)


def test_camera_measures_the_true_angle_after_alignment() -> None:
    config = {
        "protocol": "dxl1",
        "baud": 1000000,
        "return_delay": 0,
        "joints": [{"id": 1, "model": "AX-12A", "stops": [92, 914], "start": 512}],
    }
    with SimBus.start(config) as sim:
        # the camera looks at the horn from the front: it sees the servo turn the other way, from 40° off
        cam = HornCamera(lambda: 40.0 - sim.true_angle_deg(1))
        ref = CameraReference("fake", capture=cam, settle_frames=1)
        bus = open_bus(sim.port_path, "dxl1", 1000000)
        try:
            bus.identify([1])
            with TorqueGuard(bus) as guard:
                guard.set_ram(1, "moving_speed", speed_register(bus.model(1), 600))
                guard.torque_on(1)
                driver = Driver(bus, guard, 1, Motion(backoff_ticks=10, dwell_s=0.01))
                note = align_reference(driver, ref, 100, 900, "up")
                assert note is not None and note.startswith("sign -1")
                commands = plan_commands(100, 900, "up", 10, points=7)
                samples = measure(driver, ref, commands, "up", 100, 900, reads=1)
        finally:
            bus.close()
        truth = [sim.servo(1).theta_of(c) for c in commands]
        errors = [s.reference_deg - t for s, t in zip(samples, truth)]
        assert max(abs(e) for e in errors) < 0.4, errors  # tag detection ~0.1°, alignment at the middle
        assert sim.peek(1, "torque_enable") == 0


def test_a_tag_that_does_not_turn_fails_alignment() -> None:
    config = {
        "protocol": "dxl1",
        "baud": 1000000,
        "return_delay": 0,
        "joints": [{"id": 1, "model": "AX-12A", "stops": [92, 914], "start": 512}],
    }
    with SimBus.start(config) as sim:
        ref = CameraReference("fake", capture=HornCamera(lambda: 10.0), settle_frames=1)
        bus = open_bus(sim.port_path, "dxl1", 1000000)
        try:
            bus.identify([1])
            with TorqueGuard(bus) as guard:
                guard.set_ram(1, "moving_speed", speed_register(bus.model(1), 600))
                guard.torque_on(1)
                with pytest.raises(ArmtoolError, match="is the tag fixed flat on the horn"):
                    align_reference(Driver(bus, guard, 1, Motion(dwell_s=0.01)), ref, 100, 900, "up")
        finally:
            bus.close()
        assert sim.peek(1, "torque_enable") == 0


def test_tag_not_in_view_and_bad_options() -> None:
    blank = type("Blank", (), {"read": lambda self: (True, np.full((240, 320), 128, np.uint8))})()
    ref = CameraReference("fake", capture=blank, settle_frames=1)
    with pytest.raises(ArmtoolError, match="tag 0 not found"):
        ref.read_deg(1, 0)
    with pytest.raises(ArmtoolError, match="camera option 'zoom=2' not understood"):
        open_reference("camera:0,zoom=2")
    with pytest.raises(ArmtoolError, match="cannot open camera /nonexistent/video9"):
        open_reference("camera:/nonexistent/video9,tag=3")
