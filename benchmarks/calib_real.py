"""Real measurements through the documented commands: a Franka Research 3 with a camera on its
flange, 114 poses of a ChArUco board (../shared/calib-real/franka_fr3, MIT, from
PhilNad/robot-arm-kinematic-calibration; never copied into the project).

Writes the README's worked dataset.yaml for those files into a temporary directory, then runs
`armtool calibrate check` and `armtool calibrate fit --format json` (default options: 5-fold
cross-validation, nested) as a user would, and prints a markdown table: the nominal robot (only
the camera and board placements fitted) against the calibrated one, in-sample and on held-out
poses, RMS and max, in mm and degrees; the estimated noise; the time taken; and what the
convention check says of the same file read inverted.

    python benchmarks/calib_real.py [--data ../shared/calib-real/franka_fr3] [--folds 5]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import yaml

ROOT = Path(__file__).resolve().parents[1]
JOINTS = [f"panda_joint{i}" for i in range(1, 8)]


def panda_urdf() -> Path:
    from calib_bench import (
        robot_file,
    )  # the benchmarks' way to example-robot-data (this script's directory is on sys.path)

    return robot_file("panda_description/urdf/panda.urdf")


def write_manifest(directory: Path, data: Path, pose: str = "sensor_in_target") -> Path:
    """The README's worked example, pointing at the shared CSVs."""
    directory.mkdir(parents=True)
    doc = {
        "format": "armtool-calib-dataset/1",
        "setup": "eye_in_hand",
        "robot": {
            "urdf": str(panda_urdf()),
            "base_link": "panda_link0",
            "flange_link": "panda_link8",
            "joints": JOINTS,
            "joint_units": "rad",
        },
        "samples": str(data / "joints.csv"),
        "observations": {
            "kind": "pose",
            "file": str(data / "camera_in_board.csv"),
            "sensor": "camera",
            "target": "board",
            "pose": pose,
            "position_units": "m",
            "rotation": "matrix",
            "position_columns": ["T03", "T13", "T23"],
            "rotation_columns": ["T00", "T01", "T02", "T10", "T11", "T12", "T20", "T21", "T22"],
        },
    }
    (directory / "dataset.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    return directory


def armtool(*args: str) -> tuple[subprocess.CompletedProcess[str], float, float]:
    """Run the command; (result, wall seconds, CPU seconds of the child)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run([sys.executable, "-m", "armtool", *args], capture_output=True, text=True, cwd=ROOT)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return result, wall, cpu


def rms(values: list[float]) -> float:
    return math.sqrt(sum(v * v for v in values) / len(values)) if values else math.nan


def in_sample(document: dict[str, Any], key: str, roles: tuple[str, ...]) -> tuple[float, float]:
    """RMS and max of a per-sample figure over the samples of the given roles."""
    values = [s[key] for s in document["samples"] if s["role"] in roles and s.get(key) is not None]
    return rms(values), max(values)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT / ".." / "shared" / "calib-real" / "franka_fr3")
    parser.add_argument("--folds", type=int, default=5)
    args = parser.parse_args()
    if not (args.data / "camera_in_board.csv").is_file():
        sys.exit(f"no FR3 data at {args.data}")
    load = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        dataset = write_manifest(Path(tmp) / "fr3", args.data.resolve())
        check, check_wall, check_cpu = armtool("calibrate", "check", str(dataset))
        if check.returncode != 0:
            sys.exit(check.stderr)
        out = Path(tmp) / "out"
        fit, fit_wall, fit_cpu = armtool(
            "calibrate", "fit", str(dataset), "-o", str(out), "--format", "json", "--folds", str(args.folds)
        )
        if fit.returncode != 0:
            sys.exit(fit.stderr)
        summary = json.loads(fit.stdout)
        document = yaml.safe_load((out / "calibration.yaml").read_text())
        inverted = write_manifest(Path(tmp) / "inverted", args.data.resolve(), pose="target_in_sensor")
        wrong, wrong_wall, _ = armtool("calibrate", "check", str(inverted))
    load_after = os.getloadavg()

    nested = summary["cross_validation"]["nested"]
    everyone, kept = ("fit", "outlier"), ("fit",)
    rows = []
    for label, key, held in (
        ("nominal robot (hand-eye only)", "hand_eye_only", "hand_eye_only"),
        (f"calibrated ({summary['fitted']})", "calibrated", "calibrated"),
    ):
        p_all, p_all_max = in_sample(document, f"{key}_mm", everyone)
        r_all, r_all_max = in_sample(document, f"{key}_deg", everyone)
        p_in, _ = in_sample(document, f"{key}_mm", kept)
        held_p, held_p_max = nested["heldout_rms_mm"][held], nested["heldout_max_mm"][held]
        held_r, held_r_max = nested["heldout_rms_deg"][held], nested["heldout_max_deg"][held]
        held_in = nested["heldout_without_outliers_rms_mm"] if key == "calibrated" else math.nan
        rows.append(
            f"| {label} | {p_all:.2f} / {p_all_max:.2f} | {p_in:.2f} | {r_all:.3f} / {r_all_max:.3f} | "
            f"{held_p:.2f} / {held_p_max:.2f} | {'-' if math.isnan(held_in) else f'{held_in:.2f}'} | "
            f"{held_r:.3f} / {held_r_max:.3f} |"
        )
    print(
        f"FR3, {nested['samples']} poses, {args.folds}-fold cross-validation, nested "
        f"(chosen per outer fold: {', '.join(nested['chosen_per_fold'])}); outliers named: {', '.join(summary['outliers']) or 'none'}"
    )
    print()
    print(
        "| model | in-sample position RMS / max mm (all) | in-sample position RMS mm (without outliers) | "
        "in-sample rotation RMS / max ° | held-out position RMS / max mm | held-out position RMS mm (without outliers) | "
        "held-out rotation RMS / max ° |"
    )
    print("|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    print()
    noise = summary["noise"]
    print(
        f"estimated noise (σ per coordinate): position {noise['position_mm']:.3f} mm, rotation {noise['rotation_deg']:.4f}°"
    )
    for c in summary["cross_validation"]["candidates"]:
        print(
            f"  {c['name']}: {c['parameters']:.0f} parameters, held-out position {c['heldout_rms_mm']:.2f} mm "
            f"({c['heldout_without_outliers_rms_mm']:.2f} without outliers), rotation {c['heldout_rms_deg']:.3f}°, score {c['score']:.3f}"
        )
    camera = summary["frames"]["camera_in_flange"]
    print(
        "camera in flange: " + ", ".join(f"{v * 1e3:.2f}" for v in camera["xyz"]) + " mm, yaw "
        f"{math.degrees(camera['rpy'][2]):.2f}° (mount drawing: 94.5, -9, 40.55 mm, 90°)"
    )
    flat = " ".join(wrong.stderr.split())
    print(
        f"the file read inverted (pose: target_in_sensor): check exits {wrong.returncode}: "
        + flat.split("error: ")[1].split(" hint:")[0]
        if "error: " in flat
        else flat
    )
    print(
        f"time: check {check_wall:.1f} s wall ({check_cpu:.1f} s CPU), fit {fit_wall:.1f} s wall ({fit_cpu:.1f} s CPU), "
        f"inverted check {wrong_wall:.1f} s; load average {load[0]:.1f} before, {load_after[0]:.1f} after ({os.cpu_count()} cores)"
    )


if __name__ == "__main__":
    main()
