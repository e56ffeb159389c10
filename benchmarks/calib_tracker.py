"""Real laser-tracker data through the documented commands: a k-fold of our own over the UR5's
1000 grid poses (../shared/calib-real/ur5_tracker, MIT, P. Jacobi's thesis data; never copied
into the project), one `calibrate fit` per fold and per `--params`, each scored on the fold it
never saw (`--validation`).

The dataset is written as docs/calibrate.md says a user would: joints converted to radians
(the file has degrees), the measured point = target + achieved − target (`x_t + x_dif`, mm),
`kind: point`, `setup: eye_to_hand`, example-robot-data's UR5 to `tool0`. Inside each fit the
parameter set is chosen by its own k-fold (`--no-nested`: the outer folds here score the choice).

Prints, per `--params`: the mean and RMS held-out position error (mm) over every pose (each pose
held out once), the parameter set chosen per fold, and, for compliance, the fitted stiffness (or
its lower bound, where the sag is within 2 σ of zero). A chosen set with joint terms is scored as
it predicts: the held-out readings through `calibrate apply`, then its `joint_terms.frames`
(calibrated.urdf alone, the set's URDF rung, is what `--validation` scores).

    python benchmarks/calib_tracker.py [--params none origins,offsets origins,offsets,compliance] [--folds 5]
"""

from __future__ import annotations

import argparse
import csv
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / ".." / "shared" / "calib-real" / "ur5_tracker" / "3D_UR5_uncalibrated_grid_cleaned.csv"
JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]


def ur5_urdf() -> Path:
    from calib_bench import robot_file  # this script's directory is on sys.path

    return robot_file("ur_description/urdf/ur5_robot.urdf")


def read_grid(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(joints in rad (N, 6), measured points in mm (N, 3))."""
    with path.open() as handle:
        rows = list(csv.DictReader(handle))
    q = np.radians([[float(r[f"joint_{i}"]) for i in range(1, 7)] for r in rows])
    p = np.array([[float(r[f"{a}_t"]) + float(r[f"{a}_dif"]) for a in "xyz"] for r in rows])
    return q, p


def write_dataset(directory: Path, q: np.ndarray, p: np.ndarray, rows: list[int]) -> Path:
    directory.mkdir(parents=True)
    with (directory / "data.csv").open("w", newline="") as handle:
        out = csv.writer(handle)
        out.writerow(["id", *JOINTS, "x", "y", "z"])
        for k in rows:
            out.writerow([str(k), *(repr(float(v)) for v in q[k]), *(repr(float(v)) for v in p[k])])
    doc = {
        "format": "armtool-calib-dataset/1",
        "setup": "eye_to_hand",
        "robot": {"urdf": str(ur5_urdf()), "base_link": "base_link", "flange_link": "tool0", "joints": JOINTS},
        "samples": "data.csv",
        "observations": {"kind": "point", "file": "data.csv", "position_units": "mm"},
    }
    (directory / "dataset.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    return directory


def fit(train: Path, test: Path, out: Path, params: str, inner_folds: int) -> tuple[dict[str, Any], float]:
    start = time.perf_counter()
    args = ["calibrate", "fit", str(train), "-o", str(out), "--validation", str(test), "--format", "json"]
    args += ["--params", params, "--no-nested", "--folds", str(inner_folds), "--allow-nominal"]
    result = subprocess.run([sys.executable, "-m", "armtool", *args], capture_output=True, text=True, cwd=ROOT)
    if result.returncode != 0:
        sys.exit(f"fit failed ({params}): {result.stderr}")
    return yaml.safe_load((out / "calibration.yaml").read_text()), time.perf_counter() - start


def held_out_mm(document: dict[str, Any], out: Path, q: np.ndarray, p: np.ndarray, rows: list[int]) -> list[float]:
    """The held-out position error of every test pose, mm (outliers included): calibrated.urdf's
    from `--validation`, or, when the chosen set has joint terms, that set's own prediction."""
    if not document.get("joint_terms"):
        return [
            float(s["calibrated_mm"])
            for s in document["samples"]
            if str(s["id"]).startswith("validation:") and s.get("calibrated_mm") is not None
        ]
    from scipy.spatial.transform import Rotation

    readings, applied = out / "readings.csv", out / "applied.csv"
    with readings.open("w", newline="") as handle:
        csv.writer(handle).writerows([JOINTS, *([repr(float(v)) for v in q[k]] for k in rows)])
    args = ["calibrate", "apply", str(out / "calibration.yaml"), str(readings), "-o", str(applied)]
    result = subprocess.run([sys.executable, "-m", "armtool", *args], capture_output=True, text=True, cwd=ROOT)
    if result.returncode != 0:
        sys.exit(f"calibrate apply failed: {result.stderr}")
    with applied.open(newline="") as handle:
        table = list(csv.DictReader(handle))
    frames = document["joint_terms"]["frames"]
    tracker = frames["tracker_in_base"]
    R_tracker = Rotation.from_euler("xyz", tracker["rpy"]).as_matrix()  # URDF rpy: fixed axes x, y, z
    R = Rotation.from_quat([[float(r[f"flange_q{a}"]) for a in "xyzw"] for r in table]).as_matrix()
    t = np.array([[float(r[f"flange_{a}"]) for a in "xyz"] for r in table])
    in_base = R @ np.array(frames["point_in_flange"]["xyz"]) + t
    in_tracker = (in_base - np.array(tracker["xyz"])) @ R_tracker  # T_base_tracker⁻¹ · p
    return [float(e) for e in np.linalg.norm(in_tracker * 1e3 - p[rows], axis=1)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=DATA)
    parser.add_argument("--params", nargs="+", default=["none", "origins,offsets", "origins,offsets,compliance"])
    parser.add_argument("--folds", type=int, default=5, help="outer folds (each pose held out once)")
    parser.add_argument("--inner-folds", type=int, default=5, help="--folds of each fit (the choice of set)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    if not args.data.is_file():
        sys.exit(f"no UR5 tracker data at {args.data}")
    q, p = read_grid(args.data)
    order = np.random.default_rng(args.seed).permutation(len(q))
    folds = [sorted(int(k) for k in order[f :: args.folds]) for f in range(args.folds)]
    print(
        f"UR5 tracker, {len(q)} poses, {args.folds}-fold of our own (seed {args.seed}), inner --folds {args.inner_folds}"
    )
    print()
    print("| --params | held-out mean mm | held-out RMS mm | chosen per fold | fit s (mean) | stiffness per fold |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for params in args.params:
            errors: list[float] = []
            chosen, seconds, notes = [], [], []
            for f, test_rows in enumerate(folds):
                train_rows = sorted(set(range(len(q))) - set(test_rows))
                base = Path(tmp) / f"{params.replace(',', '_')}_{f}"
                train = write_dataset(base / "train", q, p, train_rows)
                test = write_dataset(base / "test", q, p, test_rows)
                document, wall = fit(train, test, base / "out", params, args.inner_folds)
                errors += held_out_mm(document, base / "out", q, p, test_rows)
                chosen.append(str((document.get("joint_terms") or document).get("fitted", "?")))
                seconds.append(wall)
                notes += stiffness_notes(document)
            mean = float(np.mean(errors))
            rms = math.sqrt(float(np.mean(np.square(errors))))
            print(
                f"| {params} | {mean:.4f} | {rms:.4f} | {', '.join(chosen)} | {np.mean(seconds):.1f} | "
                f"{'; '.join(n for n in notes if n.startswith(('shoulder_lift', 'elbow')))} |"
            )
            sys.stdout.flush()


def stiffness_notes(document: dict[str, Any]) -> list[str]:
    """'shoulder_lift_joint 27.9 ± 0.8 kN·m/rad' (or '≥ 33.5', a sag within 2 σ of zero) per fitted compliance."""
    out = []
    for name, entry in ((document.get("joint_terms") or {}).get("joints") or {}).items():
        k, low = entry.get("stiffness_knm_per_rad"), entry.get("stiffness_min_knm_per_rad")
        if isinstance(k, dict):
            out.append(f"{name} {k['value']:.1f} ± {k['sigma']:.1f} kN·m/rad")
        elif low is not None:
            out.append(f"{name} ≥ {low:.1f} kN·m/rad")
    return out


if __name__ == "__main__":
    main()
