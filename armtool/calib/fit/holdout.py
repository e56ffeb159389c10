"""What is kept out of a fit to validate it: a random share of the samples, a second dataset of
the same setup, or both.

Why: the fit residuals always look good (the fit minimised them); only samples the fit never saw
say whether the calibrated robot is right. A validation dataset must share the robot chain,
setup, camera and tag, or its residuals mean nothing.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from armtool.calib.inputs.dataset import Dataset, Sample
from armtool.calib.model.camera import CameraModel
from armtool.errors import ArmtoolError
from armtool.model.chain import Chain

VALIDATION_PREFIX = "validation:"  # sample ids of a validation dataset, apart from the dataset's own


def split_holdout(ids: list[str], fraction: float, seed: int) -> set[str]:
    """A reproducible random `fraction` of `ids` (rounded to whole samples)."""
    if fraction <= 0:
        return set()
    if not fraction < 1:
        raise ArmtoolError(f"--holdout {fraction} leaves nothing to fit", hint="use a fraction such as 0.3")
    rng = np.random.default_rng(seed)
    count = int(round(fraction * len(ids)))
    return set(rng.choice(ids, size=count, replace=False).tolist()) if count else set()


def check_same_setup(
    ds: Dataset,
    chain: Chain,
    camera: CameraModel | None,
    vds: Dataset,
    vchain: Chain | None,
    vcamera: CameraModel | None,
    where: Path,
) -> None:
    """A validation dataset must share the robot chain, setup, camera and tag (or the measured
    kind and its conventions), or its residuals mean nothing."""
    differences = []
    if vchain is None or vchain.joint_names != chain.joint_names:
        differences.append("robot chain (joints)")
    if vds.setup != ds.setup:
        differences.append(f"setup ({vds.setup.value} vs {ds.setup.value})")
    if ds.measurement is not None or vds.measurement is not None:
        mine, theirs = ds.measurement, vds.measurement
        if (
            mine is None
            or theirs is None
            or (mine.kind, mine.sensor, mine.target) != (theirs.kind, theirs.sensor, theirs.target)
        ):
            differences.append("observations (kind, sensor or target)")
    elif camera is None or (
        vcamera is None
        or (vcamera.width, vcamera.height) != (camera.width, camera.height)
        or not np.allclose(vcamera.K, camera.K)
        or not np.allclose(np.resize(vcamera.dist, 5), np.resize(camera.dist, 5))
    ):
        differences.append("camera intrinsics")
    same_target = (vds.family, vds.tag_id, vds.size_m, vds.board) == (ds.family, ds.tag_id, ds.size_m, ds.board)
    if ds.measurement is None and not same_target:
        differences.append("target (family, id or size, or board)")
    if differences:
        raise ArmtoolError(
            "the validation dataset differs from the dataset in: " + ", ".join(differences),
            str(where),
            "validate with poses of the same robot, camera and tag (a second session of the same setup)",
        )


def validation_samples(validation: list[Sample]) -> list[Sample]:
    """A validation dataset's samples renamed `validation:<id>`, so that their ids cannot collide
    with the dataset's (its measurements are renamed alike by `Measurements.merged`)."""
    return [replace(s, id=f"{VALIDATION_PREFIX}{s.id}") for s in validation]


def holdout_ids(usable: list[str], fraction: float, seed: int, validation: set[str] | None = None) -> set[str]:
    """The samples kept out of the fit: the validation dataset's, plus a random `fraction` of the
    other `usable` ones (those with a measurement, in the samples' order)."""
    already = validation or set()
    return already | split_holdout([u for u in usable if u not in already], fraction, seed)
