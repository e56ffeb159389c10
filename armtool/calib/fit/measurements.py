"""A dataset's measurements by sample id, and the residual problem of the samples that have one.

Between the inputs and the fit: detected target corners (`observations.observe`), measured poses
or measured points (a dataset's `observations:` rows, `measured.read_rows`) become the residual
problem of the usable samples (`problems`). Kept apart from both sides so that reading a dataset
never needs the fit, and the fit's residuals never need the dataset's files.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence

import numpy as np

from armtool.calib.fit.problems import CornerProblem, PointProblem, PoseProblem, Problem
from armtool.calib.inputs.conventions import PoseConvention, PoseFrame
from armtool.calib.inputs.dataset import Sample
from armtool.calib.inputs.measured import MeasurementSpec
from armtool.calib.inputs.observations import Observation
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError


class Measurements(ABC):
    """A dataset's measurements by sample id: which samples are usable, and their residual problem."""

    sensor: str  # names the frames: `camera_in_flange`, `tracker_in_base`, ...
    target: str

    @abstractmethod
    def reason(self, sample_id: str) -> str | None:
        """Why a sample has no usable measurement (no tag detected, no row in the file), or None."""

    @abstractmethod
    def problem(self, model: CalibModel, samples: Sequence[Sample]) -> Problem:
        """The residual problem of usable samples."""

    def merged(self, other: Measurements, prefix: str) -> Measurements:
        """These measurements and `other`'s (a validation dataset's), its ids prefixed."""
        raise ArmtoolError(f"cannot merge {type(other).__name__} into {type(self).__name__}")


class CornerMeasurements(Measurements):
    """Detected target corners per sample (`observations.observe`), of a target's points (P, 3)."""

    sensor, target = "camera", "tag"

    def __init__(self, camera: CameraModel, observations: dict[str, Observation], points: Array) -> None:
        self.camera, self.observations, self.points = camera, observations, points

    def reason(self, sample_id: str) -> str | None:
        ob = self.observations[sample_id]
        return ob.reason if ob.corners_px is None else None

    def merged(self, other: Measurements, prefix: str) -> Measurements:
        if not isinstance(other, CornerMeasurements):
            return super().merged(other, prefix)
        renamed = {prefix + k: Observation(prefix + k, o.corners_px, o.reason) for k, o in other.observations.items()}
        return CornerMeasurements(self.camera, {**self.observations, **renamed}, self.points)

    def problem(self, model: CalibModel, samples: Sequence[Sample]) -> CornerProblem:
        P = len(self.points)
        uv = (
            np.stack([np.asarray(self.observations[s.id].corners_px, dtype=np.float64) for s in samples])
            if samples
            else np.zeros((0, P, 2))
        )
        return CornerProblem(model, self.camera, _joints(samples, model), uv, self.points)


class PoseMeasurements(Measurements):
    """Measured target-in-sensor poses (4, 4) per sample id, and the direction the file states them in."""

    def __init__(self, poses: dict[str, Array], frame: PoseFrame, sensor: str, target: str, source: str) -> None:
        self.poses, self.frame, self.sensor, self.target, self.source = poses, frame, sensor, target, source

    def reason(self, sample_id: str) -> str | None:
        return None if sample_id in self.poses else f"no usable row in {self.source}"

    def merged(self, other: Measurements, prefix: str) -> Measurements:
        if not isinstance(other, PoseMeasurements):
            return super().merged(other, prefix)
        poses = {**self.poses, **{prefix + k: v for k, v in other.poses.items()}}
        return PoseMeasurements(poses, self.frame, self.sensor, self.target, self.source)

    def problem(self, model: CalibModel, samples: Sequence[Sample]) -> PoseProblem:
        measured = np.stack([self.poses[s.id] for s in samples]) if samples else np.zeros((0, 4, 4))
        return PoseProblem(model, _joints(samples, model), measured, self.frame)


class PointMeasurements(Measurements):
    """Measured points (3,) in the sensor frame per sample id."""

    def __init__(self, points: dict[str, Array], sensor: str, target: str, source: str) -> None:
        self.points, self.sensor, self.target, self.source = points, sensor, target, source

    def reason(self, sample_id: str) -> str | None:
        return None if sample_id in self.points else f"no usable row in {self.source}"

    def merged(self, other: Measurements, prefix: str) -> Measurements:
        if not isinstance(other, PointMeasurements):
            return super().merged(other, prefix)
        points = {**self.points, **{prefix + k: v for k, v in other.points.items()}}
        return PointMeasurements(points, self.sensor, self.target, self.source)

    def problem(self, model: CalibModel, samples: Sequence[Sample]) -> PointProblem:
        measured = np.stack([self.points[s.id] for s in samples]) if samples else np.zeros((0, 3))
        return PointProblem(model, _joints(samples, model), measured)


def _joints(samples: Sequence[Sample], model: CalibModel) -> Array:
    return np.stack([s.q for s in samples]) if samples else np.zeros((0, model.chain.n))


def dataset_measurements(spec: MeasurementSpec, rows: dict[str, Array]) -> Measurements:
    """The fit's measurements of a dataset's rows: target-in-sensor poses, or points, in metres."""
    ids = list(rows)
    values = np.stack([rows[i] for i in ids]) if ids else np.zeros((0, len(spec.columns)))
    source = spec.file.name
    convention = spec.convention
    if isinstance(convention, PoseConvention):
        poses = convention.poses(values) if ids else np.zeros((0, 4, 4))
        return PoseMeasurements(dict(zip(ids, poses)), convention.frame, spec.sensor, spec.target, source)
    points = convention.points(values) if ids else np.zeros((0, 3))
    return PointMeasurements(dict(zip(ids, points)), spec.sensor, spec.target, source)
