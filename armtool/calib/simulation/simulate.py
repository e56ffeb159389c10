"""Synthetic calibration datasets with known truth, for rehearsing a pose set and for the tests.

A "true" robot is the URDF with injected errors (6-D origin errors per joint, zero offsets), seen
by a camera at a made-up but plausible place; images of the target (one AprilTag, or a board with
`board`) are rendered from the true robot and the joint readings written as the controller would
report them. The truth (injected errors, frames,
validation poses, the true URDF) goes to `truth/`, which `armtool calibrate fit` never reads.
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
from armtool.calib.inputs.dataset import manifest_document
from armtool.calib.model import se3
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.calib.targets.spec import Target
from armtool.errors import ArmtoolError

if TYPE_CHECKING:
    from armtool.calib.targets.boards import BoardSpec

QUALITY: dict[Quality, dict[str, tuple[float, float]]] = {  # research/calibration.md §2 image conditions
    Quality.GOOD: {"blur": (0.5, 0.7), "noise": (1.5 / 255, 1.5 / 255), "black": (0.06, 0.10), "white": (0.85, 0.9)},
    Quality.TYPICAL: {"blur": (0.8, 1.2), "noise": (3 / 255, 3 / 255), "black": (0.08, 0.20), "white": (0.60, 0.90)},
    Quality.POOR: {"blur": (1.4, 2.0), "noise": (6 / 255, 6 / 255), "black": (0.15, 0.30), "white": (0.45, 0.70)},
}


DISTANCE_M = {Setup.EYE_TO_HAND: (0.5, 1.3), Setup.EYE_IN_HAND: (0.3, 0.8)}


@dataclass(frozen=True)
class SimulationSpec:
    samples: int = 60
    validation: int = 30  # poses kept in truth/ to check a calibration against the true robot
    setup: Setup = Setup.EYE_TO_HAND
    seed: int = 0
    quality: Quality = Quality.TYPICAL
    tag_size_m: float = 0.08
    tag_id: int = 0
    family: str = "tag36h11"
    origin_error_mm: tuple[float, float] = (0.5, 3.0)
    origin_error_deg: tuple[float, float] = (0.05, 0.3)
    offset_error_deg: tuple[float, float] = (0.1, 0.5)
    distance_m: tuple[float, float] | None = None  # camera-tag distance; default 0.5-1.3 m fixed, 0.3-0.8 m hand-held
    max_tilt_deg: float = 60.0
    bad_samples: int = 0  # wrong rows mixed in: a joint reading off by 5°, or a mislabeled image
    joint_noise_deg: float = 0.0
    distortion: bool = False
    xacro_args: dict[str, str] = field(default_factory=dict)  # for a .xacro robot
    package_paths: tuple[Path, ...] = ()
    board: BoardSpec | None = None  # a board instead of the tag (tag_size_m, tag_id, family unused)

    def __post_init__(self) -> None:
        # From Python, plain strings are welcome ("poor", "eye_in_hand"); a wrong one is named
        # here with the choices, not found later as a KeyError inside the rendering.
        for name, kind in (("quality", Quality), ("setup", Setup)):
            value = getattr(self, name)
            try:
                object.__setattr__(self, name, kind(value))
            except ValueError:
                choices = ", ".join(v.value for v in kind)
                raise ArmtoolError(f"unknown {name} {value!r}", hint=f"choose from: {choices}") from None

    @property
    def distances(self) -> tuple[float, float]:
        return self.distance_m or DISTANCE_M[self.setup]

    @property
    def target(self) -> Target:
        return Target(self.family, self.tag_id, self.tag_size_m, self.board)


def default_camera(distortion: bool = False) -> CameraModel:
    K = np.array([[910.0, 0.0, 641.3], [0.0, 910.0, 358.7], [0.0, 0.0, 1.0]])
    dist = np.array([0.10, -0.25, 5e-4, -3e-4, 0.10]) if distortion else np.zeros(5)
    return CameraModel(K, dist, 1280, 720)


def _random_unit(rng: np.random.Generator) -> Array:
    v: Array = rng.normal(size=3)
    return v / float(np.linalg.norm(v))


def true_errors(model: CalibModel, spec: SimulationSpec, rng: np.random.Generator) -> Array:
    """A parameter vector of injected robot errors: origin errors and zero offsets, no gain error,
    measurement frames left at 0 (the true frames are the model's L0, R0)."""
    x = np.zeros(model.size)
    parts = model.split(x)
    for i in range(model.chain.n):
        parts.origin[i, :3] = _random_unit(rng) * rng.uniform(*spec.origin_error_mm) * 1e-3
        parts.origin[i, 3:] = _random_unit(rng) * math.radians(rng.uniform(*spec.origin_error_deg))
        parts.offset[i] = rng.choice([-1.0, 1.0]) * math.radians(rng.uniform(*spec.offset_error_deg))
    return x


def _look_at(eye: Array, target: Array, up: Array) -> Array:
    """bMc of an OpenCV camera (z forward, y down) at `eye` looking at `target`."""
    z = target - eye
    z /= np.linalg.norm(z)
    x = np.cross(z, -up)
    if np.linalg.norm(x) < 1e-6:
        x = np.cross(z, np.array([1.0, 0.0, 0.0]))
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return se3.make(np.column_stack([x, y, z]), eye)


def _place(
    model0: CalibModel, spec: SimulationSpec, rng: np.random.Generator, camera: CameraModel | None = None
) -> tuple[Array, Array, Array]:
    """(L, R, Q_pool): measurement frames of the true setup and a pool of joint vectors.

    Eye-to-hand: a camera looking at the middle of the workspace, random joint vectors. Eye-in-hand:
    the tag is put where the flange camera looks in many reachable poses, and the pool holds those
    poses (`_eye_in_hand_views`), so any arm that can point its camera works, 5-DOF ones included.
    The target is placed by its face frame (`Target.face_pose`: centred, z out of the face); R is
    its own frame.
    """
    faceMtarget = se3.inv(spec.target.face_pose())
    chain = model0.chain
    Q = chain.random(rng, 40000)
    F = model0.flange(np.zeros(model0.size), Q)
    P = F[:, :3, 3]
    reach = float(np.percentile(np.linalg.norm(P, axis=1), 95))
    centre = np.median(P, axis=0)
    if spec.setup is Setup.EYE_TO_HAND:
        fMt = se3.xyz_rpy([0.0, 0.0, 0.012], [0.0, 0.0, math.pi / 2])
        direction = np.array([1.0, 0.35, 0.55])
        eye = centre + direction / np.linalg.norm(direction) * (0.5 * reach + 0.75)
        bMc = _look_at(eye, centre, np.array([0.0, 0.0, 1.0]))
        return se3.inv(bMc), fMt @ faceMtarget, Q
    fMc = se3.xyz_rpy([0.04, 0.0, 0.03], [0.0, 0.0, 0.0])
    bMt, views = _eye_in_hand_views(
        model0, fMc, camera or default_camera(spec.distortion), spec, rng, Q, 3 * (spec.samples + spec.validation)
    )
    return se3.inv(fMc), bMt @ faceMtarget, views


def _good_views(bMc: Array, bMt: Array, camera: CameraModel, spec: SimulationSpec) -> Array:
    """Mask of camera poses that see the tag's centre well: in range, not too oblique, well inside the image."""
    v = bMt[:3, 3] - bMc[:, :3, 3]
    dist = np.linalg.norm(v, axis=1)
    pc = np.einsum("nji,nj->ni", bMc[:, :3, :3], v)  # tag centre in camera coordinates
    z = np.maximum(pc[:, 2], 1e-9)
    u = camera.K[0, 0] * pc[:, 0] / z + camera.K[0, 2]
    w = camera.K[1, 1] * pc[:, 1] / z + camera.K[1, 2]
    facing = -(v @ bMt[:3, 2]) / np.maximum(dist, 1e-9)  # cos(angle between the tag normal and the ray)
    lo, hi = spec.distances
    mask: Array = (
        (pc[:, 2] > 0)
        & (dist > lo)
        & (dist < hi)
        & (facing > math.cos(math.radians(spec.max_tilt_deg)))
        & (np.abs(u - camera.width / 2) < 0.38 * camera.width)
        & (np.abs(w - camera.height / 2) < 0.38 * camera.height)
    )
    return mask


def _eye_in_hand_views(
    model: CalibModel,
    fMc: Array,
    camera: CameraModel,
    spec: SimulationSpec,
    rng: np.random.Generator,
    Q: Array,
    count: int,
) -> tuple[Array, Array]:
    """(bMt, joint vectors) for a camera on the flange: sample, place the tag, then explore.

    No IK on 6-D camera poses (an arm with fewer than six joints reaches almost none of them):
    random joint vectors give reachable camera poses; candidate tags are put on the optical axis
    of some of them, facing that camera, and the one most other poses see well is kept; then the
    good poses are perturbed joint-wise to find more, until `count` are found or the search stops.
    """
    chain = model.chain
    bMc = model.flange(np.zeros(model.size), Q) @ fMc
    best_mask, best_tag = None, None
    for k in rng.choice(len(Q), size=min(300, len(Q)), replace=False):
        normal = -bMc[k, :3, 2]
        centre = bMc[k, :3, 3] + bMc[k, :3, 2] * rng.uniform(*spec.distances)
        x = np.cross(normal, [0.0, 0.0, 1.0] if abs(normal[2]) < 0.9 else [1.0, 0.0, 0.0])
        x /= np.linalg.norm(x)
        bMt = se3.make(np.column_stack([x, np.cross(normal, x), normal]), centre)
        mask = _good_views(bMc, bMt, camera, spec)
        if best_mask is None or mask.sum() > best_mask.sum():
            best_mask, best_tag = mask, bMt
    assert best_mask is not None and best_tag is not None
    views = Q[best_mask]
    lower, upper = chain.lower, chain.upper
    for _round in range(20):
        if len(views) >= count or len(views) == 0:
            break
        seeds = views[rng.integers(len(views), size=4000)]
        trial = np.clip(seeds + rng.normal(scale=0.25, size=seeds.shape), lower, upper)
        ok = _good_views(model.flange(np.zeros(model.size), trial) @ fMc, best_tag, camera, spec)
        views = np.concatenate([views, trial[ok]])
    return best_tag, views


def _visible(model: CalibModel, x: Array, camera: CameraModel, Q: Array, spec: SimulationSpec) -> Array:
    """Indices of rows of Q whose target pose renders well (distance, tilt, whole plate or board in view)."""
    from armtool.calib.simulation.render import board_in_view, tag_in_view

    C = model.tag_in_camera(x, Q)  # the target's own frame
    F = C @ spec.target.face_pose()  # its face frame: centred, z towards a camera that sees it
    t = F[:, :3, 3]
    dist = np.linalg.norm(t, axis=1)
    view = -t / np.maximum(dist[:, None], 1e-9)
    facing = np.einsum("ni,ni->n", F[:, :3, 2], view)  # cos(angle between the target's normal and the ray)
    ok = (dist > spec.distances[0]) & (dist < spec.distances[1]) & (facing > math.cos(math.radians(spec.max_tilt_deg)))
    good = []
    for i in np.flatnonzero(ok):
        if spec.board is not None and board_in_view(camera, C[i], spec.board):
            good.append(i)
        elif spec.board is None and tag_in_view(camera, C[i], spec.tag_size_m, spec.family):
            good.append(i)
    return np.array(good, dtype=int)


def _write_text(path: Path, text: str) -> None:
    from armtool.fileio import write_atomic

    write_atomic(path, text)


def simulate(
    urdf: Path,
    out: Path,
    base: str | None,
    flange: str | None,
    spec: SimulationSpec,
    progress: Callable[[int, int], None] | None = None,
) -> dict[str, object]:
    """Write a dataset into `out` (must be empty or new); return a summary of what was injected.
    `base`/`flange` None: the URDF's root, the end of its longest chain."""
    import cv2
    import yaml

    from armtool.calib.model.camera import save_intrinsics
    from armtool.calib.outputs.urdf import (
        check_reproduces,
        corrected_text,
        joint_corrections,
        relocate_meshes,
    )
    from armtool.calib.simulation.render import render_board, render_tag
    from armtool.calib.targets.apriltag import family_dictionary
    from armtool.model.chain import chain_from_xml
    from armtool.model.load import load_robot_xml, urdf_text

    if spec.board is None:
        family_dictionary(spec.family)
    elif spec.board.symmetric:
        from armtool.calib.targets.spec import symmetric_board_error

        raise symmetric_board_error(spec.board, "--target")
    if out.exists() and any(out.iterdir()):
        raise ArmtoolError("output directory is not empty", str(out), "choose a new directory, nothing was written")
    rng = np.random.default_rng(spec.seed)
    chain = chain_from_xml(load_robot_xml(urdf, spec.xacro_args, spec.package_paths), base, flange, source=urdf.name)
    camera = default_camera(spec.distortion)
    nominal = CalibModel(chain, spec.setup, np.eye(4), np.eye(4))
    L, R, pool = _place(nominal, spec, rng, camera)
    x_true = true_errors(nominal, spec, rng)
    truth_model = nominal.with_frames(L, R)
    visible = _visible(truth_model, x_true, camera, pool, spec)
    need = spec.samples + spec.validation
    if len(visible) < need:
        raise ArmtoolError(
            f"only {len(visible)} of {len(pool)} candidate poses show the {'board' if spec.board else 'tag'} well; {need} are needed",
            hint="lower --samples or --validation, or name with --flange a link that can point the camera (eye_in_hand) or the tag (eye_to_hand) at the other",
        )
    chosen = rng.choice(visible, size=need, replace=False)
    Q_fit, Q_val = pool[chosen[: spec.samples]], pool[chosen[spec.samples :]]

    out.mkdir(parents=True, exist_ok=True)
    (out / "images").mkdir()
    (out / "truth").mkdir()
    text = relocate_meshes(urdf_text(urdf, spec.xacro_args, spec.package_paths), urdf.parent, out)
    _write_text(out / "robot.urdf", text)
    save_intrinsics(camera, out / "camera.yaml")
    q_cfg = QUALITY[spec.quality]
    C = truth_model.tag_in_camera(x_true, Q_fit)
    readings = Q_fit.copy()
    if spec.joint_noise_deg:
        readings = readings + rng.normal(scale=math.radians(spec.joint_noise_deg), size=readings.shape)
    images = [f"images/{i:04d}.png" for i in range(spec.samples)]
    for i in range(spec.samples):
        blur, noise = rng.uniform(*q_cfg["blur"]), q_cfg["noise"][0]
        black, white = rng.uniform(*q_cfg["black"]), rng.uniform(*q_cfg["white"])
        img: NDArray[np.uint8] | None
        if spec.board is not None:
            img = render_board(
                camera,
                C[i],
                spec.board,
                blur_sigma_px=blur,
                noise_sigma=noise,
                black=black,
                white=white,
                gradient=0.1,
                rng=rng,
            )
        else:
            img = render_tag(
                camera,
                C[i],
                spec.tag_size_m,
                spec.family,
                spec.tag_id,
                blur_sigma_px=blur,
                noise_sigma=noise,
                black=black,
                white=white,
                rng=rng,
            )
        if img is None:  # cannot happen: poses were chosen by the same visibility test
            raise ArmtoolError(f"internal: pose {i} is not renderable")
        cv2.imwrite(str(out / images[i]), img)
        if progress:
            progress(i + 1, spec.samples)
    bad: dict[str, str] = {}
    if spec.bad_samples:
        picks = rng.choice(spec.samples, size=min(spec.bad_samples, spec.samples // 4), replace=False)
        for k, i in enumerate(picks):
            if k % 2 == 0:
                j = int(rng.integers(chain.n))
                readings[i, j] += math.radians(5.0)
                bad[str(i)] = f"joint '{chain.joint_names[j]}' reading off by +5°"
            else:
                other = (int(i) + 1 + int(rng.integers(spec.samples - 1))) % spec.samples
                images[i] = f"images/{other:04d}.png"
                bad[str(i)] = f"image label points at sample {other}'s image"
    rows = ["id,image," + ",".join(chain.joint_names)]
    for i in range(spec.samples):
        rows.append(f"{i},{images[i]}," + ",".join(f"{v:.9f}" for v in readings[i]))
    _write_text(out / "samples.csv", "\n".join(rows) + "\n")
    if spec.setup is Setup.EYE_TO_HAND:
        hints = {"camera_in_base": se3.inv(L), "tag_in_flange": R}
    else:
        hints = {"camera_in_flange": se3.inv(L), "tag_in_base": R}
    manifest = manifest_document("armtool calibrate simulate", spec.setup, chain, spec.target)
    manifest["hints"] = {k: _rough(v, rng) for k, v in hints.items()}
    _write_text(out / "dataset.yaml", yaml.safe_dump(manifest, sort_keys=False))
    # The truth, kept apart.
    corrections = joint_corrections(truth_model, x_true)
    true_text = corrected_text(text, corrections, "robot.urdf")
    check_reproduces(true_text, truth_model, x_true, "truth/robot_true.urdf")
    _write_text(out / "truth" / "robot_true.urdf", relocate_meshes(true_text, out, out / "truth"))
    true_k = truth_model.split(x_true)
    truth = {
        "note": "ground truth of this synthetic dataset; armtool calibrate fit never reads it",
        "setup": spec.setup.value,
        "left_frame": _pose_dict(L),
        "right_frame": _pose_dict(R),
        "joints": {
            name: {
                "origin_t_m": true_k.origin[i, :3].tolist(),
                "origin_r_rad": true_k.origin[i, 3:].tolist(),
                "offset_rad": float(true_k.offset[i]),
            }
            for i, name in enumerate(chain.joint_names)
        },
        "bad_samples": bad,
        "spec": {
            "quality": spec.quality.value,
            "seed": spec.seed,
            "samples": spec.samples,
            "tag_size_m": spec.tag_size_m,
            "target": spec.target.describe(),
        },
    }
    _write_text(out / "truth" / "truth.yaml", yaml.safe_dump(truth, sort_keys=False))
    val_rows = [",".join(chain.joint_names)] + [",".join(f"{v:.9f}" for v in q) for q in Q_val]
    _write_text(out / "truth" / "validation.csv", "\n".join(val_rows) + "\n")
    return {"samples": spec.samples, "validation": spec.validation, "bad_samples": bad, "joints": chain.joint_names}


def _pose_dict(T: Array) -> dict[str, list[float]]:
    return {"xyz": [float(v) for v in T[:3, 3]], "rpy": [float(v) for v in se3.rpy_of(T[:3, :3])]}


def _rough(T: Array, rng: np.random.Generator) -> dict[str, list[float]]:
    """A hint as a person would measure it: a few cm and degrees off."""
    noisy = T @ se3.delta(np.concatenate([rng.normal(scale=0.02, size=3), rng.normal(scale=math.radians(3), size=3)]))
    return {k: [round(v, 3) for v in vals] for k, vals in _pose_dict(noisy).items()}
