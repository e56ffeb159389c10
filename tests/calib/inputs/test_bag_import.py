"""ROS bags into calibration datasets: settled windows on a simulated motion, all three bag formats."""

from __future__ import annotations

import csv
from pathlib import Path
from types import SimpleNamespace

import cv2
import numpy as np
import pytest

pytest.importorskip("rosbags", reason="the calib extra (rosbags) is not installed")

from armtool.calib.inputs.bag_import import ImportOptions, import_bag, raw_image_array, settled_windows
from armtool.calib.inputs.dataset import load_dataset
from armtool.calib.targets.spec import Target
from armtool.errors import ArmtoolError
from tests.calib.bag_builder import JOINTS, TICK, frame_index, simulate_motion, write_bag

ROOT = Path(__file__).resolve().parents[3]
CLEAN_ARM = ROOT / "fixtures" / "robots" / "clean_arm" / "urdf" / "clean_arm.urdf"


def test_position_windows_match_the_known_stops() -> None:
    m = simulate_motion(n_stops=5, seed=3)
    windows = settled_windows(m.t, m.q, 0.5, tolerance=0.002)
    assert len(windows) == 5
    for w, (a, b), stop in zip(windows, m.holds, m.stops):
        assert abs(w.start_s - a) < 0.15 and abs(w.end_s - b) < 0.15
        assert np.abs(w.q - stop).max() < 2 * TICK


def test_velocity_windows_match_the_known_stops() -> None:
    m = simulate_motion(n_stops=4, seed=4)
    windows = settled_windows(m.t, m.q, 0.5, velocity=m.v, max_velocity=0.01)
    assert len(windows) == 4
    for w, (a, b) in zip(windows, m.holds):
        assert abs(w.centre_s - (a + b) / 2) < 0.15 and w.end_s - w.start_s > 0.8 * (b - a)


def test_slow_motion_and_short_pauses_are_not_settled() -> None:
    t = np.arange(0, 10, 0.02)
    creeping = np.column_stack([0.01 * t, np.zeros_like(t)])  # 0.01 rad/s: 0.005 rad per 0.5 s
    assert settled_windows(t, creeping, 0.5, tolerance=0.002) == []
    q = (0.2 * np.clip(t, None, 4.0) + 0.2 * np.clip(t - 4.3, 0.0, None))[
        :, None
    ]  # 0.2 rad/s with one 0.3 s pause at 4 s
    assert settled_windows(t, q, 0.5, tolerance=0.002) == []
    assert len(settled_windows(t, q, 0.2, tolerance=0.002)) == 1


@pytest.mark.parametrize(("kind", "mode"), [("ros1", "bgr8"), ("sqlite3", "jpeg"), ("mcap", "mono8")])
def test_import_takes_the_image_nearest_each_window_centre(tmp_path: Path, kind: str, mode: str) -> None:
    m = simulate_motion(n_stops=4, seed=0)
    bag = tmp_path / ("cal.bag" if kind == "ros1" else "cal")
    image_topic = "/camera/image_raw/compressed" if mode == "jpeg" else "/camera/image_raw"
    stamps = np.array(write_bag(bag, kind, m, image_topic=image_topic, image_mode=mode, camera_info=True))
    out = tmp_path / "dataset"
    result = import_bag(bag, CLEAN_ARM, out, ImportOptions(image_topic, flange="tool0", target=Target(size_m=0.05)))
    assert result.clock == "header stamps" and result.intrinsics_source == "camera_info topic /camera/camera_info"
    assert len(result.samples) == 4 and not result.skipped
    for s, stop in zip(result.samples, m.stops):
        image = cv2.imread(str(out / s.image), cv2.IMREAD_UNCHANGED)
        k = frame_index(image, len(stamps))
        centre = (s.start_s + s.end_s) / 2
        inside = np.nonzero((stamps >= s.start_s) & (stamps <= s.end_s))[0]
        assert k == inside[np.argmin(np.abs(stamps[inside] - centre))]
        assert np.abs(np.array([s.q[j] for j in JOINTS]) - stop).max() < 2 * TICK
    assert (out / "images" / "0000.jpg").is_file() == (mode == "jpeg")
    ds = load_dataset(out, JOINTS)
    assert not ds.errors, ds.errors
    assert ds.base_link == "base_link" and ds.flange_link == "tool0" and ds.size_m == 0.05 and len(ds.samples) == 4
    with open(out / "samples.csv", newline="") as f:
        assert next(csv.reader(f)) == ["id", "image", *JOINTS]


def test_without_header_stamps_the_bag_time_is_used(tmp_path: Path) -> None:
    m = simulate_motion(n_stops=3, seed=1)
    write_bag(tmp_path / "cal.bag", "ros1", m, zero_stamps=True)
    result = import_bag(
        tmp_path / "cal.bag", CLEAN_ARM, tmp_path / "out", ImportOptions("/camera/image_raw", flange="tool0")
    )
    assert result.clock == "bag receive time" and len(result.samples) == 3
    assert any("no header stamp" in w for w in result.warnings) and any("no intrinsics" in w for w in result.warnings)


def _nothing_written(tmp_path: Path, out: Path) -> bool:
    return not out.exists() and not list(tmp_path.glob(".out.*"))


def test_a_missing_topic_names_the_recorded_ones_and_writes_nothing(tmp_path: Path) -> None:
    write_bag(tmp_path / "cal.bag", "ros1", simulate_motion(n_stops=2))
    out = tmp_path / "out"
    with pytest.raises(
        ArmtoolError, match=r"topic '/camera/image' is not in the bag \(did you mean '/camera/image_raw'\?\)"
    ) as info:
        import_bag(tmp_path / "cal.bag", CLEAN_ARM, out, ImportOptions("/camera/image", flange="tool0"))
    assert "/joint_states (sensor_msgs/msg/JointState)" in (info.value.hint or "")
    assert _nothing_written(tmp_path, out)
    with pytest.raises(ArmtoolError, match=r"'/joint_states' is sensor_msgs/msg/JointState, not sensor_msgs/msg/Image"):
        import_bag(tmp_path / "cal.bag", CLEAN_ARM, out, ImportOptions("/joint_states", flange="tool0"))
    assert _nothing_written(tmp_path, out)


def test_joints_that_the_urdf_does_not_name_are_an_error(tmp_path: Path) -> None:
    write_bag(tmp_path / "cal", "sqlite3", simulate_motion(n_stops=2), joint_names=[f"arm_{j}" for j in JOINTS])
    out = tmp_path / "out"
    with pytest.raises(
        ArmtoolError, match=r"joint\(s\) joint1 \(did you mean 'arm_joint1'\?\).* are not in the JointState messages"
    ) as info:
        import_bag(tmp_path / "cal", CLEAN_ARM, out, ImportOptions("/camera/image_raw", flange="tool0"))
    assert "arm_joint6" in (info.value.hint or "")
    assert _nothing_written(tmp_path, out)


def test_no_settled_window_and_existing_output_are_errors(tmp_path: Path) -> None:
    write_bag(tmp_path / "cal.bag", "ros1", simulate_motion(n_stops=2))
    with pytest.raises(ArmtoolError, match="no settled window"):
        import_bag(
            tmp_path / "cal.bag",
            CLEAN_ARM,
            tmp_path / "out",
            ImportOptions("/camera/image_raw", flange="tool0", min_still_s=5.0),
        )
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "keep.txt").write_text("mine")
    with pytest.raises(ArmtoolError, match="not an empty directory"):
        import_bag(
            tmp_path / "cal.bag", CLEAN_ARM, tmp_path / "full", ImportOptions("/camera/image_raw", flange="tool0")
        )
    assert [p.name for p in (tmp_path / "full").iterdir()] == ["keep.txt"]
    with pytest.raises(ArmtoolError, match="not a ROS bag|bag not found"):
        import_bag(tmp_path / "full" / "keep.txt", CLEAN_ARM, tmp_path / "o2", ImportOptions("/camera/image_raw"))


def _raw(encoding: str, data: np.ndarray, h: int, w: int, step: int, big: int = 0) -> SimpleNamespace:
    return SimpleNamespace(
        encoding=encoding, height=h, width=w, step=step, is_bigendian=big, data=data.reshape(-1).view(np.uint8)
    )


def test_raw_encodings_decode_to_opencv_arrays() -> None:
    rgb = np.zeros((2, 3, 3), np.uint8)
    rgb[..., 0] = 255  # red
    assert raw_image_array(_raw("rgb8", rgb, 2, 3, 9))[0, 0].tolist() == [0, 0, 255]
    padded = np.zeros((2, 4), np.uint8)
    padded[:, :3] = 7  # rows padded to a 4-byte step
    assert raw_image_array(_raw("mono8", padded, 2, 3, 4)).tolist() == [[7, 7, 7], [7, 7, 7]]
    big = np.array([[1, 2]], dtype=">u2")
    assert raw_image_array(_raw("mono16", big, 1, 2, 4, big=1)).tolist() == [[1, 2]]
    bayer = np.full((4, 4), 100, np.uint8)
    assert raw_image_array(_raw("bayer_rggb8", bayer, 4, 4, 4)).shape == (4, 4, 3)
    with pytest.raises(ArmtoolError, match="encoding '32FC1' is not supported"):
        raw_image_array(_raw("32FC1", np.zeros(4, np.float32), 1, 1, 4))
    with pytest.raises(ArmtoolError, match="inconsistent"):
        raw_image_array(_raw("mono8", np.zeros(3, np.uint8), 2, 3, 3))


def _edge_bag(tmp_path: Path, fractions: list[float]) -> tuple[Path, list[tuple[float, float]]]:
    """A ROS 2 bag whose only image of settled window k is `fractions[k]` of its half-window after its centre."""
    m = simulate_motion(n_stops=len(fractions), seed=2)
    windows = settled_windows(m.t, m.q, 0.5, tolerance=0.002)
    assert len(windows) == len(fractions)
    times = [w.centre_s + f * 0.5 * (w.end_s - w.start_s) for w, f in zip(windows, fractions)]
    write_bag(tmp_path / "cal", "sqlite3", m, image_times=times)
    return tmp_path / "cal", [(w.start_s, w.end_s) for w in windows]


def test_an_image_near_its_window_edge_is_warned_about_and_refused_beyond_the_limit(tmp_path: Path) -> None:
    bag, windows = _edge_bag(tmp_path, [0.0, 0.7, 0.95])
    result = import_bag(bag, CLEAN_ARM, tmp_path / "out", ImportOptions("/camera/image_raw", flange="tool0"))
    assert [s.id for s in result.samples] == ["0000", "0001"]
    assert abs(result.samples[1].image_offset_fraction - 0.7) < 0.01 and result.samples[0].image_offset_fraction < 0.01
    (warning,) = [w for w in result.warnings if "settled window" in w]
    assert warning.startswith("sample 0001: its image was taken") and "70% of the way to its edge" in warning
    ((start, end, reason),) = result.skipped
    assert (start, end) == pytest.approx(windows[2])
    assert "95% of the way to the edge (limit 80%)" in reason and "pass --max-image-offset 0.95 to keep it" in reason
    assert result.summary()["samples"][1]["image_offset_fraction"] == pytest.approx(0.7, abs=0.01)  # type: ignore[index]
    relaxed = import_bag(
        bag, CLEAN_ARM, tmp_path / "all", ImportOptions("/camera/image_raw", flange="tool0", max_image_offset=1.0)
    )
    assert len(relaxed.samples) == 3 and not relaxed.skipped
    assert sum("settled window" in w for w in relaxed.warnings) == 2


def test_the_text_report_names_the_edge_image_and_the_option(tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from armtool.cli import app

    bag, _ = _edge_bag(tmp_path, [0.7, 0.95])
    args = ["calibrate", "import-bag", str(bag), "--image-topic", "/camera/image_raw", "--urdf", str(CLEAN_ARM)]
    result = CliRunner().invoke(app, [*args, "--flange", "tool0", "--tag-size", "0.05", "-o", str(tmp_path / "o")])
    assert result.exit_code == 0, result.output
    text = " ".join(result.stderr.split())
    assert "warning: sample 0000: its image was taken" in text and "--max-image-offset 0.95" in text
    import subprocess
    import sys

    only_edges = subprocess.run(
        [sys.executable, "-m", "armtool", *args[:-2], "--urdf", str(CLEAN_ARM), "--tag-size", "0.05"]
        + ["--max-image-offset", "0.5", "-o", str(tmp_path / "o2")],
        capture_output=True,
        text=True,
    )
    assert only_edges.returncode == 2 and "Traceback" not in only_edges.stderr
    assert "--max-image-offset 1" in " ".join(only_edges.stderr.split())
    assert not (tmp_path / "o2").exists()


def test_an_interrupted_ros2_recording_names_ros2_bag_reindex(tmp_path: Path) -> None:
    for kind in ("sqlite3", "mcap"):
        bag = tmp_path / kind
        write_bag(bag, kind, simulate_motion(n_stops=2))
        (bag / "metadata.yaml").unlink()  # what a killed `ros2 bag record` leaves
        storage = next(p for p in bag.iterdir() if p.suffix in (".db3", ".mcap"))
        for given in (bag, storage):
            with pytest.raises(ArmtoolError, match="the ROS 2 recording was interrupted") as info:
                import_bag(given, CLEAN_ARM, tmp_path / "out", ImportOptions("/camera/image_raw"))
            assert "not a ROS 2 bag" not in info.value.what
            assert f"ros2 bag reindex {bag}" in (info.value.hint or "")
    (tmp_path / "empty").mkdir()
    with pytest.raises(ArmtoolError, match="no .db3 or .mcap storage file: not a ROS 2 bag"):
        import_bag(tmp_path / "empty", CLEAN_ARM, tmp_path / "out", ImportOptions("/camera/image_raw"))


def _unindexed(bag: Path) -> bytes:
    """The bytes of a ROS 1 bag as `rosbag record` leaves it when killed: no index (index_pos 0), cut short."""
    data = bytearray(bag.read_bytes())
    at = data.index(b"index_pos=") + len(b"index_pos=")
    data[at : at + 8] = bytes(8)
    return bytes(data[: int(len(data) * 0.8)])


def test_an_interrupted_ros1_recording_names_rosbag_reindex(tmp_path: Path) -> None:
    write_bag(tmp_path / "done.bag", "ros1", simulate_motion(n_stops=2))
    active = tmp_path / "cal.bag.active"
    active.write_bytes(_unindexed(tmp_path / "done.bag"))
    options = ImportOptions("/camera/image_raw")
    with pytest.raises(ArmtoolError, match=r"an unfinished ROS 1 recording \(.bag.active\)") as info:
        import_bag(active, CLEAN_ARM, tmp_path / "out", options)
    assert "`rosbag reindex cal.bag.active`" in (info.value.hint or "") and "mv cal.bag.active cal.bag" in (
        info.value.hint or ""
    )
    with pytest.raises(ArmtoolError, match="bag not found, but cal.bag.active is there") as info:
        import_bag(tmp_path / "cal.bag", CLEAN_ARM, tmp_path / "out", options)
    assert "rosbag reindex cal.bag.active" in (info.value.hint or "")
    (tmp_path / "cut.bag").write_bytes(_unindexed(tmp_path / "done.bag"))  # renamed without reindexing
    with pytest.raises(ArmtoolError, match="cannot read the bag: Bag is not indexed") as info:
        import_bag(tmp_path / "cut.bag", CLEAN_ARM, tmp_path / "out", options)
    assert "rosbag reindex cut.bag" in (info.value.hint or "")


def test_a_board_target_goes_into_the_manifest(tmp_path: Path) -> None:
    from armtool.calib.targets.boards import parse_board
    from armtool.calib.targets.spec import named_target

    write_bag(tmp_path / "cal.bag", "ros1", simulate_motion(n_stops=2), camera_info=True)
    target = named_target("charuco:6x5:0.04:0.03:4X4_50", None)
    import_bag(tmp_path / "cal.bag", CLEAN_ARM, tmp_path / "out", ImportOptions("/camera/image_raw", target=target))
    ds = load_dataset(tmp_path / "out", JOINTS)
    assert not ds.errors and ds.board == parse_board("charuco:6x5:0.04:0.03:4X4_50")
    with pytest.raises(ArmtoolError, match="--tag-size is required for an AprilTag target"):
        named_target(None, None)
    with pytest.raises(ArmtoolError, match="looks the same turned by 180°"):
        named_target("chessboard:8x6:0.03", None)
