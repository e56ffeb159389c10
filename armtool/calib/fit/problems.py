"""What a fit minimises: each sample's residuals for one kind of measurement, weighted by its noise.

Three kinds of measurement, one residual problem each, all on the same model cMt = L · F(q)^±1 · R:
- `CornerProblem`: target corners in the image (pixels), from AprilTag or board detection;
- `PoseProblem`: the measured pose of the target in the sensor (a ChArUco or hand-eye pipeline,
  a tracker's rigid body): a position block (m) and a rotation block (rad);
- `PointProblem`: one measured 3-D point in the sensor's frame (a laser tracker's reflector, a
  single mocap marker): the target frame is only a point, so its rotation is not a parameter.

Residual coordinates come in blocks (pixels; position; rotation) that each have a noise level σ:
the fit divides every coordinate by its block's σ, so positions in metres and angles in radians
count by how well they are measured (`noise.estimate` finds the σ's from the data). Pose residuals
are expressed as the dataset states the pose (`PoseFrame`): for camera-in-board poses, the camera's
position error in the board frame, which is what a reader of that file compares.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from armtool.calib.inputs.conventions import PoseFrame
from armtool.calib.model import se3
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError

JACOBIAN_STEP = 1e-6  # central differences on a smooth model: parameters are mm, mrad, 0.1 % of gain


@dataclass(frozen=True)
class Block:
    """A group of residual coordinates that share one noise level."""

    name: str  # "corner", "position" or "rotation"
    unit: str  # how reports show it
    to_unit: float  # internal unit (px, m, rad) → `unit`
    statistic: Literal["rms", "norm"]  # per sample: RMS over the coordinates (pixels), or the vector's length

    def describe(self) -> str:
        return {"corner": "corner reprojection", "position": "position", "rotation": "rotation"}[self.name]


CORNER = Block("corner", "px", 1.0, "rms")
POSITION = Block("position", "mm", 1e3, "norm")
ROTATION = Block("rotation", "deg", math.degrees(1.0), "norm")


class Problem(ABC):
    """Residuals of some samples: raw per coordinate, or divided by the noise for the fit.

    Subclasses say how a target-in-sensor pose becomes a sample's residual coordinates
    (`_residuals`), which coordinates a sample measured (`seen`), and how to start the frames
    (`_closed_form_frames`).
    """

    blocks: tuple[Block, ...]
    column_blocks: NDArray[np.intp]  # (k,) the block of each of a sample's k coordinates

    def __init__(self, model: CalibModel, Q: Array, sigma: Array | None = None) -> None:
        self.model, self.Q = model, Q
        self.sigma = np.ones(len(self.blocks)) if sigma is None else np.asarray(sigma, dtype=np.float64)

    # -- what each kind defines ------------------------------------------------------------------

    @abstractmethod
    def _residuals(self, C: Array) -> Array:
        """Raw residuals (B, N, k), measured minus predicted, of target-in-sensor poses C (B, N, 4, 4)
        of every sample; 0 where a coordinate was not measured."""

    @abstractmethod
    def subset(self, rows: Sequence[int]) -> Problem:
        """The same problem on some of its samples (by row)."""

    @abstractmethod
    def with_model(self, model: CalibModel) -> Problem:
        """The same samples on another model (new frames)."""

    @abstractmethod
    def _closed_form_frames(self) -> tuple[Array, Array]:
        """(L, R) from the nominal robot and the measurements; ArmtoolError when they do not determine them."""

    @property
    @abstractmethod
    def seen(self) -> NDArray[np.bool_]:
        """(N, k): which coordinates each sample measured."""

    def frame_parameters(self) -> list[int]:
        """The measurement frames' parameters that change a measurement (all twelve by default)."""
        return self.model.layout.frames

    # -- shared --------------------------------------------------------------------------------

    def start_frames(self, hints: dict[str, Array]) -> tuple[Array, Array]:
        """(L, R) close enough to start the fit: the closed form from the nominal robot and the
        measurements, or the dataset's hints when that fails."""
        try:
            return self._closed_form_frames()
        except ArmtoolError:
            found = _hinted_frames(self.model, hints)
            if found is None:
                raise
            return found

    @property
    def samples(self) -> int:
        return int(self.Q.shape[0])

    @property
    def coordinates(self) -> int:
        """Measured coordinates: what the parameters are fitted to."""
        return int(self.seen.sum())

    def with_sigma(self, sigma: Array) -> Problem:
        out = self.with_model(self.model)
        out.sigma = np.asarray(sigma, dtype=np.float64)
        return out

    def raw(self, x: Array) -> Array:
        """(N, k) raw residuals at x."""
        C = self.model.tag_in_camera(x, self.Q)
        out: Array = self._residuals(C[None])[0]
        return out

    def weights(self) -> Array:
        weights: Array = 1.0 / self.sigma[self.column_blocks]
        return weights

    def residuals(self, x: Array) -> Array:
        """The fit's residual vector: every coordinate divided by its block's σ."""
        return (self.raw(x) * self.weights()).ravel()

    def jacobian(self, x: Array, free: Sequence[int], h: float = JACOBIAN_STEP) -> Array:
        """∂ `residuals` / ∂ the parameters `free`: (N·k, len(free)). The residuals' derivatives
        along the six left twists of cMt, by central differences, times each parameter's twist
        (`CalibModel.twists`)."""
        N, k = self.samples, len(self.column_blocks)
        if not free or N == 0:
            return np.zeros((N * k, len(free)))
        C, twists = self.model.twists(x, self.Q, list(free))  # cMt, and (N, 6, P)
        steps = np.concatenate([np.eye(6), -np.eye(6)]) * h
        moved = se3.delta_batch(steps)[:, None] @ C[None]  # (12, N, 4, 4)
        r = self._residuals(moved) * self.weights()
        along = np.moveaxis((r[:6] - r[6:]) / (2 * h), 0, -1)  # (N, k, 6)
        J: Array = np.einsum("nkm,nmp->nkp", along, twists).reshape(N * k, len(free))
        return J

    def per_sample(self, x: Array) -> dict[str, Array]:
        """Each block's per-sample figure in its unit: pixel RMS, position or rotation error length."""
        return self.figures(self.raw(x))

    def figures(self, r: Array) -> dict[str, Array]:
        """`per_sample` of the raw residuals r (N, k)."""
        figures = self.per_block(r, lengths=True)
        return {block.name: figures[:, b] * block.to_unit for b, block in enumerate(self.blocks)}

    def per_block(self, r: Array, lengths: bool = False) -> Array:
        """(N, B) each sample's RMS of `r` (N, k) over each block's measured coordinates; with
        `lengths`, the vector's length instead for the blocks whose statistic is "norm"."""
        seen = self.seen
        out = np.empty((len(r), len(self.blocks)))
        for b, block in enumerate(self.blocks):
            cols = self.column_blocks == b
            squares = (r[:, cols] ** 2).sum(axis=1)
            if not (lengths and block.statistic == "norm"):
                squares = squares / np.maximum(seen[:, cols].sum(axis=1), 1)
            out[:, b] = np.sqrt(squares)
        return out

    def normalized_rms(self, r: Array) -> Array:
        """(N,) each sample's RMS of its noise-weighted raw residuals r (N, k): ~1 for a sample as
        good as the noise."""
        w = r * self.weights()
        rms: Array = np.sqrt((w**2).sum(axis=1) / np.maximum(self.seen.sum(axis=1), 1))
        return rms

    def block_rms(self, x: Array) -> Array:
        """(N, B) each sample's RMS of each block's noise-weighted coordinates: a sample whose
        position is off stands out in its position block even when its rotation is good."""
        out: Array = self.per_block(self.raw(x)) / self.sigma
        return out

    def outliers(self, r: Array, limit: Array) -> NDArray[np.bool_]:
        """(N,) samples whose raw residuals r (N, k) are beyond a per-block outlier limit in any block."""
        flags: NDArray[np.bool_] = np.asarray((self.per_block(r) / self.sigma > limit).any(axis=1), dtype=bool)
        return flags

    def noise(self) -> dict[str, float]:
        """The σ's in each block's unit (e.g. {'position': 0.6 mm, 'rotation': 0.1°})."""
        return {block.name: float(s * block.to_unit) for block, s in zip(self.blocks, self.sigma)}


class CornerProblem(Problem):
    """Pixels of the target's points (a tag's 4 corners, a board's corners) in each image.

    `uv` (N, P, 2) holds each sample's pixels of the target's P points (`points`, (P, 3)), NaN
    where an image does not show a point (a partial board view): those coordinates count 0.
    """

    blocks = (CORNER,)

    def __init__(
        self,
        model: CalibModel,
        camera: CameraModel,
        Q: Array,
        uv: Array,
        points: Array,
        sigma: Array | None = None,
    ) -> None:
        self.camera, self.uv, self.points = camera, uv, points
        self.column_blocks = np.zeros(2 * points.shape[0], dtype=np.intp)
        self._seen = np.isfinite(uv).reshape(len(uv), -1)
        super().__init__(model, Q, sigma)

    @property
    def seen(self) -> NDArray[np.bool_]:
        return self._seen

    def predict(self, C: Array) -> Array:
        """Pixels (B, N, P, 2) of the target points for target-in-camera poses C (B, N, 4, 4)."""
        pts = np.einsum("bnij,pj->bnpi", C[..., :3, :3], self.points) + C[..., None, :3, 3]
        out: Array = self.camera.project(pts.reshape(-1, 3)).reshape(*C.shape[:2], -1, 2)
        return out

    def _residuals(self, C: Array) -> Array:
        uv = self.uv.reshape(len(self.uv), -1)
        predicted = self.predict(C).reshape(C.shape[0], C.shape[1], -1)
        out: Array = np.where(np.isfinite(uv), np.nan_to_num(uv) - predicted, 0.0)
        # Residuals are measured − predicted for every kind; a pixel behind the camera is a huge error.
        return np.where(np.isfinite(out), out, 1e6)

    def subset(self, rows: Sequence[int]) -> CornerProblem:
        rows = list(rows)
        return CornerProblem(self.model, self.camera, self.Q[rows], self.uv[rows], self.points, self.sigma)

    def with_model(self, model: CalibModel) -> CornerProblem:
        return CornerProblem(model, self.camera, self.Q, self.uv, self.points, self.sigma)

    def _closed_form_frames(self) -> tuple[Array, Array]:
        """The target's pose in each image (IPPE on the points it shows), then the closed-form AX = XB."""
        from armtool.calib.fit.handeye import initial_frames
        from armtool.calib.targets.pose import planar_pose

        model = self.model
        F = model.flange(np.zeros(model.size), self.Q)
        flanges, tags = [], []
        for i in range(len(self.Q)):
            cMt, _rms, ambiguous = planar_pose(self.points, self.uv[i], self.camera)
            if not ambiguous:
                flanges.append(F[i])
                tags.append(cMt)
        if len(tags) < 3:
            raise ArmtoolError("fewer than 3 unambiguous tag poses")
        return initial_frames(model.setup, flanges, tags)


class PoseProblem(Problem):
    """The measured pose of the target in the sensor, per sample: 3 position and 3 rotation coordinates.

    `measured` (N, 4, 4) holds target-in-sensor poses. The residual is taken in the direction the
    dataset states (`frame`): for sensor-in-target files, the sensor's position in the target frame
    and the rotation between measured and predicted (log(R_pred⁻¹ R_meas)).
    """

    blocks = (POSITION, ROTATION)

    def __init__(
        self, model: CalibModel, Q: Array, measured: Array, frame: PoseFrame, sigma: Array | None = None
    ) -> None:
        self.measured, self.frame = measured, frame
        self.column_blocks = np.array([0, 0, 0, 1, 1, 1], dtype=np.intp)
        self._expected = se3.inv(measured) if frame is PoseFrame.SENSOR_IN_TARGET else measured
        super().__init__(model, Q, sigma)

    @property
    def seen(self) -> NDArray[np.bool_]:
        return np.ones((len(self.Q), 6), dtype=bool)

    def _residuals(self, C: Array) -> Array:
        P = se3.inv(C) if self.frame is PoseFrame.SENSOR_IN_TARGET else C
        M = self._expected
        position = M[None, :, :3, 3] - P[..., :3, 3]
        rotation = se3.log3_batch(np.swapaxes(P[..., :3, :3], -1, -2) @ M[None, :, :3, :3])
        return np.concatenate([position, rotation], axis=-1)

    def subset(self, rows: Sequence[int]) -> PoseProblem:
        rows = list(rows)
        return PoseProblem(self.model, self.Q[rows], self.measured[rows], self.frame, self.sigma)

    def with_model(self, model: CalibModel) -> PoseProblem:
        return PoseProblem(model, self.Q, self.measured, self.frame, self.sigma)

    def _closed_form_frames(self) -> tuple[Array, Array]:
        """The closed-form AX = XB on the measured poses themselves."""
        from armtool.calib.fit.handeye import initial_frames

        F = self.model.flange(np.zeros(self.model.size), self.Q)
        return initial_frames(self.model.setup, list(F), list(self.measured))


class PointProblem(Problem):
    """One measured point in the sensor frame per sample: 3 position coordinates.

    The target frame R is the point (its translation); its rotation changes nothing, so it is not
    among the parameters (`frame_parameters`).
    """

    blocks = (POSITION,)

    def __init__(self, model: CalibModel, Q: Array, measured: Array, sigma: Array | None = None) -> None:
        self.measured = measured
        self.column_blocks = np.zeros(3, dtype=np.intp)
        super().__init__(model, Q, sigma)

    @property
    def seen(self) -> NDArray[np.bool_]:
        return np.ones((len(self.Q), 3), dtype=bool)

    def _residuals(self, C: Array) -> Array:
        out: Array = self.measured[None] - C[..., :3, 3]
        return out

    def frame_parameters(self) -> list[int]:
        frames = self.model.layout.frames
        return frames[:6] + frames[6:9]  # the sensor frame, and the point's position

    def subset(self, rows: Sequence[int]) -> PointProblem:
        rows = list(rows)
        return PointProblem(self.model, self.Q[rows], self.measured[rows], self.sigma)

    def with_model(self, model: CalibModel) -> PointProblem:
        return PointProblem(model, self.Q, self.measured, self.sigma)

    def _closed_form_frames(self) -> tuple[Array, Array]:
        """Alternating closed forms (Kabsch for the sensor frame, linear least squares for the point)."""
        from armtool.calib.fit.handeye import initial_point_frames

        F = self.model.flange(np.zeros(self.model.size), self.Q)
        return initial_point_frames(self.model.setup, F, self.measured)


def _hinted_frames(model: CalibModel, hints: dict[str, Array]) -> tuple[Array, Array] | None:
    """(L, R) from the dataset's hints (`camera_in_base` and `tag_in_flange`, …), or None."""
    sensor, target = model.frame_names()
    if sensor in hints and target in hints:
        return se3.inv(hints[sensor]), hints[target]
    return None
