"""IK benchmark: armtool's solvers beside TRAC-IK (pytracik) and roboticstoolbox's ik_LM, one process.

TRAC-IK's protocol on Panda, UR5, xArm7 and Kinova (example-robot-data): N configurations uniform
within limits → FK → targets; every solve from the mid-range seed; 5 ms timeout; tolerance 1e-5
per twist component, verified by armtool's FK. Prints a markdown table per robot, ratios against
the peers measured in the same run, and PASS/FAIL for the targets of the ik-bench issue.
Peers need `pip install 'armtool[peers]'`; missing ones are skipped with the install command.

    python benchmarks/ik_bench.py --samples 1000
"""

from __future__ import annotations

import argparse
import glob
import os
import sys
from pathlib import Path

ROBOTS = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_hand"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", None, None),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", None, None),
    "kinova": ("kinova_description/robots/kinova.urdf", None, None),
}


def robot_file(relative: str) -> Path:
    hits = glob.glob(f"{sys.prefix}/**/example-robot-data/robots/{relative}", recursive=True)
    if not hits:
        sys.exit("example-robot-data is not installed: pip install example-robot-data")
    return Path(hits[0])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--samples", type=int, default=1000)
    parser.add_argument("--timeout", type=float, default=0.005)
    parser.add_argument("--robots", default=",".join(ROBOTS))
    parser.add_argument("--ikpy-samples", type=int, default=100, help="ikpy is slow: fewer targets for it")
    args = parser.parse_args()

    from armtool.errors import ArmtoolError
    from armtool.ik.bench import BenchConfig, make_targets, run_solver
    from armtool.ik.chain import chain_from_xml
    from armtool.ik.peers import make_peer
    from armtool.ik.registry import make_solver, solver_names
    from armtool.model.load import load_robot_xml

    print(f"armtool ik benchmark: {args.samples} targets per robot, timeout {args.timeout * 1e3:g} ms, "
          f"tolerance 1e-5, seed mid-range; Python {sys.version.split()[0]}, {os.cpu_count()} CPUs\n")
    checks: list[tuple[str, bool]] = []
    for name in args.robots.split(","):
        relative, base, tip = ROBOTS[name]
        root = load_robot_xml(robot_file(relative))
        chain = chain_from_xml(root, base, tip, source=name)
        config = BenchConfig(samples=args.samples, timeout=args.timeout, repeat=0)
        targets = make_targets(chain, config)
        rows = []
        for solver_name in solver_names():
            try:
                solver = make_solver(solver_name, chain, timeout=args.timeout)
            except ArmtoolError as exc:
                print(f"  {name}: {solver_name} skipped: {exc.what}")
                continue
            rows.append(run_solver(chain, solver, targets, config))
            if solver_name == "lm":
                rows.append(run_solver(chain, solver, targets, config, batch=True))
        for peer_name in ("pytracik", "rtb-lm", "ikpy"):
            peer = make_peer(peer_name, chain, root, timeout=args.timeout, tolerance=1e-5)
            if isinstance(peer, str):
                print(f"  {peer_name} skipped: {peer}")
                continue
            if peer_name == "ikpy":
                small = BenchConfig(samples=min(args.ikpy_samples, args.samples), timeout=args.timeout, repeat=0)
                rows.append(run_solver(chain, peer, make_targets(chain, small), small))
            else:
                rows.append(run_solver(chain, peer, targets, config))
        by = {(r.solver, r.mode): r for r in rows}
        tracik, rtb = by.get(("pytracik", "single")), by.get(("rtb-lm", "single"))
        print(f"### {name} ({chain.base} → {chain.tip}, {chain.n} joints)\n")
        print("| solver | success % | median µs | p95 µs | solves/s | median vs pytracik | median vs rtb-lm |")
        print("|---|---|---|---|---|---|---|")
        for r in rows:
            vs_t = f"{r.wall_us['median'] / tracik.wall_us['median']:.2f}x" if tracik else "-"
            vs_r = f"{r.wall_us['median'] / rtb.wall_us['median']:.2f}x" if rtb else "-"
            label = r.solver + (" (batch)" if r.mode == "batch" else "") + (f" (N={r.samples})" if r.samples != args.samples else "")
            print(f"| {label} | {100 * r.success_rate:.1f} | {r.wall_us['median']:.0f} | {r.wall_us['p95']:.0f} | "
                  f"{r.solves_per_s:,.0f} | {vs_t} | {vs_r} |")
        print()
        lm, batch = by[("lm", "single")], by[("lm", "batch")]
        checks.append((f"{name}: lm success >= 99.9 % ({100 * lm.success_rate:.1f} %)", lm.success_rate >= 0.999))
        if tracik:
            checks.append((f"{name}: lm median below pytracik's ({lm.wall_us['median']:.0f} vs {tracik.wall_us['median']:.0f} µs)",
                           lm.wall_us["median"] < tracik.wall_us["median"]))
        if rtb:
            checks.append((f"{name}: lm median within 3x of rtb ik_LM ({lm.wall_us['median'] / rtb.wall_us['median']:.2f}x)",
                           lm.wall_us["median"] <= 3 * rtb.wall_us["median"]))
            checks.append((f"{name}: lm batch >= 2x rtb ik_LM solves/s ({batch.solves_per_s / rtb.solves_per_s:.2f}x) "
                           f"at its success ({100 * batch.success_rate:.1f} vs {100 * rtb.success_rate:.1f} %)",
                           batch.solves_per_s >= 2 * rtb.solves_per_s and batch.success_rate >= rtb.success_rate))
        if name == "ur5" and ("analytic", "single") in by:
            a = by[("analytic", "single")]
            checks.append((f"ur5: analytic 100 % and median <= 50 µs ({100 * a.success_rate:.1f} %, {a.wall_us['median']:.0f} µs)",
                           a.success_rate == 1.0 and a.wall_us["median"] <= 50))
        if name == "panda" and ("kdl-nr-jl", "single") in by:
            k = by[("kdl-nr-jl", "single")]
            checks.append((f"panda: kdl-nr-jl within 3 points of KDL's published 62 % ({100 * k.success_rate:.1f} %)",
                           abs(100 * k.success_rate - 62) <= 3))
    print("Targets:")
    for text, ok in checks:
        print(f"  {'PASS' if ok else 'FAIL'}  {text}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
