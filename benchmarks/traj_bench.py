"""How good is `armtool traj`? Limits, optimality against TOPP-RA, the lecture's circle, a wrist flip.

1. Limits and optimality: 100 random joint paths (5 waypoints each, uniform within the middle
   half of every joint's range; paths whose spline through the waypoints leaves the position limits
   are redrawn) for Panda and UR5 from example-robot-data, with the URDF's velocity limits and the
   acceleration limits below. Each is timed four ways on the same path (the same cubic spline
   through the waypoints): armtool's TOPP-RA (`traj time`), toppra 0.6's `TOPPRA` (its own grid)
   with each of its two parametrizers, `ParametrizeConstAccel` and its default `ParametrizeSpline`,
   and a uniform-scaling trapezoid (one trapezoidal ṡ profile whose ṡ and s̈ bounds are the most
   restrictive along the whole path, ignoring the q''·ṡ² term, as a naive timer does).
   Each method is judged by its own exact trajectory, never through another's model: toppra's by
   its own `jt(t)`, `jt(t, 1)`, `jt(t, 2)` and the trapezoid's by its own formula, both on a
   20,000-point grid; armtool's by its own output model, the cubic Hermite between its samples
   (exactly, `armtool.traj.check`). Reported: total duration, paths with a violation (velocity >
   limit·(1+1e-6), acceleration > limit·(1+1e-3)) and the worst ratio to the limit.
2. The lecture's circle on Panda (radius 0.1 m in the base y-z plane through the flange's start
   position, eef step 1 mm ≈ the lecture's 0.01 rad): fraction, worst deviation of points and joint
   midpoints from the circle (recomputed here by FK), jumps, and the CPU time of cartesian + time
   in this process and of the `armtool traj cartesian | armtool traj time` pipeline (two processes,
   start-up included; median of 5, against the issue's 1 s target, beside the CPU that importing the
   two processes' libraries costs alone). `--armtool` names the executable: use a regular install.
3. A UR5 line through a wrist singularity: what `lm` and `analytic` do, with the jump indices by
   both rules.

    python benchmarks/traj_bench.py [--paths 100] [--format markdown|json] [--armtool /path/to/bin/armtool]
"""

from __future__ import annotations

import argparse
import glob
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

from armtool.ik.registry import make_solver
from armtool.ik.solver import rotation_error
from armtool.model.chain import load_chain
from armtool.traj import cartesian as cart
from armtool.traj.check import ACC_TOL, VEL_TOL, check, hermite_extremes
from armtool.traj.limits import JointLimits, load_limits
from armtool.traj.path import joint_path
from armtool.traj.timing import time_optimal
from armtool.traj.trajectory import Trajectory

# Acceleration limits (rad/s²) are not in a URDF: those of MoveIt's own configurations.
# Panda: moveit_resources/panda_moveit_config/config/joint_limits.yaml (the limits of moveit2 #3778).
# UR5: Universal_Robots_ROS2_Driver/ur_moveit_config/config/joint_limits.yaml (5.0 for every joint).
ACC = {
    "panda": [3.75, 1.875, 2.5, 3.125, 3.75, 5.0, 5.0],
    "ur5": [5.0] * 6,
}
GRID = 20_000  # points on which a peer's own trajectory is evaluated
TOPPRA_PARAMETRIZERS = ("ParametrizeConstAccel", "ParametrizeSpline")
PIPELINE_TARGET_S = 1.0  # issue 11: the whole `cartesian | time` pipeline in under 1 s of CPU
PIPELINE_RUNS = 5
ROBOTS = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_link8"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", None, None),
}


def erd(relative: str) -> Path:
    hits = glob.glob(f"{sys.prefix}/**/example-robot-data/robots/{relative}", recursive=True)
    if not hits:
        sys.exit(f"example-robot-data not installed ({relative}): pip install -e '.[dev]'")
    return Path(hits[0])


Evaluate = Any  # t (k,) -> (q, q', q'') each (k, n): a method's own trajectory


def worst_armtool(traj: Trajectory, lim: JointLimits) -> tuple[float, float]:
    """Worst velocity and acceleration ratio to the limit of armtool's output by its own model: the
    cubic Hermite between its samples, exactly (as `traj check` and a controller read it)."""
    assert traj.times is not None and traj.velocities is not None and traj.accelerations is not None
    vmax, amax, _ = hermite_extremes(traj.times, traj.positions, traj.velocities)
    v = max(float((vmax / lim.velocity).max()), float((np.abs(traj.velocities) / lim.velocity).max()))
    a = max(float((amax / lim.acceleration).max()), float((np.abs(traj.accelerations) / lim.acceleration).max()))
    return v, a


def worst_exact(evaluate: Evaluate, duration: float, lim: JointLimits, grid: int = GRID) -> tuple[float, float]:
    """Worst velocity and acceleration ratio to the limit of a trajectory by its own evaluation on a
    `grid`-point grid over [0, duration]: no resampling, no interpolation of ours in between."""
    t = np.linspace(0.0, duration, grid)
    _, qd, qdd = evaluate(t)
    return float((np.abs(qd) / lim.velocity).max()), float((np.abs(qdd) / lim.acceleration).max())


def toppra_time(path: Any, lim: JointLimits, parametrizer: str) -> tuple[float, Evaluate]:
    import toppra as ta
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    ta.setup_logging("ERROR")
    spline = ta.SplineInterpolator(path.s, path.waypoints, bc_type="natural")
    vlim = np.stack([-lim.velocity, lim.velocity], axis=1)
    alim = np.stack([-lim.acceleration, lim.acceleration], axis=1)
    inst = algo.TOPPRA(
        [constraint.JointVelocityConstraint(vlim), constraint.JointAccelerationConstraint(alim)],
        spline,
        parametrizer=parametrizer,
    )
    jt = inst.compute_trajectory()
    return float(jt.duration), lambda t: (jt(t), jt(t, 1), jt(t, 2))


def trapezoid_time(path: Any, lim: JointLimits) -> tuple[float, Evaluate]:
    s = np.linspace(0, path.length, 2000)
    _, dq, _ = path.eval(s)
    sd_max = float(np.min(lim.velocity / np.maximum(np.abs(dq), 1e-12)))
    sdd_max = float(np.min(lim.acceleration / np.maximum(np.abs(dq).max(axis=0), 1e-12)))
    L = path.length
    t_acc = sd_max / sdd_max
    if sdd_max * t_acc**2 > L:  # triangle
        t_acc = math.sqrt(L / sdd_max)
        sd_max = sdd_max * t_acc
    t_cruise = (L - sdd_max * t_acc**2) / sd_max
    T = 2 * t_acc + t_cruise

    def profile(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        a1, c1 = t < t_acc, t < t_acc + t_cruise
        td = T - t
        sv = np.where(
            a1,
            0.5 * sdd_max * t**2,
            np.where(c1, 0.5 * sdd_max * t_acc**2 + sd_max * (t - t_acc), L - 0.5 * sdd_max * td**2),
        )
        v = np.where(a1, sdd_max * t, np.where(c1, sd_max, sdd_max * td))
        acc = np.where(a1, sdd_max, np.where(c1, 0.0, -sdd_max))
        q, d1, d2 = path.eval(np.clip(sv, 0, L))
        return q, d1 * v[:, None], d1 * acc[:, None] + d2 * (v**2)[:, None]

    return T, profile


def random_paths(lim: JointLimits, count: int, seed: int) -> list[Trajectory]:
    rng = np.random.default_rng(seed)
    lo, hi = np.maximum(lim.lower, -2 * math.pi), np.minimum(lim.upper, 2 * math.pi)
    mid, half = (lo + hi) / 2, (hi - lo) / 4
    out: list[Trajectory] = []
    while len(out) < count:
        q = rng.uniform(mid - half, mid + half, size=(5, len(lim.names)))
        dense = joint_path(q).spline(np.linspace(0, joint_path(q).length, 400))
        if np.all((dense >= lim.lower) & (dense <= lim.upper)):
            out.append(Trajectory(lim.names, q))
    return out


def limits_bench(robot: str, count: int) -> dict[str, Any]:
    rel, base, tip = ROBOTS[robot]
    urdf = erd(rel)
    chain = load_chain(urdf, base, tip)
    names = chain.joint_names
    full = load_limits(urdf, acc_limits=[",".join(f"{n}={a}" for n, a in zip(names, ACC[robot]))])
    lim = full.subset(names)
    methods = ["armtool", *(f"toppra ({p})" for p in TOPPRA_PARAMETRIZERS), "trapezoid"]
    rows: dict[str, dict[str, Any]] = {
        k: {
            "duration_s": 0.0,
            "violating_paths": 0,
            "worst_velocity_ratio": 0.0,
            "worst_acceleration_ratio": 0.0,
            "cpu_s": 0.0,
        }
        for k in methods
    }
    ratios = []
    reference = f"toppra ({TOPPRA_PARAMETRIZERS[0]})"
    for path in random_paths(lim, count, seed=1 if robot == "panda" else 2):
        spline = joint_path(path.positions)
        c0 = time.process_time()
        ours = time_optimal(path, full)
        c1 = time.process_time()
        errors = [f for f in check(ours, full) if f.severity.value == "error"]
        # (duration, worst v ratio, worst a ratio, CPU, flagged by armtool's own check)
        results = {"armtool": (ours.duration_s, *worst_armtool(ours, lim), c1 - c0, bool(errors))}
        for parametrizer in TOPPRA_PARAMETRIZERS:
            c0 = time.process_time()
            d, evaluate = toppra_time(spline, lim, parametrizer)
            cpu = time.process_time() - c0
            results[f"toppra ({parametrizer})"] = (d, *worst_exact(evaluate, d, lim), cpu, False)
        d, evaluate = trapezoid_time(spline, lim)
        results["trapezoid"] = (d, *worst_exact(evaluate, d, lim), 0.0, False)
        for key, (dur, v, a, cpu, flagged) in results.items():
            row = rows[key]
            row["duration_s"] += dur
            row["cpu_s"] += cpu
            row["violating_paths"] += int(flagged or v > 1 + VEL_TOL or a > 1 + ACC_TOL)
            row["worst_velocity_ratio"] = max(row["worst_velocity_ratio"], v)
            row["worst_acceleration_ratio"] = max(row["worst_acceleration_ratio"], a)
        ratios.append(results["armtool"][0] / results[reference][0])
    return {
        "robot": robot,
        "paths": count,
        "per_method": rows,
        "duration_ratio_to_toppra": {
            "reference": reference,
            "total": rows["armtool"]["duration_s"] / rows[reference]["duration_s"],
            "max_per_path": max(ratios),
            "min_per_path": min(ratios),
        },
    }


def circle_bench(armtool: Path) -> dict[str, Any]:
    urdf = erd(ROBOTS["panda"][0])
    chain = load_chain(urdf, "panda_link0", "panda_link8")
    q0 = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])
    full = load_limits(urdf, acc_limits=[",".join(f"{n}={a}" for n, a in zip(chain.joint_names, ACC["panda"]))])
    T0 = chain.fk(q0)
    center = T0[:3, 3] + np.array([0.0, -0.1, 0.0])
    seg = cart.circle_segment(T0, center, np.array([1.0, 0.0, 0.0]), 2 * math.pi)
    c0 = time.process_time()
    ik = make_solver("lm", chain, lazy_table=True)  # as `traj cartesian` builds it
    r = cart.compute_cartesian(chain, ik, q0, [seg], cart.CartesianOptions(eef_step_m=0.001))
    c1 = time.process_time()
    timed = time_optimal(Trajectory(tuple(chain.joint_names), r.q), full)
    c2 = time.process_time()
    dev_m = dev_rad = 0.0
    for k in range(len(r.q) - 1):
        for q, lam in ((r.q[k], r.params[k]), ((r.q[k] + r.q[k + 1]) / 2, (r.params[k] + r.params[k + 1]) / 2)):
            T, ideal = chain.fk(q), seg.pose_at(float(lam))
            dev_m = max(dev_m, float(np.linalg.norm(T[:3, 3] - ideal[:3, 3])))
            dev_rad = max(dev_rad, float(np.linalg.norm(rotation_error(T[:3, :3], ideal[:3, :3]))))
    findings = [f.code for f in check(timed, full)]
    # The same as two processes through a pipe, start-up included.
    exe, python = str(armtool), str(armtool.with_name("python"))
    with tempfile.TemporaryDirectory() as d:
        jl = Path(d) / "jl.yaml"
        jl.write_text(
            "joint_limits:\n"
            + "".join(
                f"  {n}: {{has_acceleration_limits: true, max_acceleration: {a}}}\n"
                for n, a in zip(chain.joint_names, ACC["panda"])
            )
        )
        cmd = (
            f"{exe} traj cartesian {urdf} --base panda_link0 --tip panda_link8 --start {','.join(map(str, q0))} "
            f"--center-offset 0,-0.1,0 --normal 1,0,0 --eef-step 0.001 2>/dev/null | {exe} traj time - --urdf {urdf} "
            f"--joint-limits {jl} -o {d}/out.csv 2>/dev/null"
        )
        runs = []
        for _ in range(PIPELINE_RUNS):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run(cmd, shell=True, check=True, env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            runs.append((after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime))
        # The floor: the same two interpreters importing only what the two commands cannot do without.
        floor = []
        for _ in range(PIPELINE_RUNS):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            for modules in (
                "numpy, typer, rich.console, lxml.etree, pinocchio",
                "numpy, typer, rich.console, lxml.etree, yaml",
            ):
                subprocess.run([python, "-c", f"import {modules}"], check=True)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            floor.append((after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime))
    pipeline_cpu = sorted(runs)[len(runs) // 2]
    return {
        "points": len(r.q),
        "fraction": r.fraction,
        "inserted": r.inserted,
        "max_deviation_mm": dev_m * 1000,
        "max_deviation_rad": dev_rad,
        "relative_jumps": r.relative_jumps,
        "absolute_jumps": r.absolute_jumps,
        "cpu_cartesian_s": c1 - c0,
        "cpu_time_s": c2 - c1,
        "duration_s": timed.duration_s,
        "check_findings": findings,
        "cpu_pipeline_two_processes_s": pipeline_cpu,
        "cpu_pipeline_runs_s": runs,
        "cpu_import_floor_s": sorted(floor)[len(floor) // 2],
        "load_average": os.getloadavg()[0],
        "armtool": exe,
    }


def flip_bench() -> dict[str, Any]:
    chain = load_chain(erd(ROBOTS["ur5"][0]))
    qa = np.array([0.3, -1.2, 1.5, -1.8, 0.15, 0.4])
    qb = qa.copy()
    qb[4] = -0.15
    seg = cart.line_segment(chain.fk(qa), chain.fk(qb))
    out = {}
    for name in ("lm", "analytic"):
        r = cart.compute_cartesian(
            chain, make_solver(name, chain), qa, [seg], cart.CartesianOptions(eef_step_m=0.002, eef_step_rad=0.01)
        )
        out[name] = {
            "fraction": r.fraction,
            "reason": r.reason,
            "detail": r.detail,
            "relative_jumps": r.relative_jumps,
            "absolute_jumps": r.absolute_jumps,
            "points": len(r.q),
        }
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--paths", type=int, default=100)
    ap.add_argument("--format", choices=["markdown", "json"], default="markdown")
    ap.add_argument(
        "--armtool",
        type=Path,
        default=Path(sys.executable).with_name("armtool"),
        help="the armtool executable for the pipeline's CPU; use a regular (non-editable) install: with "
        "PYTHONDONTWRITEBYTECODE=1 an editable one compiles armtool's sources at every start",
    )
    args = ap.parse_args()
    results = {
        "limits": [limits_bench(r, args.paths) for r in ("panda", "ur5")],
        "circle": circle_bench(args.armtool),
        "flip": flip_bench(),
    }
    if args.format == "json":
        print(json.dumps(results, indent=2))
        return
    print(
        "| robot | timing | total duration (s) | paths over a limit | worst v/limit | worst a/limit | CPU per path (ms) |"
    )
    print("|---|---|---|---|---|---|---|")
    for res in results["limits"]:
        for key, row in res["per_method"].items():
            cpu = f"{row['cpu_s'] / res['paths'] * 1000:.1f}" if key != "trapezoid" else "-"
            print(
                f"| {res['robot']} | {key} | {row['duration_s']:.2f} | {row['violating_paths']}/{res['paths']} | "
                f"{row['worst_velocity_ratio']:.4f} | {row['worst_acceleration_ratio']:.4f} | {cpu} |"
            )
    print(
        f"\nEach method judged by its own exact trajectory: armtool by the cubic Hermite through its samples "
        f"(exactly), toppra by its own jt(t, 1) and jt(t, 2), the trapezoid by its own formula, both on a "
        f"{GRID:,}-point grid."
    )
    for res in results["limits"]:
        r = res["duration_ratio_to_toppra"]
        print(
            f"{res['robot']}: armtool / {r['reference']} duration: total {r['total']:.4f}, "
            f"per path {r['min_per_path']:.4f}..{r['max_per_path']:.4f}"
        )
    c = results["circle"]
    print(
        f"\nPanda circle: {c['points']} points, fraction {c['fraction']}, {c['inserted']} inserted, worst deviation "
        f"{c['max_deviation_mm']:.4f} mm / {c['max_deviation_rad']:.5f} rad, jumps rel {c['relative_jumps']} abs {c['absolute_jumps']}, "
        f"check findings {c['check_findings']}; CPU in-process: cartesian {c['cpu_cartesian_s']:.3f} s + time {c['cpu_time_s']:.3f} s; "
        f"duration {c['duration_s']:.3f} s"
    )
    verdict = "met" if c["cpu_pipeline_two_processes_s"] < PIPELINE_TARGET_S else "missed"
    print(
        f"Pipeline `armtool traj cartesian ... | armtool traj time -` (two processes, start-up included): "
        f"{c['cpu_pipeline_two_processes_s']:.2f} s of CPU (user+sys of both, median of {PIPELINE_RUNS}: "
        f"{', '.join(f'{x:.2f}' for x in c['cpu_pipeline_runs_s'])}) against the target < {PIPELINE_TARGET_S:g} s: "
        f"{verdict}. Importing what the two need (numpy, typer, rich, lxml, and pinocchio or yaml) costs "
        f"{c['cpu_import_floor_s']:.2f} s by itself here (load average {c['load_average']:.1f}; {c['armtool']})."
    )
    for name, f in results["flip"].items():
        print(
            f"UR5 wrist flip, {name}: fraction {f['fraction']:.4f}, reason '{f['reason']}' {f['detail']}; "
            f"relative-rule jumps {f['relative_jumps']}, absolute-rule jumps {f['absolute_jumps']}"
        )


if __name__ == "__main__":
    main()
