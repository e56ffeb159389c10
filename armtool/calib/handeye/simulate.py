"""Synthetic hand-eye datasets with known truth: images of a board and the flange poses a controller reports.

The camera's and the board's true frames are made up but plausible (eye-in-hand: a camera 5-10 cm
off the flange, a board on the table 0.5 m in front of the base; eye-to-hand: a camera 1.2 m away,
a board on the flange). Each image's board pose is drawn as a careful user takes them (the whole
board in view, 0.35-0.8 m away, tilted up to `max_tilt_deg`, turned about the optical axis by any
angle, so that the detector's corner order starts at either end), the flange pose follows from
G_i = Z C_i⁻¹ X⁻¹ (`armtool.calib.handeye.views`), and the reported pose gets the controller's
error (`flange_noise_mm`, `flange_noise_deg`, 1σ per axis). Images are rendered by the exact
renderer of the simulation stage. The truth goes to `truth/truth.yaml`, which nothing reads.
`corner_observations` makes the same data without images (the corners where the camera sees the
board, with Gaussian noise), for the fits alone.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armtool.calib.choices import Quality, Setup
from armtool.calib.model import se3
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.calib.targets.boards import BoardSpec, board_size_m, parse_board
from armtool.errors import ArmtoolError

if TYPE_CHECKING:
    from armtool.calib.handeye.views import Observations

# A 640x480 camera (f = 600 px, webcam-like distortion): small images render fast, for the tests
# and the benchmark.
SMALL_CAMERA = CameraModel(
    np.array([[600.0, 0, 322.4], [0, 600.0, 236.8], [0, 0, 1]]), np.array([-0.12, 0.08, 4e-4, -3e-4, 0.0]), 640, 480
)


@dataclass(frozen=True)
class HandEyeSimulation:
    images: int = 30
    setup: Setup = Setup.EYE_IN_HAND
    board: BoardSpec = field(default_factory=lambda: parse_board("chessboard:10x7:0.025"))
    seed: int = 0
    quality: Quality = Quality.TYPICAL
    distortion: bool = True
    flange_noise_mm: float = 0.2
    flange_noise_deg: float = 0.02
    distance_m: tuple[float, float] = (0.35, 0.8)
    max_tilt_deg: float = 45.0
    bad_rows: int = 0  # rows whose flange pose is off by 3 cm and 3° (a pose written for another image)
    camera: CameraModel | None = None  # default: the simulation stage's 1280x720 camera


@dataclass(frozen=True)
class Rendered:
    """A simulated dataset in memory: the images, the reported flange poses (flange in base), the truth."""

    images: list[NDArray[np.uint8]]
    flanges: Array  # (N, 4, 4) as the controller reports them
    true_flanges: Array
    board_in_camera: Array  # (N, 4, 4)
    X: Array  # camera in flange (eye-in-hand) or in base (eye-to-hand)
    Z: Array  # board in base (eye-in-hand) or in flange (eye-to-hand)
    camera: CameraModel
    bad_rows: list[int]


def true_frames(setup: Setup, board: BoardSpec, rng: np.random.Generator) -> tuple[Array, Array]:
    """(X, Z): the camera's and the board's true frames, jittered by a few mm and degrees."""
    jitter = se3.delta(np.concatenate([rng.normal(scale=0.005, size=3), rng.normal(scale=math.radians(2), size=3)]))
    w, h = board_size_m(board)
    if setup is Setup.EYE_IN_HAND:
        X = se3.make(se3.exp3(np.array([0.0, 0.0, math.radians(90)])), np.array([0.07, -0.01, 0.05])) @ jitter
        Z = se3.make(np.diag([1.0, -1.0, -1.0]), np.array([0.55 - w / 2, 0.1 + h / 2, 0.0]))  # on the table, face up
    else:
        X = se3.make(se3.exp3(np.array([0.0, -math.radians(100), 0.0])), np.array([1.3, 0.1, 0.6])) @ jitter
        Z = se3.make(np.diag([1.0, -1.0, -1.0]), np.array([-w / 2, h / 2, 0.03]))  # on the flange, face out
    return X, Z


def board_pose(camera: CameraModel, board: BoardSpec, spec: HandEyeSimulation, rng: np.random.Generator) -> Array:
    """A board pose cMb with the whole board in view (module docstring)."""
    from armtool.calib.simulation.render import _rotvec, board_in_view

    w, h = board_size_m(board)
    centre = np.array([w / 2, h / 2, 0.0])
    for _attempt in range(1000):
        a, tilt = rng.uniform(0, 2 * math.pi), math.radians(rng.uniform(10.0, spec.max_tilt_deg))
        R = _rotvec(np.array([math.cos(a), math.sin(a), 0.0]) * tilt) @ _rotvec(
            np.array([0.0, 0.0, rng.uniform(-math.pi, math.pi)])
        )
        u, v = rng.uniform(0.3, 0.7) * camera.width, rng.uniform(0.3, 0.7) * camera.height
        ray = np.append(camera.normalized(np.array([[u, v]]))[0], 1.0)
        cMb = se3.make(R, ray / np.linalg.norm(ray) * rng.uniform(*spec.distance_m) - R @ centre)
        if board_in_view(camera, cMb, board):
            return cMb
    raise ArmtoolError("no pose shows the whole board", hint="use a smaller board or larger distances")


def render(spec: HandEyeSimulation, progress: Callable[[int, int], None] | None = None) -> Rendered:
    """The images and poses of a simulated dataset (module docstring)."""
    from armtool.calib.simulation.render import render_board
    from armtool.calib.simulation.simulate import QUALITY, default_camera

    rng = np.random.default_rng(spec.seed)
    camera = spec.camera or default_camera(spec.distortion)
    X, Z = true_frames(spec.setup, spec.board, rng)
    look = QUALITY[spec.quality]
    images, C, G = [], [], []
    for i in range(spec.images):
        cMb = board_pose(camera, spec.board, spec, rng)
        C.append(cMb)
        G.append(Z @ se3.inv(cMb) @ se3.inv(X))
        image = render_board(
            camera,
            cMb,
            spec.board,
            blur_sigma_px=rng.uniform(*look["blur"]),
            noise_sigma=look["noise"][0],
            black=rng.uniform(*look["black"]),
            white=rng.uniform(*look["white"]),
            gradient=0.1,
            rng=rng,
        )
        images.append(image)
        if progress:
            progress(i + 1, spec.images)
    true_flanges = np.stack(G) if spec.setup is Setup.EYE_IN_HAND else se3.inv(np.stack(G))
    noise = np.concatenate(
        [
            rng.normal(scale=spec.flange_noise_mm * 1e-3, size=(spec.images, 3)),
            rng.normal(scale=math.radians(spec.flange_noise_deg), size=(spec.images, 3)),
        ],
        axis=1,
    )
    reported = true_flanges @ se3.delta_batch(noise)
    bad = sorted(int(i) for i in rng.choice(spec.images, size=min(spec.bad_rows, spec.images // 4), replace=False))
    for i in bad:
        reported[i] = reported[i] @ se3.delta(np.concatenate([0.03 * _unit(rng), math.radians(3.0) * _unit(rng)]))
    return Rendered(images, reported, true_flanges, np.stack(C), X, Z, camera, bad)


def _unit(rng: np.random.Generator) -> Array:
    v: Array = rng.normal(size=3)
    return v / float(np.linalg.norm(v))


def write_dataset(out: Path, spec: HandEyeSimulation, rendered: Rendered) -> None:
    """The dataset directory: dataset.yaml, camera.yaml, images/, poses.csv (flange in base, metres,
    quaternion xyzw) and truth/truth.yaml; `out` must be new or empty."""
    import cv2
    import yaml

    from armtool.calib.fit.handeye import quaternions
    from armtool.calib.model.camera import save_intrinsics
    from armtool.fileio import write_atomic

    if out.exists() and any(out.iterdir()):
        raise ArmtoolError("output directory is not empty", str(out), "choose a new directory, nothing was written")
    (out / "images").mkdir(parents=True, exist_ok=True)
    (out / "truth").mkdir()
    save_intrinsics(rendered.camera, out / "camera.yaml")
    rows = ["image,x,y,z,qx,qy,qz,qw"]
    for i, (image, F) in enumerate(zip(rendered.images, rendered.flanges)):
        name = f"images/{i:04d}.png"
        if not cv2.imwrite(str(out / name), image):
            raise ArmtoolError("cannot write image", str(out / name))
        w, x, y, z = quaternions(F[None, :3, :3])[0]
        rows.append(f"{name}," + ",".join(f"{v:.9f}" for v in (*F[:3, 3], x, y, z, w)))
    write_atomic(out / "poses.csv", "\n".join(rows) + "\n")
    manifest = {
        "format": "armtool-handeye-dataset/1",
        "created_by": "armtool calibrate handeye-simulate",
        "setup": spec.setup.value,
        "camera": {"intrinsics": "camera.yaml"},
        "target": {"board": spec.board.text()},
        "poses": {
            "file": "poses.csv",
            "image_column": "image",
            "pose": "flange_in_base",
            "position_units": "m",
            "rotation": "quaternion",
            "quaternion_order": "xyzw",
            "position_columns": ["x", "y", "z"],
            "rotation_columns": ["qx", "qy", "qz", "qw"],
        },
    }
    write_atomic(out / "dataset.yaml", yaml.safe_dump(manifest, sort_keys=False))
    names = (
        ("camera_in_flange", "board_in_base")
        if spec.setup is Setup.EYE_IN_HAND
        else ("camera_in_base", "board_in_flange")
    )
    truth = {
        "note": "ground truth of this synthetic dataset; armtool calibrate handeye never reads it",
        names[0]: _pose(rendered.X),
        names[1]: _pose(rendered.Z),
        "flange_noise": {"position_mm": spec.flange_noise_mm, "rotation_deg": spec.flange_noise_deg},
        "bad_rows": [f"images/{i:04d}.png" for i in rendered.bad_rows],
        "seed": spec.seed,
    }
    write_atomic(out / "truth" / "truth.yaml", yaml.safe_dump(truth, sort_keys=False, default_flow_style=None))


def _pose(T: Array) -> dict[str, list[float]]:
    return {"xyz": [float(v) for v in T[:3, 3]], "rpy": [float(v) for v in se3.rpy_of(T[:3, :3])]}


def corner_observations(
    n: int = 25,
    seed: int = 0,
    flange_mm: float = 0.2,
    flange_deg: float = 0.02,
    pixel_px: float = 0.05,
    setup: Setup = Setup.EYE_IN_HAND,
    board: str = "chessboard:10x7:0.025",
    camera: CameraModel | None = None,
    distance_m: tuple[float, float] = (0.5, 1.0),
) -> tuple[Observations, Array, Array]:
    """(observations, X, Z) without images, for the fits alone: the corners where the camera
    (default `SMALL_CAMERA`) sees the board, plus Gaussian pixel noise, and each flange pose off by
    the controller's error (1σ per axis, on its right)."""
    from armtool.calib.handeye.views import Observations
    from armtool.calib.targets.boards import board_points
    from armtool.calib.targets.pose import planar_pose

    camera = camera or SMALL_CAMERA
    rng = np.random.default_rng(seed)
    spec = HandEyeSimulation(board=parse_board(board), setup=setup, camera=camera, distance_m=distance_m)
    X, Z = true_frames(setup, spec.board, rng)
    points = board_points(spec.board)
    G, C, rms, pixels = [], [], [], []
    for _ in range(n):
        cMb = board_pose(camera, spec.board, spec, rng)
        F = Z @ se3.inv(cMb) @ se3.inv(X)
        F = F if setup is Setup.EYE_IN_HAND else se3.inv(F)  # the flange in the base, exact
        e = np.concatenate(
            [rng.normal(scale=flange_mm * 1e-3, size=3), rng.normal(scale=np.radians(flange_deg), size=3)]
        )
        F = F @ se3.delta(e)
        u = camera.project(points @ cMb[:3, :3].T + cMb[:3, 3]) + rng.normal(scale=pixel_px, size=(len(points), 2))
        pose, r, _ambiguous = planar_pose(points, u, camera)
        G.append(F if setup is Setup.EYE_IN_HAND else se3.inv(F))
        C.append(pose)
        rms.append(r)
        pixels.append(u)
    obs = Observations(
        setup,
        np.array(G),
        np.array(C),
        np.ones(n, dtype=bool),
        np.array(rms),
        np.repeat(np.arange(n), len(points)),
        np.tile(points, (n, 1)),
        np.concatenate(pixels),
    )
    return obs, X, Z
