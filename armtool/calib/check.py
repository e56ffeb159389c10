"""`armtool calibrate check` end to end, without the terminal: every problem of a dataset, collected
at once with its file and line (the command prints them and picks the exit code).

The files, joints and units first (`inputs.load`), then the target in every image when asked
(`detect`), then, for measured poses or points, every other reading of the file fitted with the
nominal robot (`fit.convention_check`). Only that last step brings the fit and SciPy's optimizer,
so it is imported when a dataset has measurements (an image check stays fast).
"""

from __future__ import annotations

from pathlib import Path

from armtool.calib.inputs.dataset import Dataset, Problem
from armtool.calib.inputs.load import detection_problems, load_inputs
from armtool.calib.inputs.observations import Detect
from armtool.errors import ArmtoolError
from armtool.model.chain import Chain


def check_dataset(
    root: Path, xacro_args: dict[str, str], package_paths: list[Path], detect: Detect | None
) -> tuple[Dataset, str | None]:
    """The dataset with every problem in `ds.problems`, and how well the declared conventions of its
    measured poses or points fit (None when it has none, or when another reading is a problem)."""
    ds, chain, camera = load_inputs(root, xacro_args, package_paths)
    if detect is not None and chain is not None and camera is not None and ds.samples:
        ds.problems += detection_problems(ds, detect(ds, camera))
    note = _conventions(ds, chain) if chain is not None else None
    return ds, note


def _conventions(ds: Dataset, chain: Chain) -> str | None:
    """Measured poses or points: whether another reading of the file fits far better (an error
    naming the dataset.yaml lines to change), or how well the declared one fits."""
    if ds.measurement is None or ds.errors or len(ds.measured_rows) < 3:
        return None  # before the import: the convention check brings the fit and SciPy's optimizer
    from armtool.calib.fit.convention_check import checked_conventions

    try:
        found = checked_conventions(ds, chain, refuse=False)
    except ArmtoolError as exc:
        ds.problems.append(Problem(exc.where or "dataset.yaml", exc.what, exc.hint or ""))
        return None
    if found.better is not None:
        ds.problems.append(Problem("dataset.yaml", found.message(), found.fix()))
        return None
    return found.message()
