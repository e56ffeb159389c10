"""Real measurements through the documented commands (../shared/calib-real, MIT; never copied
into the project):

- a Franka Research 3 with a camera on its flange, 114 poses of a ChArUco board (`franka_fr3/`,
  from PhilNad/robot-arm-kinematic-calibration);
- a UR5 measured by a laser tracker, 1000 grid poses of one reflector (`ur5_tracker/`, from
  pauljac7700/serial_robots_datasets).

For each, a dataset is written into a temporary directory as a user would (the README's worked
manifest for the FR3; for the UR5 one CSV with the joints converted to radians and the measured
point = target + (achieved − target), as the dataset's README defines its columns), then
`armtool calibrate check` and `armtool calibrate fit --format json` run with default options
(5-fold cross-validation, nested). Held-out figures are each sample's residual from the outer
fold that held it out, its parameter set chosen on that fold's training poses alone.

FR3: a markdown table for one split (`--seed 0`), then the same figures pooled over `--splits`
different fold partitions (seeds 0, 1, …) with their spread over the splits. UR5: the held-out
point error (mean, RMS, max), the calibrated URDF's tool0 against the nominal arm's over the 1000
poses (what one tracked point cannot see must stay nominal), the reflector's fitted place, the
combinations held, and the same on `--subsets` disjoint 50-pose subsets.

    python benchmarks/calib_real.py [--data ../shared/calib-real] [--splits 5] [--subsets 20] [--only fr3|ur5]
"""

from __future__ import annotations

import argparse
import csv
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

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]
JOINTS = [f"panda_joint{i}" for i in range(1, 8)]
UR5_JOINTS = [
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "elbow_joint",
    "wrist_1_joint",
    "wrist_2_joint",
    "wrist_3_joint",
]
UR5_CSV = "3D_UR5_uncalibrated_grid_cleaned.csv"


def panda_urdf() -> Path:
    from calib_bench import (
        robot_file,
    )  # the benchmarks' way to example-robot-data (this script's directory is on sys.path)

    return robot_file("panda_description/urdf/panda.urdf")


def ur5_urdf() -> Path:
    from calib_bench import robot_file

    return robot_file("ur_description/urdf/ur5_robot.urdf")


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


def ur5_rows(data: Path) -> list[dict[str, str]]:
    with (data / UR5_CSV).open(newline="") as f:
        return list(csv.DictReader(f))


def write_ur5_dataset(directory: Path, rows: list[dict[str, str]]) -> Path:
    """The tracker rows as a dataset: `id`, the joints in radians, the measured point in mm."""
    directory.mkdir(parents=True)
    lines = ["id," + ",".join(UR5_JOINTS) + ",x,y,z"]
    for r in rows:
        q = [math.radians(float(r[f"joint_{k}"])) for k in range(1, 7)]
        p = [float(r[f"{a}_t"]) + float(r[f"{a}_dif"]) for a in "xyz"]
        lines.append(r["step_order"] + "," + ",".join(repr(v) for v in q + p))
    (directory / "data.csv").write_text("\n".join(lines) + "\n")
    doc = {
        "format": "armtool-calib-dataset/1",
        "setup": "eye_to_hand",
        "robot": {
            "urdf": str(ur5_urdf()),
            "base_link": "base_link",
            "flange_link": "tool0",
            "joints": UR5_JOINTS,
            "joint_units": "rad",
        },
        "samples": "data.csv",
        "observations": {
            "kind": "point",
            "file": "data.csv",
            "position_units": "mm",
            "position_columns": ["x", "y", "z"],
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


def fit(dataset: Path, out: Path, *extra: str) -> tuple[dict[str, Any], dict[str, Any], float, float]:
    """`calibrate fit --format json`: (its summary, calibration.yaml, wall s, CPU s); exits on failure."""
    result, wall, cpu = armtool("calibrate", "fit", str(dataset), "-o", str(out), "--format", "json", *extra)
    if result.returncode != 0:
        sys.exit(result.stderr)
    return json.loads(result.stdout), yaml.safe_load((out / "calibration.yaml").read_text()), wall, cpu


def rms(values: list[float]) -> float:
    return math.sqrt(sum(v * v for v in values) / len(values)) if values else math.nan


def in_sample(document: dict[str, Any], key: str, roles: tuple[str, ...]) -> tuple[float, float]:
    """RMS and max of a per-sample figure over the samples of the given roles."""
    values = [s[key] for s in document["samples"] if s["role"] in roles and s.get(key) is not None]
    return rms(values), max(values)


def held_out(document: dict[str, Any], key: str, without_outliers: bool = False) -> list[float]:
    """Each fit sample's nested cross-validated figure (`cross_validated_mm`, …)."""
    roles = ("fit",) if without_outliers else ("fit", "outlier")
    return [s[key] for s in document["samples"] if s["role"] in roles and s.get(key) is not None]


def fr3(data: Path, tmp: Path, folds: int, splits: int) -> None:
    dataset = write_manifest(tmp / "fr3", data.resolve())
    check, check_wall, check_cpu = armtool("calibrate", "check", str(dataset))
    if check.returncode != 0:
        sys.exit(check.stderr)
    summary, document, fit_wall, fit_cpu = fit(dataset, tmp / "fr3-out", "--folds", str(folds))
    inverted = write_manifest(tmp / "inverted", data.resolve(), pose="target_in_sensor")
    wrong, wrong_wall, _ = armtool("calibrate", "check", str(inverted))

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
        f"FR3, {nested['samples']} poses, {folds}-fold cross-validation, nested, --seed 0 "
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
    for h in summary["identifiability"]["held"]:
        print(
            f"  held: σ {h['sigma_in_precision_units']:.2f} × the precision, "
            f"{h['sigmas_from_nominal']:.1f} σ from nominal"
        )
    camera = summary["frames"]["camera_in_flange"]
    print(
        "camera in flange: " + ", ".join(f"{v * 1e3:.2f}" for v in camera["xyz"]) + " mm, yaw "
        f"{math.degrees(camera['rpy'][2]):.2f}° (mount drawing: 94.5, -9, 40.55 mm, 90°)"
    )
    print(flange_gauge_line(document))
    flat = " ".join(wrong.stderr.split())
    print(
        f"the file read inverted (pose: target_in_sensor): check exits {wrong.returncode}: "
        + flat.split("error: ")[1].split(" hint:")[0]
        if "error: " in flat
        else flat
    )
    print(
        f"time: check {check_wall:.1f} s wall ({check_cpu:.1f} s CPU), fit {fit_wall:.1f} s wall ({fit_cpu:.1f} s CPU), "
        f"inverted check {wrong_wall:.1f} s"
    )
    pooled_all, pooled_kept, per_split = list(held_out(document, "cross_validated_mm")), [], []
    pooled_kept += held_out(document, "cross_validated_mm", without_outliers=True)
    per_split.append((rms(pooled_all), rms(pooled_kept), len(summary["outliers"])))
    for seed in range(1, splits):
        _s, doc, _w, _c = fit(dataset, tmp / f"fr3-out{seed}", "--folds", str(folds), "--seed", str(seed))
        every, kept_here = held_out(doc, "cross_validated_mm"), held_out(doc, "cross_validated_mm", True)
        pooled_all += every
        pooled_kept += kept_here
        per_split.append((rms(every), rms(kept_here), len(_s["outliers"])))
    print(
        f"pooled over {splits} splits (--seed 0..{splits - 1}): held-out position {rms(pooled_all):.2f} mm RMS over all "
        f"{len(pooled_all) // splits} poses, {rms(pooled_kept):.2f} mm over the ones each fit keeps; one split gives "
        f"{min(a for a, _b, _n in per_split):.2f}-{max(a for a, _b, _n in per_split):.2f} mm and "
        f"{min(b for _a, b, _n in per_split):.2f}-{max(b for _a, b, _n in per_split):.2f} mm"
    )


def tool0_deviation(calibrated: Path, Q: np.ndarray) -> tuple[float, float, float, float]:  # type: ignore[type-arg]
    """tool0 of the calibrated URDF against the nominal arm's over the poses Q: max and mean mm, max and mean °."""
    from armtool.model.chain import load_chain

    return flange_deviation(load_chain(calibrated, "base_link", "tool0").fk_batch(Q), Q)


def flange_deviation(F: np.ndarray, Q: np.ndarray) -> tuple[float, float, float, float]:  # type: ignore[type-arg]
    """The flange poses F against the nominal arm's tool0 at the readings Q, as `tool0_deviation`."""
    from armtool.calib.model import se3
    from armtool.model.chain import load_chain

    nominal = load_chain(ur5_urdf(), "base_link", "tool0").fk_batch(Q)
    distance = np.linalg.norm(F[:, :3, 3] - nominal[:, :3, 3], axis=1) * 1e3
    angle = np.degrees(np.linalg.norm(se3.log3_batch(np.swapaxes(nominal[:, :3, :3], -1, -2) @ F[:, :3, :3]), axis=-1))
    return float(distance.max()), float(distance.mean()), float(angle.max()), float(angle.mean())


def flange_gauge_line(document: dict[str, Any]) -> str:
    """calibration.yaml's flange gauge: the flange against the nominal arm's before and after."""
    g = document["identifiability"]["flange_gauge"]
    before, after = g["before"], g["after"]
    return (
        f"flange gauge ({g['free_combinations']} free combinations, chi2 {g['chi2_change']:+.3f}): the flange "
        f"{before['mean_mm']:.2f} mm / {before['mean_deg']:.3f}° from the nominal arm's on average before, "
        f"{after['mean_mm']:.2f} mm / {after['mean_deg']:.3f}° after (at most {after['max_mm']:.2f} mm / {after['max_deg']:.3f}°)"
    )


def unseen_points(data_rows: list[dict[str, str]], tmp: Path) -> str:
    """The default fit on 800 grid poses (seed 1), scored on the other 200: calibrated.urdf read as it
    is, calibrated_with_terms.urdf read as it is (a tool that knows no terms), and with its terms
    applied by `calibrate apply`; each with its own frames from calibration.yaml."""
    from armtool.calib.model import se3
    from armtool.model.chain import load_chain

    order = np.random.default_rng(1).permutation(len(data_rows))
    unseen = [data_rows[int(i)] for i in sorted(order[:200])]
    train = [data_rows[int(i)] for i in sorted(order[200:])]
    out = tmp / "ur5-800-out"
    _summary, document, _w, _c = fit(write_ur5_dataset(tmp / "ur5-800", train), out)
    readings = write_ur5_dataset(tmp / "ur5-200", unseen) / "data.csv"
    Q = np.radians([[float(r[f"joint_{k}"]) for k in range(1, 7)] for r in unseen])
    measured = np.array([[float(r[f"{a}_t"]) + float(r[f"{a}_dif"]) for a in "xyz"] for r in unseen]) * 1e-3

    def error(T: np.ndarray, frames: dict[str, Any]) -> str:  # type: ignore[type-arg]
        tracker = se3.inv(se3.xyz_rpy(frames["tracker_in_base"]["xyz"], frames["tracker_in_base"]["rpy"]))
        in_base = T[:, :3, :3] @ np.array(frames["point_in_flange"]["xyz"]) + T[:, :3, 3]
        e = np.linalg.norm(in_base @ tracker[:3, :3].T + tracker[:3, 3] - measured, axis=1) * 1e3
        return f"{np.mean(e):.4f} / {np.max(e):.3f}"

    parts = [
        f"calibrated.urdf {error(load_chain(out / 'calibrated.urdf', 'base_link', 'tool0').fk_batch(Q), document['frames'])}"
    ]
    terms = document.get("joint_terms")
    if terms:
        as_read = load_chain(out / "calibrated_with_terms.urdf", "base_link", "tool0").fk_batch(Q)
        T = applied_flanges(out, readings)
        parts += [
            f"calibrated_with_terms.urdf read as it is {error(as_read, terms['frames'])}",
            f"with its terms applied {error(T, terms['frames'])}",
        ]
    return "200 unseen grid poses, the default fit on the other 800 (mean / max mm): " + "; ".join(parts)


def applied_flanges(out: Path, readings: Path) -> np.ndarray:  # type: ignore[type-arg]
    """calibrated_with_terms.urdf's flange poses (N, 4, 4) at the joint values `calibrate apply`
    gives for the readings: what its terms are for."""
    from scipy.spatial.transform import Rotation

    applied = out / "applied.csv"
    result, _wall, _cpu = armtool(
        "calibrate", "apply", str(out / "calibration.yaml"), str(readings), "-o", str(applied)
    )
    if result.returncode != 0:
        sys.exit(result.stderr)
    with applied.open(newline="") as f:
        table = list(csv.DictReader(f))
    T = np.tile(np.eye(4), (len(table), 1, 1))
    T[:, :3, 3] = [[float(r[f"flange_{a}"]) for a in "xyz"] for r in table]
    T[:, :3, :3] = Rotation.from_quat([[float(r[f"flange_q{a}"]) for a in "xyzw"] for r in table]).as_matrix()
    return T


def ur5(data: Path, tmp: Path, folds: int, subsets: int) -> None:
    grid = ur5_rows(data)
    Q = np.radians([[float(r[f"joint_{k}"]) for k in range(1, 7)] for r in grid])
    dataset = write_ur5_dataset(tmp / "ur5", grid)
    check, check_wall, _ = armtool("calibrate", "check", str(dataset))
    if check.returncode != 0:
        sys.exit(check.stderr)
    summary, document, fit_wall, fit_cpu = fit(dataset, tmp / "ur5-out", "--folds", str(folds))
    nested = summary["cross_validation"]["nested"]
    errors = held_out(document, "cross_validated_mm")
    hand_eye = nested["heldout_rms_mm"]["hand_eye_only"]
    distance, distance_mean, angle, angle_mean = tool0_deviation(tmp / "ur5-out" / "calibrated.urdf", Q)
    point = summary["frames"]["point_in_flange"]["xyz"]
    print(
        f"UR5 tracker, {len(grid)} grid poses, {folds}-fold cross-validation, nested (chosen per outer fold: "
        f"{', '.join(nested['chosen_per_fold'])}); outliers named: {len(summary['outliers'])}"
    )
    print()
    print(
        "| | held-out point error mean / RMS / max mm | tool0 vs nominal arm: max / mean mm | max / mean ° | reflector in tool0 (x, y, z) mm |"
    )
    print("|---|---|---|---|---|")
    print(
        f"| nominal robot (hand-eye only) | - / {hand_eye:.3f} / {nested['heldout_max_mm']['hand_eye_only']:.3f} | 0 | 0 | - |"
    )
    terms = summary.get("joint_terms")
    chosen = f"chosen: {terms['fitted']}; calibrated.urdf: {summary['fitted']}" if terms else summary["fitted"]
    print(
        f"| default options, calibrated.urdf as it is ({chosen}) | {np.mean(errors):.4f} / {rms(errors):.4f} / "
        f"{max(errors):.3f} | {distance:.2f} / {distance_mean:.2f} | {angle:.3f} / {angle_mean:.3f} | "
        + ", ".join(f"{v * 1e3:.2f}" for v in point)
        + " |"
    )
    if terms:
        with_terms = flange_deviation(applied_flanges(tmp / "ur5-out", dataset / "data.csv"), Q)
        print(
            f"| default options, calibrated_with_terms.urdf with its joint terms ({terms['fitted']}) | "
            f"{terms['nested_heldout_mean_mm']:.4f} / {terms['nested_heldout_rms_mm']:.4f} / "
            f"{terms['nested_heldout_max_mm']:.3f} | {with_terms[0]:.2f} / {with_terms[1]:.2f} | "
            f"{with_terms[2]:.3f} / {with_terms[3]:.3f} | "
            + ", ".join(f"{v * 1e3:.2f}" for v in terms["frames"]["point_in_flange"]["xyz"])
            + " |"
        )
    geometry, geometry_doc, _w, _c = fit(
        dataset, tmp / "ur5-geometry-out", "--folds", str(folds), "--params", "origins,offsets"
    )
    g_errors = held_out(geometry_doc, "cross_validated_mm")
    g_distance, g_distance_mean, g_angle, g_angle_mean = tool0_deviation(
        tmp / "ur5-geometry-out" / "calibrated.urdf", Q
    )
    print(
        f"| calibrated, --params origins,offsets ({geometry['fitted']}) | {np.mean(g_errors):.4f} / {rms(g_errors):.4f} / "
        f"{max(g_errors):.3f} | {g_distance:.2f} / {g_distance_mean:.2f} | {g_angle:.3f} / {g_angle_mean:.3f} | "
        + ", ".join(f"{v * 1e3:.2f}" for v in geometry["frames"]["point_in_flange"]["xyz"])
        + " |"
    )
    print()
    ident = summary["identifiability"]
    print(
        f"identified {ident['identified']} of {ident['candidates']} ({ident['identifiable_by_rank']} by rank), "
        f"precision {ident['precision']}; noise {summary['noise']['position_mm']:.4f} mm per coordinate"
    )
    for h in ident["held"]:
        top = sorted(h["parameter_sigma"].items(), key=lambda kv: -abs(kv[1] or 0))[:3]
        print(
            f"  held: σ {h['sigma_in_precision_units']:.3g} × the precision, {h['sigmas_from_nominal']:.1f} σ "
            "from nominal: " + ", ".join(f"{k} ±{v:.3g}" for k, v in top)
        )
    if terms:
        sigmas = [h["sigma_in_precision_units"] for h in terms["held"]]
        print(
            f"  the chosen set with its terms: {len(sigmas)} combinations held"
            + (f", σ {min(sigmas):.3g} to {max(sigmas):.3g} × the precision" if sigmas else "")
        )
    print(flange_gauge_line(geometry_doc) + " (--params origins,offsets)")
    print(unseen_points(grid, tmp))
    print(f"time: check {check_wall:.1f} s wall, fit {fit_wall:.1f} s wall ({fit_cpu:.1f} s CPU)")
    if not subsets:
        return
    order = np.random.default_rng(0).permutation(len(grid))
    found = []
    for k in range(subsets):
        picked = [grid[int(i)] for i in sorted(order[50 * k : 50 * k + 50])]
        sub = write_ur5_dataset(tmp / f"ur5-{k}", picked)
        s, doc, _w, _c = fit(sub, tmp / f"ur5-{k}-out", "--folds", str(folds))
        d, dm, a, am = tool0_deviation(tmp / f"ur5-{k}-out" / "calibrated.urdf", Q)
        errs = held_out(doc, "cross_validated_mm")
        found.append(
            (
                d,
                a,
                float(np.mean(errs)),
                dm,
                am,
                s["frames"]["point_in_flange"]["xyz"][2] * 1e3,
                len(s["identifiability"]["held"]),
            )
        )
    column = list(zip(*found))
    print(
        f"{subsets} disjoint 50-pose subsets (each fitted alone, default options; tool0 over all {len(grid)} poses): "
        f"tool0 max {min(column[0]):.2f}-{max(column[0]):.2f} mm and {min(column[1]):.3f}-{max(column[1]):.3f}°, "
        f"mean {min(column[3]):.2f}-{max(column[3]):.2f} mm and {min(column[4]):.3f}-{max(column[4]):.3f}°; "
        f"held-out mean (their own nested 5-fold) {min(column[2]):.3f}-{max(column[2]):.3f} mm; reflector z "
        f"{min(column[5]):.2f}-{max(column[5]):.2f} mm; combinations held {min(column[6])}-{max(column[6])}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT / ".." / "shared" / "calib-real")
    parser.add_argument("--folds", type=int, default=5)
    parser.add_argument("--splits", type=int, default=5, help="FR3: fold partitions pooled")
    parser.add_argument("--subsets", type=int, default=20, help="UR5: disjoint 50-pose subsets fitted alone")
    parser.add_argument("--only", choices=["fr3", "ur5"])
    args = parser.parse_args()
    load = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        if args.only != "ur5":
            if not (args.data / "franka_fr3" / "camera_in_board.csv").is_file():
                sys.exit(f"no FR3 data in {args.data}")
            fr3(args.data / "franka_fr3", Path(tmp), args.folds, args.splits)
            print()
        if args.only != "fr3":
            if not (args.data / "ur5_tracker" / UR5_CSV).is_file():
                sys.exit(f"no UR5 tracker data in {args.data}")
            ur5(args.data / "ur5_tracker", Path(tmp), args.folds, args.subsets)
    load_after = os.getloadavg()
    print(f"load average {load[0]:.1f} before, {load_after[0]:.1f} after ({os.cpu_count()} cores)")


if __name__ == "__main__":
    main()
