"""Joint readings turned into what the chosen calibration predicts: each joint's value for
calibrated_with_terms.urdf, gain·q + Σ p·f(q) − the mean of that over the fit's readings (which
the URDF's zero offsets hold), and the flange pose it gives.

Why: a URDF cannot hold the joint terms a calibration may choose (compliance under gravity,
harmonics of the joint angles), so the tools that read a URDF use calibrated.urdf, the geometry
fitted alone. What the terms add reaches a user only when something applies them to the
readings: a driver, a planner's FK, or a scorer checking the calibration on poses the fit never
saw. This is that step, from calibration.yaml's `joint_terms` exactly as the fit evaluated them
(the compliance's gravity torques from the dataset's URDF, the one the fit used).
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from armtool.calib.model.params import Family
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError

TERMS_URDF = "calibrated_with_terms.urdf"  # beside calibration.yaml (outputs/report.py writes its name)


@dataclass(frozen=True)
class Applied:
    """The readings, their joint values for calibrated_with_terms.urdf, and its flange poses."""

    header: list[str]
    rows: list[list[str]]
    joints: list[str]
    columns: list[int]  # each joint's column in `rows`
    values: Array  # (N, n) gain·q + Σ p·f(q) − mean correction, radians
    flange: Array  # (N, 4, 4) T_base_flange of calibrated_with_terms.urdf at `values`


def joint_terms(calibration: Path) -> dict[str, Any]:
    """calibration.yaml's `joint_terms` block, or why there is nothing to apply."""
    import yaml

    try:
        document = yaml.safe_load(calibration.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as exc:
        raise ArmtoolError(f"cannot read the calibration: {exc}", str(calibration)) from None
    if not isinstance(document, dict) or document.get("format") != "armtool-calibration/1":
        raise ArmtoolError(
            "not a calibration.yaml written by `armtool calibrate fit` (format: armtool-calibration/1)",
            str(calibration),
        )
    block = document.get("joint_terms")
    if not block:
        raise ArmtoolError(
            "this calibration chose no joint terms: there is nothing to apply",
            str(calibration),
            "feed the readings to calibrated.urdf as they are (apply a joint's `gain` if it differs from 1)",
        )
    return dict(block)


def apply(
    calibration: Path,
    readings: Path,
    degrees: bool = False,
    dataset: Path | None = None,
    xacro_args: dict[str, str] | None = None,
    package_paths: list[Path] | None = None,
) -> Applied:
    """The joint values and flange poses of calibrated_with_terms.urdf for each row of `readings`
    (a CSV whose header names the chain's joints; other columns are kept as they are)."""
    from armtool.calib.inputs.dataset import require_ok
    from armtool.calib.inputs.load import load_inputs
    from armtool.calib.model.terms.registry import build_terms
    from armtool.model.chain import load_chain
    from armtool.model.load import urdf_text

    block = joint_terms(calibration)
    urdf = calibration.parent / TERMS_URDF
    if not urdf.is_file():
        raise ArmtoolError(
            f"{TERMS_URDF} is not beside the calibration",
            str(urdf),
            "keep the files `calibrate fit --out` wrote together (it is not written when nothing beats the nominal robot)",
        )
    source = dataset or Path(block.get("dataset", ""))
    if not (source / "dataset.yaml").is_file():
        raise ArmtoolError(
            "the dataset the calibration was fitted on is not where it was (its URDF gives the gravity torques)",
            str(source),
            "pass it with --dataset DIR",
        )
    ds, chain, _camera = load_inputs(source, xacro_args or block.get("xacro_args") or {}, package_paths)
    require_ok(ds)
    assert chain is not None  # require_ok refused a dataset without one
    families = [Family(name) for name in block.get("terms", {})]
    try:
        terms = build_terms(families, chain, lambda: urdf_text(ds.urdf, ds.xacro_args, ds.package_paths))
    except ArmtoolError as exc:  # its hints are `calibrate fit`'s (--params): say what applies here
        raise ArmtoolError(
            f"cannot rebuild the calibration's joint terms from the dataset's URDF: {exc.what}",
            str(ds.urdf),
            "the URDF must be the one the fit used: pass the fitted dataset with --dataset DIR",
        ) from None
    header, rows, Q, columns = _readings(readings, chain.joint_names, degrees)
    gains = np.array([float(block["joints"][name]["gain"]) for name in chain.joint_names])
    values = gains * Q
    for term in terms:
        entry = block["terms"][term.family.value]
        if list(entry["components"]) != list(term.components):
            raise ArmtoolError(
                f"the calibration's {term.family.value} components {entry['components']} are not this "
                f"version's {list(term.components)}",
                str(calibration),
                "fit again with this version of armtool",
            )
        P = np.array([entry["joints"][name] for name in chain.joint_names], dtype=float)
        values = values + np.einsum("njc,jc->nj", term.regressors(Q), P)
    # the URDF's zero offsets hold each joint's mean correction (a calibration of before it: none)
    values = values - np.array([float(block["joints"][name].get("mean_correction", 0.0)) for name in chain.joint_names])
    with_terms = load_chain(urdf, str(block["base_link"]), str(block["flange_link"]))
    return Applied(header, rows, chain.joint_names, columns, values, with_terms.fk_batch(values))


def _readings(path: Path, joints: list[str], degrees: bool) -> tuple[list[str], list[list[str]], Array, list[int]]:
    """The CSV's header, rows, the joints' readings in radians (N, n) and their columns."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise ArmtoolError(f"cannot read the readings: {exc}", str(path)) from None
    table = list(csv.reader(io.StringIO(text)))
    if not table:
        raise ArmtoolError(
            "the readings file is empty", str(path), "a header row naming the joints, then one row per reading"
        )
    header = [h.strip() for h in table[0]]
    missing = [name for name in joints if name not in header]
    if missing:
        raise ArmtoolError(
            f"no column for joint(s) {', '.join(missing)}",
            f"{path}:1",
            f"the header names each of the chain's joints: {', '.join(joints)}",
        )
    columns = [header.index(name) for name in joints]
    rows: list[list[str]] = []
    readings: list[list[float]] = []
    for line, row in enumerate(table[1:], start=2):
        if not any(cell.strip() for cell in row):
            continue
        values = []
        for name, c in zip(joints, columns):
            cell = row[c].strip() if c < len(row) else ""
            try:
                value = float(cell)
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise ArmtoolError(
                    f"joint {name}: '{cell}' is not a number", f"{path}:{line}", "one finite reading per joint"
                )
            values.append(math.radians(value) if degrees else value)
        rows.append(row)
        readings.append(values)
    if not rows:
        raise ArmtoolError("the readings file has a header but no rows", str(path))
    Q = np.array(readings)
    return header, rows, Q, columns


def applied_csv(result: Applied, degrees: bool) -> str:
    """The readings with each joint's column replaced by its value for calibrated_with_terms.urdf
    (in the readings' unit) and the flange pose appended (metres; quaternion x, y, z, w)."""
    from scipy.spatial.transform import Rotation

    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(
        [*result.header, "flange_x", "flange_y", "flange_z", "flange_qx", "flange_qy", "flange_qz", "flange_qw"]
    )
    quaternions = Rotation.from_matrix(result.flange[:, :3, :3]).as_quat()
    for row, value, T, quat in zip(result.rows, result.values, result.flange, quaternions):
        cells = list(row) + [""] * (len(result.header) - len(row))
        for c, v in zip(result.columns, value):
            cells[c] = repr(float(math.degrees(v) if degrees else v))
        writer.writerow([*cells, *(repr(float(v)) for v in T[:3, 3]), *(repr(float(v)) for v in quat)])
    return out.getvalue()
