"""A calibration problem with exact truth and no images: corners projected from a true robot.

Corner noise defaults to 0.05 px per coordinate: the AprilTag refinement measured 0.07 px median
corner error (research/calibration.md §2), which is about that per coordinate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armtool.calib.apriltag import tag_object_points
from armtool.calib.camera import CameraModel
from armtool.calib.choices import Setup
from armtool.calib.dataset import Sample
from armtool.calib.model import CalibModel
from armtool.calib.observations import Observation
from armtool.calib.problems import CornerMeasurements
from armtool.calib.simulate import SimulationSpec, _place, _visible, default_camera, true_errors
from armtool.calib.truth import Truth
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
) -> Synthetic:
    spec = SimulationSpec(samples=n, setup=setup, seed=seed)
    rng = np.random.default_rng(seed)
    nominal = CalibModel(chain, setup, np.eye(4), np.eye(4))
    camera = default_camera()
    L, R, pool = _place(nominal, spec, rng, camera)
    if freeze_joint is not None:
        pool[:, freeze_joint] = 0.3
    x_true = true_errors(nominal, spec, rng)
    true_model = nominal.with_frames(L, R)
    visible = _visible(true_model, x_true, camera, pool[:8000], spec)
    chosen = rng.choice(visible, size=n + 20, replace=False)
    Q, Q_val = pool[chosen[:n]], pool[chosen[n:]]
    pts = true_model.corners_in_camera(x_true, Q, tag_object_points(spec.tag_size_m)).reshape(-1, 3)
    uv = camera.project(pts).reshape(n, 4, 2) + rng.normal(scale=noise_px, size=(n, 4, 2))
    samples = [Sample(str(i), i + 2, Q[i].copy(), None) for i in range(n)]
    obs = {s.id: Observation(s.id, uv[i]) for i, s in enumerate(samples)}
    return Synthetic(nominal, camera, samples, obs, Truth(x_true, Q_val, {}))
