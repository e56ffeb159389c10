"""ROS bags into calibration datasets: `armtool calibrate import-bag`.

Users record calibration data as a bag (an image topic and `/joint_states`) while the arm stops
at each pose. This finds the windows in which the arm is settled, takes the image nearest each
window's centre, and writes an `armtool-calib-dataset/1` directory with the joint values of that
window: the "20-line script" users would otherwise write, with the checks they would skip.

Bags are read with `rosbags` (pure Python, Apache-2.0): ROS 1 `.bag` files and ROS 2 bag
directories with sqlite3 (`.db3`) or MCAP storage. Settled (`settled_windows`): every chain
joint stays within `tolerance` of where it was for at least `min_still_s`, or (`still_by =
"velocity"`) every joint's reported velocity stays below `max_velocity` that long. Position is
the default because many drivers publish no velocity, or a velocity differenced from encoder
ticks that is never quite zero. The window's joint values are the per-joint median.

The image of a window is the one nearest its centre. When the only images fall near the window's
edge (a slow camera, dropped frames, a short stop), that image may have been taken while the arm
was starting or stopping, and the camera's and the encoders' clocks differ by tens of ms: its
offset from the centre, as a fraction of the half-window (0 at the centre, 1 at the edge), is
warned about above `WARN_OFFSET_FRACTION` and the window skipped above `max_image_offset`
(`--max-image-offset`).

A recording that was interrupted is not a finished bag: ROS 2 writes metadata.yaml when
`ros2 bag record` stops (SIGTERM or a crash leave none, ros2/rosbag2#791) and `ros2 bag reindex DIR`
rebuilds it (ros2/rosbag2#1619); ROS 1 records into NAME.bag.active and writes the index last,
which `rosbag reindex` rebuilds. Such inputs are named as interrupted, with the command that fixes them.
"""

from __future__ import annotations

import logging
import shutil
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from armtool.calib.choices import Setup, StillBy
from armtool.calib.inputs.dataset import manifest_document
from armtool.calib.model.camera import Array
from armtool.calib.targets.spec import Target
from armtool.errors import ArmtoolError

log = logging.getLogger(__name__)

IMAGE_TYPES = ("sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage")
JOINT_STATE_TYPE = "sensor_msgs/msg/JointState"
CAMERA_INFO_TYPE = "sensor_msgs/msg/CameraInfo"
Clock = Literal["header stamps", "bag receive time"]  # what images and joint states were matched by


@dataclass(frozen=True)
class ImportOptions:
    image_topic: str
    joints_topic: str = "/joint_states"
    base: str | None = None
    flange: str | None = None
    intrinsics: Path | None = None
    camera_info_topic: str | None = None
    setup: Setup = Setup.EYE_TO_HAND
    target: Target = field(default_factory=Target)  # the AprilTag (family, id, size), or a board
    still_by: StillBy = StillBy.POSITION
    tolerance: float = 0.002  # rad (or m): largest change of any joint within a window
    max_velocity: float = 0.01  # rad/s (or m/s), with still_by=StillBy.VELOCITY
    min_still_s: float = 0.5
    max_image_offset: float = 0.8  # of the half-window: beyond, the window's image is refused
    # A xacro robot: its arguments and where its packages are (the dataset gets the expansion).
    xacro_args: tuple[tuple[str, str], ...] = ()
    package_paths: tuple[Path, ...] = ()


WARN_OFFSET_FRACTION = 0.5  # an image farther from its window's centre (fraction of the half-window) is warned about


@dataclass(frozen=True)
class Window:
    """A settled stretch of joint messages [first, last] (indices), its times and joint values."""

    first: int
    last: int
    start_s: float
    end_s: float
    q: Array  # per-joint median over the window

    @property
    def centre_s(self) -> float:
        return 0.5 * (self.start_s + self.end_s)


def settled_windows(
    t: Array,
    q: Array,
    min_still_s: float,
    tolerance: float | None = None,
    velocity: Array | None = None,
    max_velocity: float | None = None,
) -> list[Window]:
    """Maximal, non-overlapping windows of at least `min_still_s` in which the arm is settled.

    `t` (N,) seconds, increasing; `q` (N, J) joint positions. With `tolerance`: every joint's
    range (max − min) within the window is at most `tolerance`; found greedily from the left,
    each window as long as it stays settled. With `velocity` (N, J) and `max_velocity`: runs of
    messages whose |velocity| is at most `max_velocity` for every joint.
    """
    n = len(t)
    windows: list[Window] = []

    def make(a: int, b: int) -> Window:
        return Window(a, b, float(t[a]), float(t[b]), np.median(q[a : b + 1], axis=0))

    if velocity is not None:
        assert max_velocity is not None
        still = np.all(np.abs(velocity) <= max_velocity, axis=1)
        a = 0
        while a < n:
            if not still[a]:
                a += 1
                continue
            b = a
            while b + 1 < n and still[b + 1]:
                b += 1
            if t[b] - t[a] >= min_still_s:
                windows.append(make(a, b))
            a = b + 1
        return windows
    assert tolerance is not None
    rows = q.tolist()
    a = 0
    while a < n:
        lo, hi = list(rows[a]), list(rows[a])
        b = a
        while b + 1 < n:
            nxt = rows[b + 1]
            lo2 = [min(x, y) for x, y in zip(lo, nxt)]
            hi2 = [max(x, y) for x, y in zip(hi, nxt)]
            if max(h - l_ for h, l_ in zip(hi2, lo2)) > tolerance:
                break
            lo, hi, b = lo2, hi2, b + 1
        if t[b] - t[a] >= min_still_s:
            windows.append(make(a, b))
            a = b + 1
        else:
            a += 1
    return windows


@dataclass(frozen=True)
class ImportedSample:
    id: str
    image: str  # relative to the dataset
    start_s: float  # window, seconds from the first joint message
    end_s: float
    image_offset_s: float  # image stamp − window centre
    q: dict[str, float]

    @property
    def image_offset_fraction(self) -> float:
        """|image_offset_s| over the half-window: 0 at the window's centre, 1 at its edge."""
        return _offset_fraction(self.image_offset_s, self.start_s, self.end_s)


def _offset_fraction(offset_s: float, start_s: float, end_s: float) -> float:
    half = 0.5 * (end_s - start_s)
    return abs(offset_s) / half if half > 0 else 0.0


@dataclass
class ImportResult:
    out: Path
    samples: list[ImportedSample]
    skipped: list[tuple[float, float, str]]  # (start_s, end_s, reason)
    intrinsics_source: str
    clock: Clock
    warnings: list[str] = field(default_factory=list)

    def summary(self) -> dict[str, object]:
        """What `calibrate import-bag --format json` prints (`schema_version` 1)."""
        return {
            "schema_version": 1,
            "dataset": str(self.out),
            "samples": [
                {
                    "id": s.id,
                    "image": s.image,
                    "window_start_s": s.start_s,
                    "window_end_s": s.end_s,
                    "image_offset_s": s.image_offset_s,
                    "image_offset_fraction": s.image_offset_fraction,
                    "joints": s.q,
                }
                for s in self.samples
            ],
            "skipped_windows": [{"window_start_s": a, "window_end_s": b, "reason": r} for a, b, r in self.skipped],
            "intrinsics": self.intrinsics_source,
            "clock": self.clock,
            "warnings": self.warnings,
        }


_ROS2_STORAGE = (".db3", ".mcap")


def _ros1_reindex_hint(active: Path) -> str:
    final = active.name[: -len(".active")] if active.name.endswith(".active") else active.name
    return (
        f"rebuild its index with `rosbag reindex {active.name}`, rename it (`mv {active.name} {final}`) "
        f"and import {final}"
    )


def _ros2_interrupted(directory: Path, where: Path) -> ArmtoolError:
    return ArmtoolError(
        "the ROS 2 recording was interrupted: its directory has storage files but no metadata.yaml, which "
        "`ros2 bag record` writes when it stops",
        str(where),
        f"rebuild it with `ros2 bag reindex {directory}` (it reads the storage files), then import again",
    )


def _bag_path(bag: Path) -> Path:
    """The path rosbags opens: a ROS 1 .bag file, or a ROS 2 bag directory (with metadata.yaml).
    An interrupted recording is named as such, with the reindex command that finishes it."""
    if not bag.exists():
        active = bag.with_name(bag.name + ".active")
        if bag.suffix == ".bag" and active.is_file():
            raise ArmtoolError(
                f"bag not found, but {active.name} is there: the ROS 1 recording was interrupted before "
                "`rosbag record` wrote its index",
                str(bag),
                _ros1_reindex_hint(active),
            )
        raise ArmtoolError("bag not found", str(bag))
    if bag.is_file() and bag.suffix == ".bag":
        return bag
    if bag.is_file() and bag.name.endswith(".bag.active"):
        raise ArmtoolError(
            "an unfinished ROS 1 recording (.bag.active): `rosbag record` was stopped before it wrote the bag's index",
            str(bag),
            _ros1_reindex_hint(bag),
        )
    if bag.is_file() and bag.suffix in _ROS2_STORAGE:
        if (bag.parent / "metadata.yaml").is_file():
            return bag.parent
        raise _ros2_interrupted(bag.parent, bag)
    if bag.is_dir():
        if (bag / "metadata.yaml").is_file():
            return bag
        if any(p.suffix in _ROS2_STORAGE for p in bag.iterdir()):
            raise _ros2_interrupted(bag, bag)
        raise ArmtoolError(
            "directory has no metadata.yaml and no .db3 or .mcap storage file: not a ROS 2 bag",
            str(bag),
            "pass a ROS 1 .bag file or a ROS 2 bag directory",
        )
    raise ArmtoolError(f"not a ROS bag (expected a .bag file or a ROS 2 bag directory), got '{bag.suffix}'", str(bag))


def _stamp(msg: Any) -> float:
    stamp = msg.header.stamp
    return float(stamp.sec) + 1e-9 * float(stamp.nanosec)


def _field(msg: Any, *names: str) -> Any:
    """A message field under its ROS 2 or ROS 1 name (CameraInfo: `k` vs `K`)."""
    for name in names:
        if hasattr(msg, name):
            return getattr(msg, name)
    raise AttributeError(names[0])


def decode_image(msg: Any, msgtype: str) -> tuple[bytes, str]:
    """(file bytes, extension) of an image message. Compressed images keep their bytes (no
    re-encoding loss); raw ones become PNG (8 or 16 bit, grey or BGR)."""
    import cv2

    if msgtype.endswith("CompressedImage"):
        data = bytes(msg.data)
        ext = ".png" if data[:8] == b"\x89PNG\r\n\x1a\n" else ".jpg" if data[:2] == b"\xff\xd8" else ""
        from armtool.calib.inputs.files import check_pixels, header_size

        size = header_size(data[:65536])
        if size is not None:
            check_pixels(size[0], size[1], f"a {msg.format} image message")
        if not ext or cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED) is None:
            raise ArmtoolError(
                f"compressed image (format '{msg.format}') is neither a readable JPEG nor PNG",
                hint="compressedDepth and other codecs are not supported; record the raw or JPEG/PNG topic",
            )
        return data, ext
    image = raw_image_array(msg)
    ok, buf = cv2.imencode(".png", image)
    if not ok:
        raise ArmtoolError("cannot encode the image as PNG")
    return buf.tobytes(), ".png"


_BAYER = {
    "bayer_rggb8": "COLOR_BayerRG2BGR",
    "bayer_bggr8": "COLOR_BayerBG2BGR",
    "bayer_gbrg8": "COLOR_BayerGB2BGR",
    "bayer_grbg8": "COLOR_BayerGR2BGR",
}
_RAW_ENCODINGS = (
    "mono8",
    "8UC1",
    "mono16",
    "16UC1",
    "bgr8",
    "rgb8",
    "bgra8",
    "rgba8",
    "8UC3",
    "yuv422",
    "uyvy",
    "yuyv",
    *_BAYER,
)


def raw_image_array(msg: Any) -> NDArray[Any]:
    """A sensor_msgs/Image as an OpenCV array: grey (uint8/uint16) or BGR."""
    import cv2

    enc, h, w, step = str(msg.encoding), int(msg.height), int(msg.width), int(msg.step)
    data = np.asarray(msg.data, dtype=np.uint8)
    if enc not in _RAW_ENCODINGS:
        raise ArmtoolError(f"image encoding '{enc}' is not supported", hint="supported: " + ", ".join(_RAW_ENCODINGS))
    channels = {"bgr8": 3, "rgb8": 3, "8UC3": 3, "bgra8": 4, "rgba8": 4, "yuv422": 2, "uyvy": 2, "yuyv": 2}.get(enc, 1)
    depth = 2 if enc in ("mono16", "16UC1") else 1
    if h <= 0 or w <= 0 or step < w * channels * depth or len(data) < step * h:
        raise ArmtoolError(f"image message is inconsistent: {w}x{h}, step {step}, {len(data)} bytes")
    rows = data[: step * h].reshape(h, step)[:, : w * channels * depth]
    if depth == 2:
        dtype = np.dtype(">u2" if msg.is_bigendian else "<u2")
        return np.ascontiguousarray(rows).view(dtype).reshape(h, w).astype(np.uint16)
    img = (
        np.ascontiguousarray(rows).reshape(h, w, channels) if channels > 1 else np.ascontiguousarray(rows).reshape(h, w)
    )
    if enc == "rgb8":
        return cv2.cvtColor(img, cv2.COLOR_RGB2BGR)
    if enc == "rgba8":
        return cv2.cvtColor(img, cv2.COLOR_RGBA2BGR)
    if enc == "bgra8":
        return cv2.cvtColor(img, cv2.COLOR_BGRA2BGR)
    if enc in ("yuv422", "uyvy"):
        return cv2.cvtColor(img, cv2.COLOR_YUV2BGR_UYVY)
    if enc == "yuyv":
        return cv2.cvtColor(img, cv2.COLOR_YUV2BGR_YUYV)
    if enc in _BAYER:
        return cv2.cvtColor(img, getattr(cv2, _BAYER[enc]))
    return img


class _Bag:
    """An open bag: topics and typed messages, errors as ArmtoolError."""

    def __init__(self, path: Path) -> None:
        try:
            from rosbags.highlevel import AnyReader
            from rosbags.typesys import Stores, get_typestore
        except ImportError:
            raise ArmtoolError(
                "reading ROS bags needs the 'rosbags' package", hint="pip install 'armtool[calib]'"
            ) from None

        self.path = path
        try:
            self.reader = AnyReader([_bag_path(path)], default_typestore=get_typestore(Stores.ROS2_HUMBLE))
            self.reader.open()
        except ArmtoolError:
            raise
        except Exception as exc:  # rosbags raises its own errors, and OSError/KeyError on damaged files
            unindexed = path.suffix == ".bag" and any(
                words in str(exc) for words in ("not indexed", "index looks damaged")
            )
            raise ArmtoolError(
                f"cannot read the bag: {exc}",
                str(path),
                "the ROS 1 recording was interrupted or cut short: " + _ros1_reindex_hint(path)
                if unindexed
                else "is it a complete ROS 1 .bag or ROS 2 bag directory?",
            ) from None
        self.topics: dict[str, str] = {c.topic: c.msgtype for c in self.reader.connections}

    def close(self) -> None:
        self.reader.close()

    def require(self, topic: str, types: Sequence[str], option: str) -> str:
        if topic not in self.topics:
            from armtool.suggest import did_you_mean

            listing = ", ".join(f"{t} ({m})" for t, m in sorted(self.topics.items())) or "none"
            raise ArmtoolError(
                f"topic '{topic}' is not in the bag{did_you_mean(topic, self.topics)}",
                str(self.path),
                f"pass {option} with one of the recorded topics: {listing}",
            )
        if self.topics[topic] not in types:
            raise ArmtoolError(
                f"topic '{topic}' is {self.topics[topic]}, not {' or '.join(types)}",
                str(self.path),
                f"pass {option} with a topic of that type",
            )
        return self.topics[topic]

    def messages(self, topic: str) -> Iterator[tuple[int, Any]]:
        """(bag receive time ns, deserialized message) of one topic, in bag order."""
        connections = [c for c in self.reader.connections if c.topic == topic]
        try:
            for connection, timestamp, raw in self.reader.messages(connections=connections):
                yield timestamp, self.reader.deserialize(raw, connection.msgtype)
        except Exception as exc:
            raise ArmtoolError(f"cannot read messages of '{topic}': {exc}", str(self.path)) from None


def _joint_series(bag: _Bag, topic: str, names: list[str]) -> tuple[Array, Array, Array, Array | None, set[str]]:
    """(header stamps, bag times, positions (N,J), velocities or None, all names seen) of the
    JointState messages that carry every joint in `names` (in that order)."""
    stamps, times, pos, vel = [], [], [], []
    seen: set[str] = set()
    has_velocity = True
    for timestamp, msg in bag.messages(topic):
        msg_names = list(msg.name)
        seen.update(msg_names)
        index = {n: i for i, n in enumerate(msg_names)}
        if not all(n in index for n in names):
            continue
        cols = [index[n] for n in names]
        position = np.asarray(msg.position, dtype=np.float64)
        if len(position) != len(msg_names):
            continue
        velocity = np.asarray(msg.velocity, dtype=np.float64)
        if len(velocity) == len(msg_names):
            vel.append(velocity[cols])
        else:
            has_velocity = False
        stamps.append(_stamp(msg))
        times.append(timestamp * 1e-9)
        pos.append(position[cols])
    q = np.array(pos).reshape(-1, len(names))
    v = np.array(vel).reshape(-1, len(names)) if has_velocity and len(vel) == len(pos) else None
    return np.array(stamps), np.array(times), q, v, seen


def _camera_info(bag: _Bag, topic: str) -> Any:
    """The first CameraInfo on `topic` with a non-zero K, as a CameraModel; None if there is none."""
    from armtool.calib.model.camera import CameraModel

    for _, msg in bag.messages(topic):
        K = np.asarray(_field(msg, "k", "K"), dtype=np.float64)
        if K.size == 9 and K[0] > 0:
            d = np.asarray(_field(msg, "d", "D"), dtype=np.float64)
            model = str(msg.distortion_model)
            if model not in ("plumb_bob", "rational_polynomial", ""):
                raise ArmtoolError(
                    f"camera_info on '{topic}' uses distortion_model '{model}'",
                    hint="only plumb_bob and rational_polynomial (OpenCV's pinhole model) are supported; pass --intrinsics",
                )
            return CameraModel(
                K.reshape(3, 3), d if d.size in (0, 4, 5, 8, 12, 14) else np.zeros(5), int(msg.width), int(msg.height)
            )
    return None


def _default_camera_info_topic(image_topic: str) -> str:
    """`/cam/image_raw` and `/cam/image_raw/compressed` → `/cam/camera_info` (image_transport's convention)."""
    parts = image_topic.rstrip("/").split("/")
    if parts[-1] in ("compressed", "theora", "compressedDepth") and len(parts) > 2:
        parts = parts[:-1]
    return "/".join(parts[:-1] + ["camera_info"])


def import_bag(bag: Path, urdf: Path, out: Path, options: ImportOptions) -> ImportResult:
    """Write the dataset; every check runs before anything is written, and the directory appears
    whole (built beside `out`, then renamed) or not at all."""
    import yaml

    from armtool.calib.targets.apriltag import family_dictionary
    from armtool.model.chain import chain_from_xml
    from armtool.model.load import load_robot_xml, urdf_text

    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise ArmtoolError("the output exists and is not an empty directory", str(out), "pass a new directory name")
    if not out.parent.is_dir():
        raise ArmtoolError("the output's parent directory does not exist", str(out), "create it first")
    family_dictionary(options.target.family)
    xacro_args = dict(options.xacro_args)
    chain = chain_from_xml(
        load_robot_xml(urdf, xacro_args, options.package_paths), options.base, options.flange, source=urdf.name
    )
    names = list(chain.joint_names)
    intrinsics_camera = None
    intrinsics_source = str(options.intrinsics)
    if options.intrinsics is not None:
        from armtool.calib.model.camera import load_intrinsics

        intrinsics_camera = load_intrinsics(options.intrinsics)
    warnings: list[str] = []

    rb = _Bag(bag)
    try:
        image_type = rb.require(options.image_topic, IMAGE_TYPES, "--image-topic")
        rb.require(options.joints_topic, (JOINT_STATE_TYPE,), "--joints-topic")
        stamps, times, q, velocity, seen = _joint_series(rb, options.joints_topic, names)
        if len(q) == 0:
            _missing_joints(names, seen, options.joints_topic, urdf, bag)
        image_stamps, image_times = [], []
        for timestamp, msg in rb.messages(options.image_topic):
            image_stamps.append(_stamp(msg))
            image_times.append(timestamp * 1e-9)
        if not image_stamps:
            raise ArmtoolError(f"topic '{options.image_topic}' has no messages", str(bag))
        use_headers = bool(np.all(stamps > 0) and np.all(np.array(image_stamps) > 0))
        clock: Clock = "header stamps" if use_headers else "bag receive time"
        if not use_headers:
            warnings.append(
                "some messages have no header stamp: images and joint states were matched by the time the bag received them"
            )
        jt = stamps if use_headers else times
        it = np.array(image_stamps if use_headers else image_times)
        order = np.argsort(jt, kind="stable")
        jt, q = jt[order], q[order]
        if velocity is not None:
            velocity = velocity[order]
        t0 = float(jt[0])
        if options.still_by is StillBy.VELOCITY:
            if velocity is None:
                raise ArmtoolError(
                    f"the JointState messages on '{options.joints_topic}' carry no velocity for every joint",
                    str(bag),
                    "use --still-by position",
                )
            windows = settled_windows(
                jt - t0, q, options.min_still_s, velocity=velocity, max_velocity=options.max_velocity
            )
        else:
            windows = settled_windows(jt - t0, q, options.min_still_s, tolerance=options.tolerance)
        if not windows:
            raise ArmtoolError(
                f"no settled window: the joints never stayed within {options.tolerance} for {options.min_still_s} s"
                if options.still_by is StillBy.POSITION
                else f"no settled window: the joint velocities never stayed below {options.max_velocity} for {options.min_still_s} s",
                str(bag),
                "let the arm stop at each pose for a second, or loosen --tolerance / --max-velocity / --min-still",
            )
        it_rel = it - t0
        chosen, skipped = _choose_images(it_rel, windows, options.max_image_offset)
        if not chosen:
            too_far = [r for *_, r in skipped if "--max-image-offset" in r]
            raise ArmtoolError(
                f"{len(windows)} settled windows, but no image of '{options.image_topic}' was taken during any of them"
                + (f" away from its edges ({len(too_far)} only near an edge)" if too_far else ""),
                str(bag),
                "check that both topics were recorded at the same time (and that their clocks agree)"
                + ("; pass --max-image-offset 1 to take images at a window's edge" if too_far else ""),
            )
        if intrinsics_camera is None:
            info_topic = options.camera_info_topic or _default_camera_info_topic(options.image_topic)
            if info_topic in rb.topics:
                rb.require(info_topic, (CAMERA_INFO_TYPE,), "--camera-info-topic")
                intrinsics_camera = _camera_info(rb, info_topic)
                intrinsics_source = f"camera_info topic {info_topic}" if intrinsics_camera is not None else ""
            elif options.camera_info_topic is not None:
                rb.require(info_topic, (CAMERA_INFO_TYPE,), "--camera-info-topic")
            if intrinsics_camera is None:
                intrinsics_source = "none: camera.yaml is missing"
                warnings.append(
                    "no intrinsics (no --intrinsics, no calibrated camera_info in the bag): write OUT/camera.yaml with "
                    "`armtool calibrate camera IMAGES --board ... -o OUT/camera.yaml` before `calibrate fit`"
                )
        # Second pass: the chosen images only.
        files: dict[int, tuple[bytes, str]] = {}
        shape: tuple[int, int] | None = None
        for k, (_, msg) in enumerate(rb.messages(options.image_topic)):
            if k in chosen:
                files[k] = decode_image(msg, image_type)
                if shape is None:
                    shape = (int(msg.width), int(msg.height)) if hasattr(msg, "width") else None
    finally:
        rb.close()

    if (
        intrinsics_camera is not None
        and shape is not None
        and shape != (intrinsics_camera.width, intrinsics_camera.height)
    ):
        warnings.append(
            f"the images are {shape[0]}x{shape[1]} but the intrinsics are for {intrinsics_camera.width}x{intrinsics_camera.height}"
        )
    samples: list[ImportedSample] = []
    for k, (i, w) in sorted(chosen.items(), key=lambda kv: kv[1][0]):
        ext = files[k][1]
        samples.append(
            ImportedSample(
                f"{i:04d}",
                f"images/{i:04d}{ext}",
                w.start_s,
                w.end_s,
                float(it_rel[k] - w.centre_s),
                {n: float(v) for n, v in zip(names, w.q)},
            )
        )
    warnings += _edge_warnings(samples, jt - t0, q, it_rel[sorted(chosen, key=lambda k: chosen[k][0])])
    manifest = manifest_document(f"armtool calibrate import-bag {bag.name}", options.setup, chain, options.target)
    rows = ["id,image," + ",".join(names)]
    rows += [f"{s.id},{s.image}," + ",".join(f"{s.q[n]:.9f}" for n in names) for s in samples]
    from armtool.fileio import atomic_directory

    with atomic_directory(out) as tmp:
        (tmp / "images").mkdir()
        for k, (i, _) in chosen.items():
            data, ext = files[k]
            (tmp / "images" / f"{i:04d}{ext}").write_bytes(data)
        (tmp / "robot.urdf").write_text(urdf_text(urdf, xacro_args, options.package_paths), encoding="utf-8")
        (tmp / "samples.csv").write_text("\n".join(rows) + "\n", encoding="utf-8")
        (tmp / "dataset.yaml").write_text(yaml.safe_dump(manifest, sort_keys=False), encoding="utf-8")
        if intrinsics_camera is not None:
            if options.intrinsics is not None and options.intrinsics.suffix.lower() in (".yaml", ".yml"):
                shutil.copyfile(options.intrinsics, tmp / "camera.yaml")
            else:
                from armtool.calib.model.camera import save_intrinsics

                save_intrinsics(intrinsics_camera, tmp / "camera.yaml")
    return ImportResult(out, samples, skipped, intrinsics_source, clock, warnings)


def _choose_images(
    it_rel: Array, windows: list[Window], max_offset: float
) -> tuple[dict[int, tuple[int, Window]], list[tuple[float, float, str]]]:
    """Per window, the image nearest its centre among those taken inside it: {image index: (sample
    number, window)}, and the windows skipped with why (no image inside, or the nearest one farther
    from the centre than `max_offset` of the half-window)."""
    chosen: dict[int, tuple[int, Window]] = {}
    skipped: list[tuple[float, float, str]] = []
    for w in windows:
        inside = np.nonzero((it_rel >= w.start_s) & (it_rel <= w.end_s))[0]
        if len(inside) == 0:
            nearest = float(np.min(np.abs(it_rel - w.centre_s)))
            skipped.append(
                (w.start_s, w.end_s, f"no image during the window (nearest {nearest:.2f} s from its centre)")
            )
            continue
        best = int(inside[np.argmin(np.abs(it_rel[inside] - w.centre_s))])
        offset = float(it_rel[best] - w.centre_s)
        fraction = _offset_fraction(offset, w.start_s, w.end_s)
        if fraction > max_offset:
            keep = min(1.0, float(np.ceil(round(fraction * 100.0, 6)) / 100.0))  # the smallest limit that keeps it
            skipped.append(
                (
                    w.start_s,
                    w.end_s,
                    f"its only images are near its edge: the nearest to its centre was taken {abs(offset):.2f} s from it, "
                    f"{fraction:.0%} of the way to the edge (limit {max_offset:.0%}), perhaps while the arm moved; "
                    f"pass --max-image-offset {keep:g} to keep it",
                )
            )
            continue
        chosen[best] = (len(chosen), w)
    return chosen, skipped


def _edge_warnings(samples: list[ImportedSample], jt_rel: Array, q: Array, image_times: Array) -> list[str]:
    """A warning per sample whose image lies in the outer part of its window (beyond
    WARN_OFFSET_FRACTION of the half-window), with how far the joints there are from the sample's values."""
    out = []
    for s, t in zip(samples, image_times):
        if s.image_offset_fraction <= WARN_OFFSET_FRACTION:
            continue
        at_image = np.array([np.interp(t, jt_rel, q[:, j]) for j in range(q.shape[1])])
        drift = float(np.max(np.abs(at_image - np.array(list(s.q.values())))))
        out.append(
            f"sample {s.id}: its image was taken {abs(s.image_offset_s):.2f} s from the centre of its settled window "
            f"{s.start_s:.2f}-{s.end_s:.2f} s ({s.image_offset_fraction:.0%} of the way to its edge; the joints there "
            f"differ from the sample's by up to {drift:.4f}): the arm may have been moving, check the image"
        )
    return out


def _missing_joints(names: list[str], seen: set[str], topic: str, urdf: Path, bag: Path) -> None:
    from armtool.suggest import did_you_mean

    if not seen:
        raise ArmtoolError(f"topic '{topic}' has no JointState messages with names", str(bag))
    missing = [n for n in names if n not in seen]
    if missing:
        lines = [f"{n}{did_you_mean(n, seen)}" for n in missing]
        raise ArmtoolError(
            f"the chain's joint(s) {', '.join(lines)} of {urdf.name} are not in the JointState messages on '{topic}'",
            str(bag),
            f"the bag names: {', '.join(sorted(seen))}; use the URDF the robot ran with, or pick the chain with --base/--flange",
        )
    raise ArmtoolError(
        f"no single JointState message on '{topic}' carries all of {', '.join(names)} (with positions)",
        str(bag),
        "armtool needs each message to hold the whole chain",
    )
