"""The flange poses' conventions checked: when another reading of the poses file explains the images
far better, say which lines of dataset.yaml select it.

Controllers write poses their own way (KUKA: mm and A, B, C = Rz·Ry·Rx in degrees; ABB: mm and a
quaternion w first; UR: m and a rotation vector), and a wrong choice does not fail: it gives frames
whose reprojection errors are tens to hundreds of times the right reading's. So every other
reading of the same columns (`PoseConvention.alternatives`: inverted, the other length unit, the
other quaternion order, every rpy order and angle unit, a matrix stored column by column, and their
combinations), in both setups, is solved by the better of Park–Martin's and Shah's closed forms and
scored by the median of the images' reprojection RMS; the declared reading and the REFINED best are
then refined (MAX_STEPS steps), so that the readings that matter are compared at their best. One
that scores BETTER times better than the declared reading is named. A pose read inverted in the
other setup is the same equations (G_i is F_i⁻¹ either way): they are solved once, and both fixes are
named, to choose from.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from armtool.calib.choices import Setup
from armtool.calib.fit.handeye import AxXbMethod
from armtool.calib.fit.robot_world import AxZbMethod
from armtool.calib.handeye.closed_forms import closed_form
from armtool.calib.handeye.dataset import FRAMES, SECTION, HandEyeDataset
from armtool.calib.handeye.refine import image_rms, refine, reprojection_residuals
from armtool.calib.handeye.views import Observations, View, observations
from armtool.calib.inputs.conventions import PoseConvention
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError

BETTER = 3.0
TIE = 1e-3  # readings whose scores differ by less than this share are the same fit
MAX_STEPS = 15
STARTS = (AxXbMethod.PARK, AxZbMethod.SHAH)
REFINED = 3  # readings refined besides the declared one: the best by their closed form


@dataclass(frozen=True)
class Reading:
    """One way of reading the poses file, and how well the frames fitted to it explain the images."""

    convention: PoseConvention
    setup: Setup
    changes: list[str]  # dataset.yaml lines that select it ([] for the declared one)
    median_rms_px: float


@dataclass(frozen=True)
class ConventionCheck:
    declared: Reading
    better: Reading | None  # the best reading, when it scores at least BETTER times better
    tried: int
    equivalent: Reading | None = None  # another reading that fits exactly as well

    def message(self) -> str:
        if self.better is None:
            return (
                f"the declared conventions fit best: median image reprojection {_px(self.declared)} "
                f"({self.tried} readings tried)"
            )
        ratio = self.declared.median_rms_px / max(self.better.median_rms_px, 1e-12)
        return (
            f"the flange poses fit {ratio:.0f} times better read another way: median image reprojection "
            f"{_px(self.better)} against {_px(self.declared)} as declared"
        )

    def fix(self) -> str:
        if self.better is None:
            return ""
        text = "in dataset.yaml, set " + "; ".join(self.better.changes)
        if self.equivalent is not None:
            text += (
                " (the images fit exactly as well with " + "; ".join(self.equivalent.changes) + ": check which is true)"
            )
        return text


def _px(reading: Reading) -> str:
    return f"{reading.median_rms_px:.2f} px" if math.isfinite(reading.median_rms_px) else "no fit at all"


def check_conventions(ds: HandEyeDataset, views: Sequence[View], camera: CameraModel) -> ConventionCheck:
    """Solve every reading of the poses file in both setups; name one that explains the images far better."""
    assert ds.convention is not None
    declared_first = [ds.setup, Setup.EYE_TO_HAND if ds.setup is Setup.EYE_IN_HAND else Setup.EYE_IN_HAND]
    candidates: list[tuple[PoseConvention, Setup, list[str], Observations | None]] = []
    for setup in declared_first:
        for convention in [ds.convention, *ds.convention.alternatives()]:
            changes = ds.convention.differences(convention, SECTION, FRAMES)
            if setup is not ds.setup:
                changes = [f"setup: {setup.value}", *changes]
            try:
                obs: Observations | None = observations(views, ds.flanges(convention), setup, ds.target)
            except (ValueError, np.linalg.LinAlgError):
                obs = None
            candidates.append((convention, setup, changes, obs))
    # Readings with the same G (a pose inverted in the other setup) are the same equations: one fit.
    solved: list[_Solved] = []
    index: list[int] = []
    for *_reading, obs in candidates:
        same = next((k for k, done in enumerate(solved) if done.same(obs)), None)
        if same is None:
            solved.append(_Solved(obs, *_closed_form_score(obs, camera)))
            same = len(solved) - 1
        index.append(same)
    # The refinement settles the declared reading and the few best ones.
    for k in {index[0], *sorted(range(len(solved)), key=lambda k: solved[k].score)[:REFINED]}:
        solved[k].refine(camera)
    readings = [Reading(c[0], c[1], c[2], solved[i].score) for c, i in zip(candidates, index)]
    declared = readings[0]
    finite = [r for r in readings if math.isfinite(r.median_rms_px)]
    if not finite:
        raise ArmtoolError(
            "no reading of the flange poses gives frames that explain the images",
            ds.poses_file.name,
            "check that each row's pose belongs to its image",
        )
    lowest = min(r.median_rms_px for r in finite)
    tied = [r for r in finite if r.median_rms_px <= lowest * (1 + TIE) + 1e-12]
    best = min(tied, key=lambda r: (r.setup is not ds.setup, len(r.changes)))
    # An equally simple reading that fits as well is worth naming (a pose inverted, or the other setup);
    # one with two more changes (the setup and the pose's frame swapped besides) is not.
    equivalent = [
        r for r in tied if r is not best and r.changes and r is not declared and len(r.changes) <= len(best.changes)
    ]
    better = best if best is not declared and best.median_rms_px * BETTER <= declared.median_rms_px else None
    return ConventionCheck(declared, better, len(readings), equivalent[0] if better and equivalent else None)


def _closed_form_score(obs: Observations | None, camera: CameraModel) -> tuple[float, tuple[Array, Array] | None]:
    """The better of the STARTS closed forms: its median image RMS and its frames."""
    if obs is None:
        return math.inf, None
    best: tuple[float, tuple[Array, Array] | None] = (math.inf, None)
    for method in STARTS:
        try:
            frames = closed_form(method, obs.G[obs.start], obs.C[obs.start])
        except (ArmtoolError, np.linalg.LinAlgError, ValueError):
            continue
        score = _median_rms(obs, *frames, camera)
        if score < best[0]:
            best = (score, frames)
    return best


@dataclass
class _Solved:
    """One set of equations (a reading's G), its frames and score."""

    obs: Observations | None
    score: float
    frames: tuple[Array, Array] | None

    def same(self, obs: Observations | None) -> bool:
        return self.obs is not None and obs is not None and np.allclose(self.obs.G, obs.G, rtol=0.0, atol=1e-9)

    def refine(self, camera: CameraModel) -> None:
        if self.obs is None or self.frames is None:
            return
        try:
            fit = refine(self.obs, *self.frames, camera, max_nfev=MAX_STEPS, rounds=1, fit_noises=False)
        except (ArmtoolError, np.linalg.LinAlgError, ValueError):
            return
        self.score = min(self.score, _median_rms(self.obs, fit.X, fit.Z, camera))


def _median_rms(obs: Observations, X: Array, Z: Array, camera: CameraModel) -> float:
    rms = image_rms(reprojection_residuals(obs, X, Z, camera), obs.image, obs.count)
    return float(np.median(np.where(np.isfinite(rms), rms, np.inf)))
