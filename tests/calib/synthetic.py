"""A calibration problem with exact truth and no images: corners projected from a true robot.

Corner noise defaults to 0.05 px per coordinate: the AprilTag refinement measured 0.07 px median
corner error (research/calibration.md §2), which is about that per coordinate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from armtool.calib.choices import Setup
from armtool.calib.fit.measurements import CornerMeasurements, Measurements, PointMeasurements, PoseMeasurements
from armtool.calib.inputs.conventions import PoseFrame
from armtool.calib.inputs.dataset import Sample
from armtool.calib.inputs.observations import Observation
from armtool.calib.model import se3
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.calib.simulation.simulate import SimulationSpec, _place, _visible, default_camera, true_errors
from armtool.calib.simulation.truth import Truth
from armtool.calib.targets.apriltag import tag_object_points
from armtool.model.chain import Chain


@dataclass
class Synthetic:
    model: CalibModel  # nominal, frames at identity
    camera: CameraModel
    samples: list[Sample]
    observations: dict[str, Observation]
    truth: Truth
    size_m: float = 0.08

    @property
    def measurements(self) -> CornerMeasurements:
        return self.measured(self.observations)

    def measured(self, observations: dict[str, Observation]) -> CornerMeasurements:
        """These corners, or others (a mislabeled image, a rejected detection), as the fit takes them."""
        return CornerMeasurements(self.camera, observations, tag_object_points(self.size_m))


def make_problem(
    chain: Chain,
    n: int = 40,
    noise_px: float = 0.05,
    seed: int = 0,
    setup: Setup = Setup.EYE_TO_HAND,
    freeze_joint: int | None = None,
    errors: bool = True,
) -> Synthetic:
    spec = SimulationSpec(samples=n, setup=setup, seed=seed)
    rng = np.random.default_rng(seed)
    nominal = CalibModel(chain, setup, np.eye(4), np.eye(4))
    camera = default_camera()
    L, R, pool = _place(nominal, spec, rng, camera)
    if freeze_joint is not None:
        pool[:, freeze_joint] = 0.3
    x_true = true_errors(nominal, spec, rng) if errors else np.zeros(nominal.size)
    true_model = nominal.with_frames(L, R)
    visible = _visible(true_model, x_true, camera, pool[:8000], spec)
    chosen = rng.choice(visible, size=n + 20, replace=False)
    Q, Q_val = pool[chosen[:n]], pool[chosen[n:]]
    pts = true_model.corners_in_camera(x_true, Q, tag_object_points(spec.tag_size_m)).reshape(-1, 3)
    uv = camera.project(pts).reshape(n, 4, 2) + rng.normal(scale=noise_px, size=(n, 4, 2))
    samples = [Sample(str(i), i + 2, Q[i].copy(), None) for i in range(n)]
    obs = {s.id: Observation(s.id, uv[i]) for i, s in enumerate(samples)}
    return Synthetic(nominal, camera, samples, obs, Truth(x_true, Q_val, {}))


@dataclass
class Measured:
    """A pose or point problem with exact truth: what a ChArUco pipeline or a tracker would report."""

    model: CalibModel  # nominal, frames at identity, with the measurement's names
    samples: list[Sample]
    measurements: Measurements
    truth: Truth
    L: Array  # the true measurement frames
    R: Array


def _sensor_frames(setup: Setup, rng: np.random.Generator) -> tuple[Array, Array]:
    """(L, R) of a plausible setup: eye-in-hand, a sensor 9 cm off the flange and a target 0.6 m
    out from the base; eye-to-hand, a sensor 1.5 m away and a target 5 cm off the flange."""
    rng.normal(size=3)  # drawn as before (a turn that cancelled out), so the rest of the stream is unchanged
    if setup is Setup.EYE_IN_HAND:
        sensor_in_flange = se3.xyz_rpy([0.09, -0.01, 0.04], [0.0, 0.0, 1.57])
        target_in_base = se3.xyz_rpy([0.55, -0.2, 0.0], [0.0, 0.02, 0.3])
        return se3.inv(sensor_in_flange), target_in_base
    sensor_in_base = se3.xyz_rpy([1.4, 0.5, 0.9], [-2.1, 0.0, 1.9])
    target_in_flange = se3.xyz_rpy([0.01, 0.02, 0.05], [0.1, 0.2, 0.3])
    return se3.inv(sensor_in_base), target_in_flange


def make_measured(
    chain: Chain,
    kind: str = "pose",
    n: int = 60,
    setup: Setup = Setup.EYE_IN_HAND,
    noise_mm: float = 0.05,
    noise_deg: float = 0.01,
    seed: int = 0,
    frame: PoseFrame = PoseFrame.SENSOR_IN_TARGET,
    errors: bool = True,
) -> Measured:
    """Measured target-in-sensor poses (or points) of a true robot with injected errors, plus
    Gaussian noise: position noise_mm per coordinate, rotation noise_deg per axis."""
    rng = np.random.default_rng(seed)
    sensor, target = ("camera", "board") if kind == "pose" else ("tracker", "point")
    nominal = CalibModel(chain, setup, np.eye(4), np.eye(4), sensor=sensor, target=target)
    L, R = _sensor_frames(setup, rng)
    if kind == "point":
        R = se3.make(t=R[:3, 3])
    x_true = true_errors(nominal, SimulationSpec(), rng) if errors else np.zeros(nominal.size)
    Q = chain.random(rng, n + 20)
    Q_fit, Q_val = Q[:n], Q[n:]
    C = nominal.with_frames(L, R).tag_in_camera(x_true, Q_fit)
    samples = [Sample(str(i), i + 2, Q_fit[i].copy(), None) for i in range(n)]
    measurements: Measurements
    if kind == "pose":
        # The noise of the pose as the file states it (the sensor's position in the target frame,
        # say): what the fit's noise estimate must find again.
        stated = se3.inv(C) if frame is PoseFrame.SENSOR_IN_TARGET else C
        turns = rng.normal(scale=math.radians(noise_deg), size=(n, 3))
        shifts = rng.normal(scale=noise_mm * 1e-3, size=(n, 3))
        noisy = np.stack(
            [se3.make(t=d) @ T @ se3.delta(np.concatenate([np.zeros(3), w])) for T, d, w in zip(stated, shifts, turns)]
        )
        noisy = se3.inv(noisy) if frame is PoseFrame.SENSOR_IN_TARGET else noisy
        measurements = PoseMeasurements({s.id: T for s, T in zip(samples, noisy)}, frame, sensor, target, "poses.csv")
    else:
        points = C[:, :3, 3] + rng.normal(scale=noise_mm * 1e-3, size=(n, 3))
        measurements = PointMeasurements({s.id: p for s, p in zip(samples, points)}, sensor, target, "points.csv")
    return Measured(nominal, samples, measurements, Truth(x_true, Q_val, {}), L, R)
