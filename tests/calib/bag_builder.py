"""Small ROS bags written with rosbags' own writers: a simulated arm that stops at known poses.

Nothing recorded is shipped: the motion is min-jerk moves between STOPS, each held for
HOLD_S seconds; /joint_states at 50 Hz with 12-bit encoder quantization and noise; images at
5 Hz whose grey level encodes the frame index (so a test can tell which frame was taken); the
bag receives each message 40-60 ms after its header stamp.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

JOINTS = ["joint1", "joint2", "joint3", "joint4", "joint5", "joint6"]
HOLD_S = 1.5
MOVE_S = 1.2
START_S = 100.0  # header stamps start here (seconds)
TICK = 2 * np.pi / 4096


@dataclass
class Motion:
    t: np.ndarray  # joint message stamps, s
    q: np.ndarray  # (N, 6) readings
    v: np.ndarray  # (N, 6) velocities
    stops: np.ndarray  # (K, 6) true stop poses
    holds: list[tuple[float, float]]  # (start, end) of each stop, s from START_S


def simulate_motion(n_stops: int = 4, rate_hz: float = 50.0, seed: int = 0, lead_in_s: float = 0.3) -> Motion:
    rng = np.random.default_rng(seed)
    stops = rng.uniform(-1.0, 1.0, (n_stops, len(JOINTS)))
    holds, segments = [], []
    t = lead_in_s
    prev = stops[0] + rng.uniform(-0.5, 0.5, len(JOINTS))
    for stop in stops:
        segments.append((t, t + MOVE_S, prev, stop))
        t += MOVE_S
        holds.append((t, t + HOLD_S))
        t += HOLD_S
        prev = stop
    segments.append((t, t + MOVE_S, prev, prev + 0.4))
    end = t + MOVE_S + 0.3
    ts = np.arange(0.0, end, 1.0 / rate_hz)
    q = np.empty((len(ts), len(JOINTS)))
    v = np.zeros_like(q)
    q[:] = segments[0][2]
    for a, b, q0, q1 in segments:
        inside = (ts >= a) & (ts < b)
        s = (ts[inside] - a) / (b - a)
        q[inside] = q0 + (q1 - q0) * (10 * s**3 - 15 * s**4 + 6 * s**5)[:, None]
        v[inside] = (q1 - q0) * ((30 * s**2 - 60 * s**3 + 30 * s**4) / (b - a))[:, None]
        q[ts >= b] = q1
    readings = np.round((q + rng.normal(0, 2e-4, q.shape)) / TICK) * TICK
    return Motion(ts, readings, v + rng.normal(0, 1e-3, v.shape), stops, holds)


def frame_image(k: int, encoding: str) -> np.ndarray:
    img = np.full((24, 32), 40 + (k * 7) % 200, np.uint8)
    return img if encoding == "mono8" else np.dstack([img, img, img])


def frame_index(image: np.ndarray, n_frames: int) -> int:
    """The frame whose grey level this image has."""
    level = int(np.median(image if image.ndim == 2 else image[..., 0]))
    return next(k for k in range(n_frames) if 40 + (k * 7) % 200 == level)


def write_bag(
    path: Path,
    kind: str,
    motion: Motion,
    *,
    image_topic: str = "/camera/image_raw",
    image_mode: str = "bgr8",
    joint_names: list[str] | None = None,
    camera_info: bool = False,
    zero_stamps: bool = False,
    image_rate_hz: float = 5.0,
    image_times: list[float] | None = None,
) -> list[float]:
    """Write a bag of `kind` ros1 | sqlite3 | mcap; return the image header stamps (s from START_S).
    Images are taken at `image_rate_hz`, or at `image_times` (s from START_S) when given."""
    from rosbags.typesys import Stores, get_typestore

    ros1 = kind == "ros1"
    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    Time = store.types["builtin_interfaces/msg/Time"]
    Header = store.types["std_msgs/msg/Header"]
    JointState = store.types["sensor_msgs/msg/JointState"]
    Image = store.types["sensor_msgs/msg/Image"]
    Compressed = store.types["sensor_msgs/msg/CompressedImage"]
    CameraInfo = store.types["sensor_msgs/msg/CameraInfo"]
    ROI = store.types["sensor_msgs/msg/RegionOfInterest"]

    def header(t: float) -> object:
        sec, nsec = (0, 0) if zero_stamps else (int(START_S + t), int(round(((START_S + t) % 1) * 1e9)) % 1_000_000_000)
        time = Time(sec=sec, nanosec=nsec)
        return Header(seq=0, stamp=time, frame_id="cam") if ros1 else Header(stamp=time, frame_id="cam")

    rng = np.random.default_rng(1)
    names = joint_names or JOINTS
    image_stamps = list(np.arange(0.05, motion.t[-1], 1.0 / image_rate_hz)) if image_times is None else image_times
    events: list[tuple[float, str, object]] = []
    for t, q, v in zip(motion.t, motion.q, motion.v):
        events.append(
            (t, "/joint_states", JointState(header=header(t), name=names, position=q, velocity=v, effort=np.zeros(0)))
        )
    for k, t in enumerate(image_stamps):
        if image_mode == "jpeg":
            _ok, buf = cv2.imencode(".jpg", frame_image(k, "bgr8"), [cv2.IMWRITE_JPEG_QUALITY, 98])
            msg = Compressed(header=header(t), format="bgr8; jpeg compressed bgr8", data=buf.reshape(-1))
        else:
            img = frame_image(k, image_mode)
            ch = 1 if image_mode == "mono8" else 3
            msg = Image(
                header=header(t),
                height=24,
                width=32,
                encoding=image_mode,
                is_bigendian=0,
                step=32 * ch,
                data=img.reshape(-1),
            )
        events.append((t, image_topic, msg))
    if camera_info:
        K = np.array([40.0, 0, 15.5, 0, 40.0, 11.5, 0, 0, 1])
        fields = dict(
            header=header(0.0),
            height=24,
            width=32,
            distortion_model="plumb_bob",
            binning_x=0,
            binning_y=0,
            roi=ROI(x_offset=0, y_offset=0, height=0, width=0, do_rectify=False),
        )
        if ros1:
            info = CameraInfo(**fields, D=np.zeros(5), K=K, R=np.eye(3).reshape(-1), P=np.zeros(12))
        else:
            info = CameraInfo(**fields, d=np.zeros(5), k=K, r=np.eye(3).reshape(-1), p=np.zeros(12))
        events.append((0.0, "/camera/camera_info", info))
    events.sort(key=lambda e: e[0])
    types = {
        "/joint_states": "sensor_msgs/msg/JointState",
        image_topic: "sensor_msgs/msg/CompressedImage" if image_mode == "jpeg" else "sensor_msgs/msg/Image",
        "/camera/camera_info": "sensor_msgs/msg/CameraInfo",
    }
    if ros1:
        from rosbags.rosbag1 import Writer as Writer1

        with Writer1(path) as writer:
            conns = {
                topic: writer.add_connection(topic, types[topic], typestore=store) for topic in {e[1] for e in events}
            }
            for t, topic, msg in events:
                latency = rng.uniform(0.04, 0.06)
                writer.write(conns[topic], int((START_S + t + latency) * 1e9), store.serialize_ros1(msg, types[topic]))
    else:
        from rosbags.rosbag2 import StoragePlugin
        from rosbags.rosbag2 import Writer as Writer2

        plugin = StoragePlugin.MCAP if kind == "mcap" else StoragePlugin.SQLITE3
        with Writer2(path, version=9, storage_plugin=plugin) as writer:
            conns = {
                topic: writer.add_connection(topic, types[topic], typestore=store) for topic in {e[1] for e in events}
            }
            for t, topic, msg in events:
                latency = rng.uniform(0.04, 0.06)
                writer.write(conns[topic], int((START_S + t + latency) * 1e9), store.serialize_cdr(msg, types[topic]))
    return [float(s) for s in image_stamps]
