"""A dataset with the robot chain and the camera it names, loaded in the order that lets every
problem be reported at once (what `calibrate check` lists and `calibrate fit` refuses).

The manifest first, then the chain it names, then the samples checked against the chain's
joints, then the intrinsics. Nothing here raises for a problem in the dataset: it is collected
in `Dataset.problems` with its file and line (`dataset.require_ok` turns them into one error).
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

from armtool.calib.inputs.dataset import Dataset, Problem, load_dataset, read_samples
from armtool.calib.inputs.files import unreadable_reason
from armtool.calib.inputs.observations import Observation
from armtool.calib.model.camera import CameraModel, load_intrinsics
from armtool.calib.targets.spec import Target
from armtool.errors import ArmtoolError
from armtool.model.chain import Chain, load_chain


class Inputs(NamedTuple):
    dataset: Dataset
    chain: Chain | None  # None when the dataset's robot could not be loaded (a problem says why)
    camera: CameraModel | None  # likewise for the intrinsics


def load_inputs(
    directory: Path, xacro_args: dict[str, str] | None = None, package_paths: list[Path] | None = None
) -> Inputs:
    """Dataset, chain and camera. Command-line xacro arguments and package paths are merged over
    the dataset's own (robot.xacro_args, robot.package_paths)."""
    ds = load_dataset(directory, with_samples=False)
    ds.xacro_args, ds.package_paths = ds.robot_sources(xacro_args, package_paths)
    chain = _chain(ds)
    read_samples(ds, chain.joint_names if chain is not None else None)
    if chain is not None and ds.joints and set(ds.joints) != set(chain.joint_names):
        ds.problems.append(
            Problem(
                "dataset.yaml",
                f"robot.joints {sorted(ds.joints)} differ from the chain's moving joints {chain.joint_names}",
                f"list the joints between {ds.base_link} and {ds.flange_link}",
            )
        )
    return Inputs(ds, chain, _camera(ds))


def _chain(ds: Dataset) -> Chain | None:
    if ds.base_link and ds.base_link == ds.flange_link:
        ds.problems.append(
            Problem(
                "dataset.yaml",
                f"robot.base_link and robot.flange_link are the same link '{ds.base_link}': the chain between them has no joints",
                "robot.flange_link names the link the tag (or camera) is mounted on, robot.base_link the robot's fixed base",
            )
        )
        return None
    if unreadable_reason(ds.urdf) is not None or not (ds.base_link and ds.flange_link):
        return None  # already a problem of the manifest
    try:
        return load_chain(
            ds.urdf, ds.base_link, ds.flange_link, xacro_args=ds.xacro_args, package_paths=ds.package_paths
        )
    except ArmtoolError as exc:
        ds.problems.append(Problem(str(ds.urdf.name), exc.what, exc.hint or ""))
        return None


def _camera(ds: Dataset) -> CameraModel | None:
    if unreadable_reason(ds.intrinsics) is not None:
        return None  # already a problem of the manifest
    try:
        camera = load_intrinsics(ds.intrinsics)
    except ArmtoolError as exc:
        ds.problems.append(Problem(Path(exc.where).name if exc.where else ds.intrinsics.name, exc.what, exc.hint or ""))
        return None
    return camera.without_distortion() if ds.images_rectified else camera


def detection_problems(ds: Dataset, observations: dict[str, Observation]) -> list[Problem]:
    """A warning per sample whose tag was not usable, and an error when fewer than half (or 3) were:
    then the dataset's target (family, id) or its images are wrong, not a few poses."""
    rows = {s.id: s.row for s in ds.samples}
    problems = [
        Problem(f"samples.csv:{rows[sid]}", f"sample {sid}: {ob.reason}", severity="warning")
        for sid, ob in observations.items()
        if ob.corners_px is None
    ]
    found = len(observations) - len(problems)
    if found < max(3, len(ds.samples) // 2):
        problems.append(
            Problem(
                "dataset.yaml",
                f"{Target.of(ds).describe()} was usable in only {found} of {len(ds.samples)} samples",
                "check the target in dataset.yaml and the images (the warnings above say what was seen)",
            )
        )
    return problems


def input_files(*datasets: Dataset | None) -> list[Path]:
    """Every file a fit reads: the outputs must not overwrite any of them."""
    files: list[Path] = []
    for ds in datasets:
        if ds is None:
            continue
        files += [ds.root / "dataset.yaml", ds.urdf, ds.intrinsics]
        files += [p for p in (ds.samples_file, ds.corners_file) if p is not None]
        files += [s.image for s in ds.samples if s.image is not None]
    return files
