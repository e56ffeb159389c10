"""armtool's `analytic` beside EAIK (pip install eaik): time per target, every solution, batch throughput.

One process; per arm, 1000 targets (FK of uniform random configurations within the limits), every
solve from the mid-range seed. The two solvers take turns on blocks of 50 targets (the order
alternating), as the CPU's speed may change during a run. Timed: armtool's `solver.call` on the
inputs `solver.prepare` made beforehand (the call does the whole solve, see
armtool/ik/solvers/analytic.py), and EAIK's `robot.IK(T)` on the target already in EAIK's tool
frame. Batch: armtool's `all_solutions(targets, seeds)` (the throughput call: every solution of
every target as arrays, one compiled call, one thread; its input conversion included) and EAIK's
`IK_batched(targets, 1)` (one worker thread), alternating BATCH_ROUNDS times; the median of each
one's throughput.

EAIK's robot is built from armtool's chain: the axes H and offsets P of its joint lines at q = 0,
a locked joint passed as EAIK's `fixed_axes`. Its tool frame is the tip's position with the base's
orientation, so its targets are T·Rot(R_tip(0))ᵀ (converted before the timing). Each run checks
every solution of both with armtool's chain FK (every twist component within 1e-5); a solution
counts when it has an equivalent modulo 2π within the joint limits; sets are compared modulo 2π
at 1e-6 rad: "missing" counts EAIK's verified solutions armtool lacks, "extra" armtool's solutions
EAIK lacks (every armtool solution is verified, so an extra one is a real solution EAIK missed).

Targets (issue 29): armtool's median ≤ 1.0× EAIK's on every arm in every run, no missing
solution, no armtool solution that fails the check, batch ≥ 5× EAIK's single-threaded batch.
PASS/FAIL lines on stdout; exit 1 with --strict when a target is missed.

    python benchmarks/ik_closed_form.py [--arms ur5,ur10,kinova,panda-j7] [--samples 1000] [--runs 3]
"""

from __future__ import annotations

import argparse
import glob
import math
import os
import statistics
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

BLOCK = 50
BATCH_ROUNDS = 5
TOLERANCE = 1e-5
SAME = 1e-6  # rad: two solutions are one modulo 2π

# name: (example-robot-data file, base, tip, locked joint and value)
ARMS: dict[str, tuple[str, str | None, str | None, tuple[str, float] | None]] = {
    "ur5": ("ur_description/urdf/ur5_robot.urdf", None, None, None),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", None, None, None),
    "kinova": ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector", None),
    "panda-j7": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_hand", ("panda_joint7", 0.3)),
    "panda-j6": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_hand", ("panda_joint6", 1.2)),
    "panda-j6-0": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_hand", ("panda_joint6", 0.0)),
    "panda-j5": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_hand", ("panda_joint5", 0.3)),
    "panda-j5-0": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_hand", ("panda_joint5", 0.0)),
    "panda-j4": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_hand", ("panda_joint4", -1.5)),
}
DEFAULT = "ur5,ur10,kinova,panda-j7,panda-j6,panda-j5,panda-j5-0,panda-j4"


def erd(relative: str) -> Path | None:
    hits = glob.glob(f"{sys.prefix}/**/example-robot-data/robots/{relative}", recursive=True)
    return Path(hits[0]) if hits else None


@dataclass
class Result:
    eaik_us: float
    ours_us: float
    eaik_solutions: float
    ours_solutions: float
    missing: int
    extra: int
    ours_failing: int  # armtool solutions that fail the FK check (must be 0)
    eaik_batch: float  # targets/s
    ours_batch: float
    family: str
    eaik_family: str


def eaik_robot(full: Any, lock: tuple[int, float] | None) -> tuple[Any, np.ndarray]:
    """EAIK's robot from the chain's joint lines (H, P), and the tool-frame conversion for its targets."""
    from eaik.IK_HP import HPRobot

    from armtool.ik.closed_form.geometry import axis_lines

    lines, tip0 = axis_lines(full)
    H = np.array([w for _, w in lines])
    pts = [p for p, _ in lines]
    P = np.array([pts[0]] + [pts[i] - pts[i - 1] for i in range(1, len(pts))] + [tip0[:3, 3] - pts[-1]])
    robot = HPRobot(H, P, [lock] if lock else [])
    to_eaik = np.eye(4)
    to_eaik[:3, :3] = tip0[:3, :3].T
    return robot, to_eaik


def counted(chain: Any, Q: np.ndarray, target: np.ndarray) -> list[np.ndarray]:
    """The solutions (rows of Q) that reach the target and have an equivalent within the limits."""
    from armtool.ik.solver import verify

    keep = []
    for q in Q:
        shifted = q.copy()
        ok = True
        for i, (lo, hi, cont) in enumerate(zip(chain.lower, chain.upper, chain.continuous)):
            if cont:
                continue
            v = q[i] + 2 * math.pi * math.ceil((lo - q[i]) / (2 * math.pi) - 1e-12)
            if v > hi + 1e-9:
                ok = False
                break
            shifted[i] = min(max(v, lo), hi)
        if ok and verify(chain, shifted, target, TOLERANCE)[0]:
            keep.append(q)
    return keep


def same(a: np.ndarray, b: np.ndarray) -> bool:
    return bool(np.max(np.abs(np.remainder(a - b + math.pi, 2 * math.pi) - math.pi)) <= SAME)


def run_arm(name: str, samples: int, seed: int) -> Result | None:
    from armtool.ik.registry import make_solver
    from armtool.model.chain import load_chain

    relative, base, tip, lock = ARMS[name]
    path = erd(relative)
    if path is None:
        print(f"{name}: example-robot-data not installed, skipped", file=sys.stderr)
        return None
    full = load_chain(path, base, tip)
    chain = full.locked({lock[0]: lock[1]}) if lock else full
    solver = make_solver("analytic", chain, tolerance=TOLERANCE)
    lock_index = (full.joint_names.index(lock[0]), lock[1]) if lock else None
    robot, to_eaik = eaik_robot(full, lock_index)
    rng = np.random.default_rng(seed)
    Q = chain.random(rng, samples)
    targets = np.ascontiguousarray(chain.fk_batch(Q))
    eaik_targets = np.ascontiguousarray(targets @ to_eaik)
    mid = chain.mid()
    prepared = [solver.prepare(t, mid) for t in targets]
    call, ik = solver.call, robot.IK
    for i in range(min(100, samples)):  # untimed first calls
        call(solver.prepare(targets[i], mid))
        ik(eaik_targets[i])
    ours_t, eaik_t = np.zeros(samples), np.zeros(samples)
    ours_raw: list[Any] = [None] * samples
    eaik_raw: list[Any] = [None] * samples
    clock = time.perf_counter
    for k, start in enumerate(range(0, samples, BLOCK)):
        stop = min(start + BLOCK, samples)
        for who in ("ours", "eaik") if k % 2 == 0 else ("eaik", "ours"):
            if who == "ours":
                for i in range(start, stop):
                    p = prepared[i]
                    t0 = clock()
                    raw = call(p)
                    ours_t[i] = clock() - t0
                    ours_raw[i] = raw
            else:
                for i in range(start, stop):
                    t = eaik_targets[i]
                    t0 = clock()
                    sol = ik(t)
                    eaik_t[i] = clock() - t0
                    eaik_raw[i] = sol
    # every solution checked, sets compared
    missing = extra = failing = 0
    n_eaik = n_ours = 0
    for i in range(samples):
        ours = list(solver.answer(ours_raw[i]).solutions)
        ok_ours = counted(chain, np.array(ours).reshape(-1, 6), targets[i])
        failing += len(ours) - len(ok_ours)
        eq = np.asarray(eaik_raw[i].Q, dtype=float).reshape(-1, full.n)
        if lock_index:
            eq = np.delete(eq, lock_index[0], axis=1)
        ok_eaik: list[np.ndarray] = []
        for q in counted(chain, eq, targets[i]):
            if not any(same(q, o) for o in ok_eaik):
                ok_eaik.append(q)
        n_eaik += len(ok_eaik)
        n_ours += len(ok_ours)
        missing += sum(not any(same(q, o) for o in ok_ours) for q in ok_eaik)
        extra += sum(not any(same(o, q) for q in ok_eaik) for o in ok_ours)
    # batch: alternating, median throughput of each
    seeds = np.tile(mid, (samples, 1))
    solver.prepare_batch(targets[:1], seeds[:1])  # the first batch loads the lanes (UR-type), untimed
    eaik_list = list(eaik_targets)
    ours_rate, eaik_rate = [], []
    for r in range(BATCH_ROUNDS):
        for who in ("ours", "eaik") if r % 2 == 0 else ("eaik", "ours"):
            if who == "ours":
                t0 = clock()
                solver.all_solutions(targets, seeds)
                ours_rate.append(samples / (clock() - t0))
            else:
                t0 = clock()
                robot.IK_batched(eaik_list, 1)
                eaik_rate.append(samples / (clock() - t0))
    return Result(
        float(np.median(eaik_t)) * 1e6,
        float(np.median(ours_t)) * 1e6,
        n_eaik / samples,
        n_ours / samples,
        missing,
        extra,
        failing,
        statistics.median(eaik_rate),
        statistics.median(ours_rate),
        solver.geometry.title,
        robot.getKinematicFamily(),
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    parser.add_argument("--arms", default=DEFAULT, help=f"of {', '.join(ARMS)}")
    parser.add_argument("--samples", type=int, default=1000)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--strict", action="store_true", help="exit 1 when a target is missed")
    args = parser.parse_args()
    try:
        import eaik  # noqa: F401
    except ImportError:
        print("EAIK is not installed (pip install eaik): nothing to compare with", file=sys.stderr)
        return 0
    names = [a.strip() for a in args.arms.split(",") if a.strip()]
    unknown = [a for a in names if a not in ARMS]
    if unknown:
        parser.error(f"unknown arm(s) {', '.join(unknown)}; arms: {', '.join(ARMS)}")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(
        f"analytic vs EAIK: {args.samples} targets per arm, {args.runs} run(s), {os.cpu_count()} CPUs, load {load:.1f}\n"
    )
    print(
        "| arm | run | family (armtool / EAIK) | EAIK µs | analytic µs | ratio | solutions EAIK / armtool | missing | extra | failing | batch EAIK k/s | batch analytic k/s | batch ratio |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    verdicts: list[tuple[str, bool, str]] = []
    for name in names:
        for run in range(args.runs):
            res = run_arm(name, args.samples, seed=11 + run)
            if res is None:
                break
            ratio, batch = res.ours_us / res.eaik_us, res.ours_batch / res.eaik_batch
            print(
                f"| {name} | {run + 1} | {res.family} / {res.eaik_family} | {res.eaik_us:.2f} | {res.ours_us:.2f} | "
                f"{ratio:.2f} | {res.eaik_solutions:.2f} / {res.ours_solutions:.2f} | {res.missing} | {res.extra} | "
                f"{res.ours_failing} | {res.eaik_batch / 1e3:.0f} | {res.ours_batch / 1e3:.0f} | {batch:.1f} |"
            )
            sys.stdout.flush()
            verdicts.append((f"{name} run {run + 1}: median ≤ 1.0× EAIK's", ratio <= 1.0, f"{ratio:.2f}×"))
            verdicts.append((f"{name} run {run + 1}: no EAIK solution missing", res.missing == 0, f"{res.missing}"))
            verdicts.append(
                (f"{name} run {run + 1}: every solution verified", res.ours_failing == 0, f"{res.ours_failing}")
            )
            verdicts.append((f"{name} run {run + 1}: batch ≥ 5× EAIK's (1 thread each)", batch >= 5.0, f"{batch:.1f}×"))
    print()
    for label, ok, value in verdicts:
        print(f"{'PASS' if ok else 'FAIL'}  {label} ({value})")
    if hasattr(os, "getloadavg"):
        print(f"\n(load average {os.getloadavg()[0]:.1f} at the end)")
    return 1 if args.strict and not all(ok for _, ok, _ in verdicts) else 0


if __name__ == "__main__":
    sys.exit(main())
