"""Conventions that cannot silently go wrong: when another reading of the file fits far better, say so.

A pose read inverted, a quaternion read in the other order, roll-pitch-yaw multiplied in the other
order, millimetres read as metres, the camera said to be fixed when it rides on the flange: each
leaves residuals tens to hundreds of times larger than the sensor's noise (a camera-in-board file
read as board-in-camera: 75 mm instead of 5 mm on a real Franka). The nominal robot with only the
measurement frames fitted (a hand-eye calibration) is fast and needs no kinematic errors to be
right, so every reading (`PoseConvention.alternatives`, both setups) gets one, and a reading that
fits at least `BETTER` times better than the declared one is named, with the dataset.yaml lines
that select it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from armtool.calib.choices import Setup
from armtool.calib.fit.measurements import dataset_measurements
from armtool.calib.fit.problems import Problem
from armtool.calib.inputs.conventions import PointConvention, PoseConvention
from armtool.calib.inputs.dataset import Dataset, Sample
from armtool.calib.inputs.measured import MeasurementSpec
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError
from armtool.model.chain import Chain

BETTER = 3.0  # an alternative must fit this many times better than the declared reading to be named
TIE = 1e-3  # readings whose scores differ by less than this share are the same fit
# A right reading converges in a few steps from its closed-form start; a wrong one does not converge
# at all, and its residual after this many steps is already hundreds of times too large.
MAX_STEPS = 30
SCALE_MM, SCALE_DEG = 1.0, 0.1  # a reading's score: position RMS / 1 mm + rotation RMS / 0.1° (a good sensor's noise)


@dataclass(frozen=True)
class Reading:
    """One way of reading the file, and how well the nominal robot explains it."""

    convention: PoseConvention | PointConvention
    setup: Setup
    changes: list[str]  # dataset.yaml lines that select it ([] for the declared one)
    position_mm: float  # RMS over the samples, after fitting the measurement frames
    rotation_deg: float | None  # None for points

    @property
    def score(self) -> float:
        rotation = 0.0 if self.rotation_deg is None else self.rotation_deg / SCALE_DEG
        return self.position_mm / SCALE_MM + rotation

    def describe(self) -> str:
        if not math.isfinite(self.position_mm):
            return "no fit at all"
        rotation = "" if self.rotation_deg is None else f", {self.rotation_deg:.2f}°"
        return f"{self.position_mm:.2f} mm{rotation} RMS"


@dataclass(frozen=True)
class ConventionCheck:
    declared: Reading
    better: Reading | None  # the best reading, when it fits at least BETTER times better
    tried: int
    equivalent: Reading | None = None  # another reading that fits exactly as well (the data cannot tell them apart)

    def message(self) -> str:
        """What the check found, for `calibrate check` and `fit`."""
        if self.better is None:
            return (
                f"the declared conventions fit best: hand-eye-only residual {self.declared.describe()} "
                f"({self.tried} readings tried)"
            )
        ratio = self.declared.score / max(self.better.score, 1e-12)
        return (
            f"the measurements fit {ratio:.0f} times better read another way: {self.better.describe()} against "
            f"{self.declared.describe()} as declared (hand-eye only, nominal robot)"
        )

    def fix(self) -> str:
        if self.better is None:
            return ""
        text = "in dataset.yaml, set " + "; ".join(self.better.changes)
        if self.equivalent is not None:
            text += (
                " (the measurements fit exactly as well with "
                + "; ".join(self.equivalent.changes)
                + ": check which is true)"
            )
        return text


def check_conventions(
    chain: Chain, setup: Setup, spec: MeasurementSpec, rows: dict[str, Array], samples: list[Sample]
) -> ConventionCheck:
    """Fit the measurement frames to every reading of the rows; name one that fits far better."""
    usable = [s for s in samples if s.id in rows]
    declared_setup_first = [setup, Setup.EYE_IN_HAND if setup is Setup.EYE_TO_HAND else Setup.EYE_TO_HAND]
    conventions = [spec.convention, *spec.convention.alternatives()]
    readings: list[Reading] = []
    declared: Reading | None = None
    for s in declared_setup_first:
        for convention in conventions:
            changes = _differences(spec.convention, convention)
            if s is not setup:
                changes = [f"setup: {s.value}", *changes]
            reading = _reading(chain, s, replace(spec, convention=convention), rows, usable, changes)
            if reading is None:
                continue
            readings.append(reading)
            if not changes:
                declared = reading
    if declared is None:  # not even a start: every other reading is measured against an impossible one
        declared = Reading(spec.convention, setup, [], math.inf, None if spec.kind == "point" else math.inf)
    if not readings:
        raise ArmtoolError(
            "the measurement frames could not be fitted to the measurements in any reading",
            "dataset.yaml",
            "check that the samples' joints and the measurements belong together (same ids, same poses)",
        )
    lowest = min(r.score for r in readings)
    # A pose read inverted with the other setup is the same fit (C⁻¹ = R⁻¹ F^∓1 L⁻¹): such ties
    # are settled for the setup the dataset states and the fewest changes.
    tied = [r for r in readings if r.score <= lowest * (1 + TIE) + 1e-12]
    best = min(tied, key=lambda r: (r.setup is not setup, len(r.changes)))
    equivalent = [r for r in tied if r is not best and r.changes and r is not declared]
    better = best if best is not declared and best.score * BETTER <= declared.score else None
    return ConventionCheck(declared, better, len(readings), equivalent[0] if better and equivalent else None)


def checked_conventions(ds: Dataset, chain: Chain, refuse: bool) -> ConventionCheck:
    """How the nominal robot explains the measurements as declared and in every other reading;
    with `refuse`, a reading that fits far better is an error that names the dataset.yaml lines to change."""
    assert ds.measurement is not None
    from armtool.calib.fit.calibration import one_blas_thread

    with one_blas_thread():
        found = check_conventions(chain, ds.setup, ds.measurement, ds.measured_rows, ds.samples)
    if refuse and found.better is not None:
        raise ArmtoolError(
            found.message(),
            f"{ds.root.name}/dataset.yaml",
            found.fix() + " (or fit as declared with `armtool calibrate fit --keep-conventions`)",
        )
    return found


def _differences(declared: PoseConvention | PointConvention, other: PoseConvention | PointConvention) -> list[str]:
    if isinstance(declared, PoseConvention) and isinstance(other, PoseConvention):
        return declared.differences(other)
    if isinstance(declared, PointConvention) and isinstance(other, PointConvention):
        return declared.differences(other)
    raise TypeError("conventions of different kinds")


def _reading(
    chain: Chain, setup: Setup, spec: MeasurementSpec, rows: dict[str, Array], samples: list[Sample], changes: list[str]
) -> Reading | None:
    """How well the nominal robot explains the rows read as `spec` states them, with `setup`."""
    model = CalibModel(chain, setup, np.eye(4), np.eye(4))
    problem = dataset_measurements(spec, rows).problem(model, samples)
    try:
        problem = problem.with_model(model.with_frames(*problem.start_frames({})))
        x = _frames_fit(problem)
    except (ArmtoolError, np.linalg.LinAlgError, ValueError):
        return None
    figures = problem.per_sample(x)
    position = float(np.sqrt(np.mean(figures["position"] ** 2)))
    rotation = float(np.sqrt(np.mean(figures["rotation"] ** 2))) if "rotation" in figures else None
    if not math.isfinite(position):
        return None
    return Reading(spec.convention, setup, changes, position, rotation)


def _frames_fit(problem: Problem) -> Array:
    """The measurement frames fitted with the nominal robot, residuals weighted by a good
    sensor's noise (1 mm, 0.1°) and a soft-L1 loss so that a few bad samples do not decide."""
    from armtool.calib.fit.calibration import solve

    sigma = np.array([SCALE_MM * 1e-3 if b.name == "position" else math.radians(SCALE_DEG) for b in problem.blocks])
    weighted = problem.with_sigma(sigma)
    x, _n = solve(
        weighted, np.zeros(weighted.model.size), weighted.frame_parameters(), robust=True, knee=3.0, max_nfev=MAX_STEPS
    )
    return x
