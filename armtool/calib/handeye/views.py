"""The board in each image of a hand-eye dataset, and the arrays the fits take.

Each image's corners come from armtool's detectors (`armtool.calib.inputs.observations.detect_images`:
chessboards ordered by handedness and colour, ChArUco and AprilTag corners with their ids), and
its pose from IPPE (`armtool.calib.targets.pose.planar_pose`), which the closed forms start from.
An image without a usable board keeps its reason and is left out.

Both setups are one equation, G_i · X · C_i = Z, with C_i the board in the camera:
eye-in-hand, G_i the flange in the base, X the camera in the flange, Z the board in the base;
eye-to-hand, G_i the base in the flange, X the camera in the base, Z the board in the flange.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from armtool.calib.choices import ChessboardDetector, Setup
from armtool.calib.handeye.dataset import HandEyeDataset
from armtool.calib.model import se3
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.calib.targets.spec import Target

MIN_POINTS = 4  # a planar pose needs 4 points


@dataclass(frozen=True)
class View:
    """One image: its name and row, the target's points it shows (ids into `Target.points_m`), their
    pixels, and the target's pose by IPPE; `reason` says why the image is not used ("" when it is)."""

    name: str
    line: int
    ids: NDArray[np.intp]
    pixels: Array
    reason: str = ""
    cMt: Array | None = None
    pnp_rms_px: float = math.nan
    ambiguous: bool = False  # IPPE's two poses explain the corners about as well: not a start

    @property
    def usable(self) -> bool:
        return not self.reason


def find_views(
    ds: HandEyeDataset,
    camera: CameraModel,
    detector: ChessboardDetector = ChessboardDetector.CLASSIC,
    progress: Callable[[int, int], None] | None = None,
) -> list[View]:
    """Every shot's view, in the poses file's order."""
    from armtool.calib.inputs.observations import detect_images

    names = {str(s.line): s.image for s in ds.shots}
    found = detect_images(names, ds.target, camera, detector, progress)
    views = []
    for shot in ds.shots:
        name = _relative(ds, shot.image)
        corners, reason = found[str(shot.line)].corners_px, found[str(shot.line)].reason
        if corners is None:
            views.append(View(name, shot.line, np.zeros(0, dtype=np.intp), np.zeros((0, 2)), reason or "not found"))
            continue
        ids = np.flatnonzero(np.all(np.isfinite(corners), axis=1))
        views.append(posed(View(name, shot.line, ids, corners[ids]), ds.target, camera))
    return views


def posed(view: View, target: Target, camera: CameraModel) -> View:
    """The view with the target's pose by IPPE (or the reason it has none)."""
    from armtool.calib.targets.pose import planar_pose

    if len(view.ids) < MIN_POINTS:
        return replace(view, reason=f"{len(view.ids)} corners found, at least {MIN_POINTS} needed")
    cMt, rms, ambiguous = planar_pose(target.points_m[view.ids], view.pixels, camera, square=target.board is None)
    if not math.isfinite(rms):
        return replace(view, reason="no pose explains the corners (are they on one line?)")
    return replace(view, cMt=cMt, pnp_rms_px=rms, ambiguous=ambiguous)


def _relative(ds: HandEyeDataset, path: Path) -> str:
    try:
        return str(path.relative_to(ds.root))
    except ValueError:
        return str(path)


@dataclass(frozen=True)
class Observations:
    """What the fits take: per image G (N, 4, 4) and its IPPE pose C (N, 4, 4); per corner its
    image, board point and pixel, stacked (M)."""

    setup: Setup
    G: Array
    C: Array
    start: NDArray[np.bool_]  # (N,) the IPPE pose is unambiguous: it may start a closed form
    pnp_rms_px: Array  # (N,) each image's own IPPE fit
    image: NDArray[np.intp]
    points: Array
    pixels: Array

    @property
    def count(self) -> int:
        return len(self.G)

    def subset(self, images: Sequence[int] | NDArray[np.intp]) -> Observations:
        """The images `images` (in that order) and their corners."""
        rows = np.asarray(images, dtype=np.intp)
        new = np.full(self.count, -1, dtype=np.intp)
        new[rows] = np.arange(len(rows))
        keep = new[self.image] >= 0
        return Observations(
            self.setup,
            self.G[rows],
            self.C[rows],
            self.start[rows],
            self.pnp_rms_px[rows],
            new[self.image[keep]],
            self.points[keep],
            self.pixels[keep],
        )

    @property
    def pixel_noise_px(self) -> float:
        """The detector's noise per coordinate: the median over images of each IPPE fit's residual
        with its 6 pose parameters' share removed."""
        n = self.corners_per_image()
        fit = n > 3
        per_image = self.pnp_rms_px[fit] * np.sqrt(n[fit] / (2 * n[fit] - 6))
        return float(np.median(per_image)) if len(per_image) else float("nan")

    def corners_per_image(self) -> NDArray[np.intp]:
        return np.bincount(self.image, minlength=self.count)

    def flange_errors(self, X: Array, Z: Array) -> Array:
        """Each image's flange pose error (N, 6: translation m, rotation vector rad, in the flange frame):
        the reported flange pose against the one its IPPE pose and the frames predict, F⁻¹ · F*."""
        predicted = Z @ se3.inv(self.C) @ se3.inv(X)  # G* = Z C⁻¹ X⁻¹
        D = se3.inv(self.G) @ predicted if self.setup is Setup.EYE_IN_HAND else self.G @ se3.inv(predicted)
        return np.concatenate([D[:, :3, 3], se3.log3_batch(D[:, :3, :3])], axis=1)


def observations(views: Sequence[View], flanges: Array, setup: Setup, target: Target) -> Observations:
    """The usable views as arrays; `flanges` (N, 4, 4) are the flange poses in the base, one per view."""
    used = [k for k, v in enumerate(views) if v.usable]
    F = flanges[used]
    G = F if setup is Setup.EYE_IN_HAND else se3.inv(F)
    points = target.points_m
    poses = [views[k].cMt for k in used]
    C = np.stack([c for c in poses if c is not None]) if used else np.zeros((0, 4, 4))
    return Observations(
        setup,
        np.asarray(G, dtype=np.float64),
        np.asarray(C, dtype=np.float64),
        np.array([not views[k].ambiguous for k in used], dtype=bool),
        np.array([views[k].pnp_rms_px for k in used], dtype=np.float64),
        np.concatenate(
            [np.full(len(views[k].ids), n, dtype=np.intp) for n, k in enumerate(used)] or [np.zeros(0, np.intp)]
        ),
        np.concatenate([points[views[k].ids] for k in used] or [np.zeros((0, 3))]),
        np.concatenate([views[k].pixels for k in used] or [np.zeros((0, 2))]),
    )
