"""armtool's `search` solver on 6R arms with no closed form (the 1-D search, armtool/ik/closed_form/search.py).

One process. Per search arm (xArm6, Kinova Gen3 lite from ../shared/realworld): targets are FK of
uniform random configurations within the limits, every solve from the mid-range seed. Timed: the
solver's `call` on the inputs `prepare` made beforehand, taking turns on blocks of 50 targets with
`analytic` on UR5 (its closed form, example-robot-data), so that the ratio compares the two in the
same run. Success: the target's own configuration is among the solutions (modulo 2π) and every
solution passes armtool's FK check. Solutions per target are compared with an independent
enumeration on the first --enumerate targets: SciPy's least squares (bounded by the limits) from
--seeds random seeds, verified, refined and deduplicated at 1e-6 rad; "missing" counts enumerated
solutions the search lacks.

Targets (issue 29, item 3): 100 % success, no missing solution, median ≤ 10× UR5's closed-form
median. Cross-check on an arm that has a closed form with the search's structure: UR10
(example-robot-data, world → tool0) on --samples bench targets (armtool.ik.bench.make_targets), the
search's solution sets against `analytic`'s, deduplicated at 1e-6 rad: missing and extra solutions.
PASS/FAIL lines on stdout; exit 1 with --strict when a target is missed.

    python benchmarks/ik_search.py [--samples 1000] [--enumerate 20] [--seeds 200] [--strict]
"""

from __future__ import annotations

import argparse
import glob
import statistics
import sys
from pathlib import Path

import numpy as np

BLOCK = 50
RATIO = 10.0
REALWORLD = Path(__file__).resolve().parents[1] / ".." / "shared" / "realworld"
ARMS = {
    "xarm6": ("xarm_ros2/xarm_description/urdf/xarm_device.urdf.xacro", {"dof": "6"}, "link_base", "link6"),
    "gen3-lite": ("ros2_kortex/kortex_description/robots/gen3_lite.urdf", {}, "base_link", "tool_frame"),
}


def load(name: str):  # type: ignore[no-untyped-def]
    from armtool.model.chain import chain_from_xml
    from armtool.model.load import load_robot_xml

    relative, args, base, tip = ARMS[name]
    return chain_from_xml(load_robot_xml(REALWORLD / relative, args, [REALWORLD.resolve()]), base, tip)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1000)
    parser.add_argument("--enumerate", type=int, default=20)
    parser.add_argument("--seeds", type=int, default=200)
    parser.add_argument("--strict", action="store_true")
    opts = parser.parse_args()

    from armtool.ik import load_chain, make_solver
    from armtool.ik.solutions import enumerate_by_least_squares, missing
    from armtool.ik.solver import verify

    ur5_path = glob.glob(
        f"{sys.prefix}/**/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf", recursive=True
    )
    ur5 = load_chain(ur5_path[0])
    ur5_solver = make_solver("analytic", ur5)
    ur5_targets = [ur5.fk(q) for q in ur5.random(np.random.default_rng(0), opts.samples)]
    failed = False
    for name in ARMS:
        if not (REALWORLD / ARMS[name][0]).is_file():
            print(f"{name}: skipped (../shared/realworld absent)")
            continue
        chain = load(name)
        solver = make_solver("search", chain)
        rng = np.random.default_rng(1)
        Q = chain.random(rng, opts.samples)
        targets = [chain.fk(q) for q in Q]
        mid, ur_mid = chain.mid(), ur5.mid()
        ours: list[float] = []
        ur: list[float] = []
        raws = []
        for start in range(0, opts.samples, BLOCK):
            for turn in (0, 1) if (start // BLOCK) % 2 == 0 else (1, 0):
                for i in range(start, min(start + BLOCK, opts.samples)):
                    if turn == 0:
                        p = solver.prepare(targets[i], mid)
                        t0 = solver.clock()
                        raw = solver.call(p)
                        ours.append(solver.clock() - t0)
                        raws.append((i, raw.copy()))
                    else:
                        p = ur5_solver.prepare(ur5_targets[i], ur_mid)
                        t0 = ur5_solver.clock()
                        ur5_solver.call(p)
                        ur.append(ur5_solver.clock() - t0)
        success, counts, enum_counts, missed, bad = 0, [], [], 0, 0
        for i, raw in sorted(raws, key=lambda item: item[0]):
            result = solver.judge(solver.answer(raw), targets[i])
            sols = np.array(result.solutions).reshape(-1, 6)
            bad += sum(not verify(chain, s, targets[i], 1e-5)[0] for s in sols)
            if len(sols) and float(np.min(np.max(np.abs((sols - Q[i] + np.pi) % (2 * np.pi) - np.pi), axis=1))) < 1e-7:
                success += 1
            counts.append(len(sols))
            if i < opts.enumerate:
                others = enumerate_by_least_squares(chain, targets[i], chain.random(rng, opts.seeds))
                enum_counts.append(len(others))
                missed += missing(chain, sols, others)
        med, ur_med = statistics.median(ours) * 1e6, statistics.median(ur) * 1e6
        n_enum = max(len(enum_counts), 1)
        print(f"{name}: {solver.method}")
        print(
            f"  success {100.0 * success / opts.samples:.1f} % of {opts.samples}; solutions per target {np.mean(counts):.2f}; "
            f"on the first {len(enum_counts)}: search {np.mean(counts[: len(enum_counts)]):.2f}, enumeration "
            f"{sum(enum_counts) / n_enum:.2f} ({opts.seeds} least-squares seeds), missing {missed}; failing the check {bad}"
        )
        print(f"  median {med:.1f} µs; UR5 closed form {ur_med:.2f} µs; ratio {med / ur_med:.1f}×")
        for label, ok in (
            ("100 % success", success == opts.samples and bad == 0),
            ("no missing solution", missed == 0),
            (f"median ≤ {RATIO:g}× UR5's closed form", med <= RATIO * ur_med),
        ):
            print(f"  {'PASS' if ok else 'FAIL'} {name}: {label}")
            failed |= not ok
    failed |= not cross_check(opts.samples)
    return 1 if (failed and opts.strict) else 0


def cross_check(samples: int) -> bool:
    """UR10: the search's solution sets against the closed form's on the bench's targets; whether they agree."""
    from armtool.ik import load_chain, make_solver
    from armtool.ik.bench import BenchConfig, make_targets

    paths = glob.glob(f"{sys.prefix}/**/example-robot-data/robots/ur_description/urdf/ur10_robot.urdf", recursive=True)
    chain = load_chain(paths[0], "world", "tool0")
    closed, search = make_solver("analytic", chain), make_solver("search", chain)
    targets = make_targets(chain, BenchConfig(samples=samples))
    total = lacking = extra = 0
    for pose, seed in zip(targets.poses, targets.seeds):
        a = np.array(closed.solve(pose, seed).solutions).reshape(-1, 6)
        s = np.array(search.solve(pose, seed).solutions).reshape(-1, 6)
        near = np.max(np.abs((a[:, None, :] - s[None, :, :] + np.pi) % (2 * np.pi) - np.pi), axis=2) < 1e-6
        total += len(a)
        lacking += int(np.sum(~near.any(axis=1))) if len(s) else len(a)
        extra += int(np.sum(~near.any(axis=0))) if len(a) else len(s)
    print(
        f"ur10 cross-check: {samples} targets, {total} closed-form solutions; the search lacks {lacking}, adds {extra}"
    )
    ok = lacking == 0 and extra == 0
    print(f"  {'PASS' if ok else 'FAIL'} ur10: the search's sets are the closed form's")
    return ok


if __name__ == "__main__":
    sys.exit(main())
