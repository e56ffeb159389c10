"""IK benchmark: every armtool solver beside TRAC-IK (pytracik), roboticstoolbox's ik_LM, ikpy and the
closed-form EAIK and IK-Geo, one process (offline).

TRAC-IK's protocol on seven arms, each at its real tool frame: Panda (panda_link0 → panda_hand),
UR5 and UR10 (→ tool0), Kinova j2s6s200 (→ j2s6s200_end_effector) and the 5-DOF SO-101 (base_link →
gripper_frame_link) from example-robot-data; xArm6 and xArm7 (link_base → link_eef) from the
real-repository corpus (xarm_ros2's xarm_device.urdf.xacro with dof:=6 / dof:=7, read in place;
an arm whose files are absent is skipped with a message). N configurations uniform within the
limits → FK → targets; every solve from the mid-range seed; 5 ms timeout; success = every twist
component within 1e-5 and q within the limits, by armtool's FK (`armtool.ik.bench.solver_report`),
whatever the solver claims. All solvers see the same targets; every solver with a batch mode of its
own (`lm`, EAIK's `IK_batched` on one thread) also runs batched (its `call_batch` over every target,
--batch-calls calls per round). ikpy is slow (~10 ms a solve) and runs on the first --ikpy-samples targets
only. A peer that is not installed is skipped with its install command (`pip install 'armtool[peers]'`);
one that cannot take an arm (EAIK and IK-Geo on a 7-DOF arm, EAIK on xArm6) is listed under the
arm's table with the reason.

Closed-form rows (`analytic`, `eaik`, `ik-geo`) are solved when any of their solutions passes the
check; "solutions" is the mean number of distinct verified solutions per target, "missing" how many
of the other closed-form solvers' solutions (their union) the row lacks (armtool.ik.bench.compare_solutions),
median over rounds. The issue-29 lines compare `analytic` with EAIK: its median at most EAIK's in
every round, its batch at least 5× EAIK's single-threaded `IK_batched`, no solution missing.

What is timed (armtool.ik.bench.TIMING): each solver's own solve call (with its own checks of its
inputs) and nothing else, for every row alike. Putting the target into a solver's input form (a
peer's quaternion, KDL frames, lm's contiguous arrays), reading its output into armtool's answer,
and checking every answer with armtool's FK happen outside the timed region.

Before round 1, every solver but ikpy solves the first --warmup targets (default 100) untimed, so that
round 1 runs in the same state as the rounds after it (lm's first round was often its slowest).
Rounds (--rounds, default 3) run one after the other, each after a garbage collection. Within a
round the solvers take turns block by block (--block targets, default 50; the order rotates from
block to block) and lm's batch calls (--batch-calls, default 4) are spread over the round, its
row showing their mean: the development VM switches between two CPU speeds 2x apart every few
seconds, and a solver that ran whole while the machine was fast would be compared with one
that ran while it was slow (with one batch call per round, timed at one moment against rtb's
throughput over the whole round, UR5's batch ratio was 2.6x, 3.3x and 3.6x in three runs). The
table shows the median over rounds of each figure. Absolute times swing with the CPU's speed;
ratios of solvers timed in turns do not, so the targets are ratios: lm's median over rtb's in
every round, and how far those per-round ratios spread ((max − min) / min).
Batched rows show the amortized time (total / N) as their median and
p95. "CPU median" is the median of each solve's process CPU time: on a loaded machine wall
times stretch with the time the process waits for a core, CPU times much less. rtb's ik_LM
and ikpy have no timeout: "> timeout" counts their solves that took longer than the protocol's.

"stalled" counts failed solves that got less than half the timeout in process CPU time while
their wall time ran past it: the machine ran something else meanwhile (a loaded machine, not
the solver). Only solvers with a timeout can fail that way. Process CPU time counts every thread
(TRAC-IK solves on two), and idle BLAS threads spinning can only lower the count.

Markdown tables and PASS/FAIL lines for the IK-speed issue's targets go to stdout; progress and
skipped solvers or arms to stderr. Exit code 0, or 1 with --strict when a target is missed.

    python benchmarks/ik_bench.py [--samples 1000] [--rounds 3] [--block 50] [--batch-calls 4] [--warmup 100] [--robots panda,ur5,ur10,xarm6,xarm7,kinova,so101]
        [--solvers lm,analytic] [--corpus ../shared/realworld]
"""

from __future__ import annotations

import argparse
import gc
import glob
import os
import platform
import statistics
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class Robot:
    """Where an arm's description lives and the chain to benchmark (base → its tool frame)."""

    source: str  # "erd" (example-robot-data) or "corpus" (the real-repository corpus)
    relative: str
    base: str | None  # None: the URDF's root
    tip: str
    xacro_args: dict[str, str] = field(default_factory=dict)


XARM = "xarm_ros2/xarm_description/urdf/xarm_device.urdf.xacro"
ROBOTS = {
    "panda": Robot("erd", "panda_description/urdf/panda.urdf", "panda_link0", "panda_hand"),
    "ur5": Robot("erd", "ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    "ur10": Robot("erd", "ur_description/urdf/ur10_robot.urdf", None, "tool0"),
    "xarm6": Robot("corpus", XARM, "link_base", "link_eef", {"dof": "6"}),
    "xarm7": Robot("corpus", XARM, "link_base", "link_eef", {"dof": "7"}),
    "kinova": Robot("erd", "kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector"),
    "so101": Robot("erd", "so_arm_description/urdf/so101.urdf", "base_link", "gripper_frame_link"),
}
DEFAULT_CORPUS = Path(__file__).resolve().parents[1] / ".." / "shared" / "realworld"
PEERS = ("pytracik", "rtb-lm", "ikpy", "pykdl", "eaik", "ik-geo")
TOLERANCE = 1e-5
KDL_PUBLISHED_PANDA = 62.0  # % success of KDL NR_JL on Panda in TRAC-IK's protocol
MAX_SPREAD = 0.20  # spread of lm's per-round ratio to rtb's median, (max - min) / min


def log(text: str) -> None:
    print(text, file=sys.stderr, flush=True)


def robot_file(relative: str) -> Path:
    hits = glob.glob(f"{sys.prefix}/**/example-robot-data/robots/{relative}", recursive=True)
    if not hits:
        sys.exit("error: example-robot-data is not installed\n  hint: pip install example-robot-data")
    return Path(hits[0])


def load_robot(name: str, corpus: Path) -> tuple[Any, Any] | None:
    """(URDF root element, chain) of a benchmark arm, or None (with a message) when its files are absent."""
    from armtool.model.chain import chain_from_xml
    from armtool.model.load import load_robot_xml

    robot = ROBOTS[name]
    if robot.source == "corpus":
        path = corpus / robot.relative
        if not path.is_file():
            log(f"warning: {name} skipped: {path} not found (the real-repository corpus; pass --corpus DIR)")
            return None
        root = load_robot_xml(path, robot.xacro_args, [corpus])
    else:
        path = robot_file(robot.relative)
        root = load_robot_xml(path)
    return root, chain_from_xml(root, robot.base, robot.tip, source=path.name)


def spread(values: Sequence[float]) -> float | None:
    """(max − min) / min of per-round values; None with fewer than two rounds."""
    return (max(values) - min(values)) / min(values) if len(values) > 1 and min(values) > 0 else None


@dataclass(frozen=True)
class Row:
    """One solver on one robot: medians over rounds."""

    label: str
    batch: bool
    samples: int
    success: float  # %
    median_us: float
    p95_us: float
    cpu_median_us: float  # process CPU time per solve: what a loaded machine does not stretch
    solves_per_s: float
    over_timeout: int | None  # solves slower than the timeout (None for batched rows)
    failures: int  # median over rounds
    stalled: int | None  # failures with < timeout/2 of process CPU in >= timeout of wall (None for batched rows)
    round_medians_us: tuple[float, ...]  # per round: the spread shows how noisy the machine was
    solutions: float | None = None  # closed-form rows: distinct verified solutions per target
    missing: int | None = None  # closed-form rows: the other closed-form solvers' solutions it lacks (median)
    round_solves_per_s: tuple[float, ...] = ()


def summarize(label: str, batch: bool, reports: Sequence[Any], timeout: float) -> Row:
    med = statistics.median
    over = None if batch else int(med([sum(t > timeout * 1e6 for t in r.wall_times_us) for r in reports]))
    stall = None if batch else int(med([r.stalled_failures or 0 for r in reports]))
    solutions = None if reports[0].distinct_solutions is None else med([r.distinct_solutions for r in reports])
    missing = None if reports[0].missing_solutions is None else int(med([r.missing_solutions for r in reports]))
    return Row(
        label,
        batch,
        reports[0].samples,
        100.0 * med([r.success_rate for r in reports]),
        med([r.wall_us["median"] for r in reports]),
        med([r.wall_us["p95"] for r in reports]),
        med([r.cpu_us["median"] for r in reports]),
        med([r.solves_per_s for r in reports]),
        over,
        int(med([r.failures for r in reports])),
        stall,
        tuple(r.wall_us["median"] for r in reports),
        solutions,
        missing,
        tuple(r.solves_per_s for r in reports),
    )


def interleaved_round(
    entries: Sequence[Any], targets: Any, args: argparse.Namespace, round_index: int
) -> dict[str, Any]:
    """One round (armtool.ik.bench.time_interleaved: the solvers take turns block by block, the
    batch calls spread over the round, the order rotated by the round's index too)."""
    from armtool.ik.bench import time_interleaved

    gc.collect()
    return time_interleaved(entries, targets, args.block, rotate=round_index, batch_calls=args.batch_calls)


def bench_robot(name: str, args: argparse.Namespace) -> tuple[str, dict[str, Row], dict[str, str]] | None:
    """(title, rows by label, {solver: why it cannot take the arm}) for one arm; None when its files are absent."""
    from armtool.errors import ArmtoolError
    from armtool.ik.bench import (
        BenchConfig,
        Entry,
        compare_solutions,
        first,
        make_targets,
        native_stderr_note,
        solver_report,
        warm_up,
    )
    from armtool.ik.peers import make_peer
    from armtool.ik.registry import make_solver, solver_names

    loaded = load_robot(name, args.corpus)
    if loaded is None:
        return None
    root, chain = loaded
    config = BenchConfig(samples=args.samples, timeout=args.timeout, tolerance=TOLERANCE, repeat=0)
    targets = make_targets(chain, config)

    entries: list[Any] = []
    not_applicable: dict[str, str] = {}
    for solver_name in solver_names():
        if args.solvers and solver_name not in args.solvers:
            continue
        try:
            solver = make_solver(solver_name, chain, timeout=args.timeout, tolerance=TOLERANCE)
        except ArmtoolError as exc:  # e.g. analytic: no closed form for this arm
            log(f"  {name}: {solver_name} skipped: {exc.what}")
            not_applicable[solver_name] = exc.what
            continue
        entries.append(Entry(solver))
        if solver.has_batch():
            entries.append(Entry(solver, batch=True))
    for peer_name in args.peers:
        try:
            peer = make_peer(peer_name, chain, root, timeout=args.timeout, tolerance=TOLERANCE)
        except ArmtoolError as exc:  # e.g. EAIK: 7 joints, or no decomposition
            log(f"  {name}: {peer_name} not applicable: {exc.what}")
            not_applicable[peer_name] = exc.what
            continue
        if isinstance(peer, str):
            log(f"warning: peer {peer_name} skipped: {peer}")
            continue
        entries.append(Entry(peer, limit=args.ikpy_samples if peer_name == "ikpy" else None))
        if peer.has_batch():
            entries.append(Entry(peer, batch=True))

    for entry in entries:
        if not entry.batch:
            warm_up(chain, entry.solver)  # the first calls of its code paths, on targets of their own
    if args.warmup:  # an untimed pass of every solver first: round 1 then runs in the state of rounds 2 and 3
        k = min(args.warmup, args.samples)
        for entry in entries:
            log(f"  {name} warm-up: {entry.label}")
            if entry.batch:
                entry.solver.solve_batch(targets.poses[:k], targets.seeds[:k])
            elif entry.limit is None:
                for pose, seed in zip(targets.poses[:k], targets.seeds[:k]):
                    entry.solver.solve(pose, seed)
    reports: dict[str, list[Any]] = {entry.label: [] for entry in entries}
    for r in range(args.rounds):
        log(f"  {name} round {r + 1}/{args.rounds}: " + ", ".join(e.label for e in entries) + " (taking turns)")
        timed = interleaved_round(entries, targets, args, r)
        made = [solver_report(chain, e.solver, first(targets, e.limit), config, timed[e.label]) for e in entries]
        compare_solutions(chain, made)
        for entry, report in zip(entries, made):
            reports[entry.label].append(report)
    rows = {e.label: summarize(e.label, e.batch, reports[e.label], args.timeout) for e in entries}
    for solver in {id(e.solver): e.solver for e in entries}.values():  # what native code printed, held back
        note = native_stderr_note(solver)
        if note:
            log(f"  {name}: note: {note}")
    return f"{name} ({chain.base} → {chain.tip}, {chain.n} joints)", rows, not_applicable


def ratio(a: float, b: float | None) -> str:
    return "-" if b is None or not b > 0 else f"{a / b:.2f}×"


def round_ratios(row: Row, reference: Row | None) -> list[float]:
    """The row's median over the reference's, round by round (both timed in turns in each round)."""
    if reference is None:
        return []
    return [a / b for a, b in zip(row.round_medians_us, reference.round_medians_us) if b > 0]


def us(value: float) -> str:
    """Microseconds: one decimal below 100 (closed forms take a few), whole above."""
    return f"{value:.1f}" if value < 100 else f"{value:,.0f}"


def print_table(title: str, rows: dict[str, Row], not_applicable: dict[str, str] | None = None) -> None:
    from armtool.ik.bench import TIMING

    tracik, rtb, eaik = rows.get("pytracik"), rows.get("rtb-lm"), rows.get("eaik")
    print(f"### {title}\n")
    print(
        "| solver | N | success % | failures (stalled) | median µs | p95 µs | CPU median µs | solves/s | > timeout "
        "| solutions | missing | median vs pytracik | median vs rtb-lm | CPU median vs rtb-lm | solves/s vs rtb-lm "
        "| median vs eaik |"
    )
    print("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|")
    for row in rows.values():
        over = "-" if row.over_timeout is None else str(row.over_timeout)
        fails = str(row.failures) + ("" if row.stalled is None else f" ({row.stalled})")
        sols = "-" if row.solutions is None else f"{row.solutions:.2f}"
        lacks = "-" if row.missing is None else str(row.missing)
        print(
            f"| {row.label} | {row.samples} | {row.success:.1f} | {fails} | {us(row.median_us)} | {us(row.p95_us)} | {us(row.cpu_median_us)} | "
            f"{row.solves_per_s:,.0f} | {over} | {sols} | {lacks} | {ratio(row.median_us, tracik.median_us if tracik else None)} | "
            f"{ratio(row.median_us, rtb.median_us if rtb else None)} | {ratio(row.cpu_median_us, rtb.cpu_median_us if rtb else None)} | "
            f"{ratio(row.solves_per_s, rtb.solves_per_s if rtb else None)} | {ratio(row.median_us, eaik.median_us if eaik else None)} |"
        )
    for solver in not_applicable or {}:
        print(f"| {solver} | - | n/a |" + " - |" * 13)
    print(f"\nTiming: {TIMING}.")
    for solver, why in (not_applicable or {}).items():
        print(f"{solver} n/a: {why}")
    shown = [
        row for row in rows.values() if row.label in ("lm", "lm (batch)", "pytracik", "rtb-lm", "analytic", "eaik")
    ]
    if any(len(row.round_medians_us) > 1 for row in shown):
        parts = [row.label + " " + ", ".join(f"{t:,.0f}" for t in row.round_medians_us) for row in shown]
        print("Median µs per round: " + "; ".join(parts))
    lm = rows.get("lm")
    if lm is not None and rtb is not None:
        print("lm / rtb-lm median, per round: " + ", ".join(f"{r:.2f}×" for r in round_ratios(lm, rtb)))
    analytic = rows.get("analytic")
    if analytic is not None and eaik is not None:
        print("analytic / eaik median, per round: " + ", ".join(f"{r:.2f}×" for r in round_ratios(analytic, eaik)))
    print()


def checks(robot: str, rows: dict[str, Row]) -> list[tuple[str, str]]:
    """(PASS | FAIL | SKIP, text) for the IK-speed issue's targets on one robot."""
    out: list[tuple[str, str]] = []

    def check(ok: bool | None, text: str) -> None:
        out.append(("SKIP" if ok is None else "PASS" if ok else "FAIL", f"{robot}: {text}"))

    lm, batch, tracik, rtb = rows.get("lm"), rows.get("lm (batch)"), rows.get("pytracik"), rows.get("rtb-lm")
    if lm is None or batch is None:
        check(None, "lm is not available")
        return out + closed_form_checks(robot, rows)
    stall_note = f"; {lm.stalled} of {lm.failures} failures stalled by the machine" if lm.stalled else ""
    check(lm.success >= 99.9, f"lm success >= 99.9 % ({lm.success:.1f} %{stall_note})")
    if tracik:
        rounds = list(zip(lm.round_medians_us, tracik.round_medians_us))
        check(
            all(a < b for a, b in rounds),
            "lm median below pytracik's in every round ("
            + ", ".join(f"{a:,.0f} vs {b:,.0f}" for a, b in rounds)
            + " µs)",
        )
    else:
        check(None, "lm median below pytracik's (pytracik not installed)")
    if rtb:
        ratios = round_ratios(lm, rtb)
        check(
            all(r <= 1.0 for r in ratios),
            "lm median <= 1.0× rtb ik_LM's in every round (" + ", ".join(f"{r:.2f}×" for r in ratios) + "; "
            f"CPU median {lm.cpu_median_us:,.0f} vs {rtb.cpu_median_us:,.0f} µs, {lm.cpu_median_us / rtb.cpu_median_us:.2f}×)",
        )
        sp = spread(ratios)
        if sp is None:
            check(None, "lm's ratio to rtb ik_LM steady over rounds (needs --rounds 2 or more)")
        else:
            check(
                sp <= MAX_SPREAD,
                f"lm's ratio to rtb ik_LM's median steady over rounds: spread {sp:.0%} <= {MAX_SPREAD:.0%}",
            )
        check(
            batch.solves_per_s >= 3 * rtb.solves_per_s and batch.success >= 99.9,
            f"lm batched >= 3× rtb ik_LM's solves/s at >= 99.9 % success ({batch.solves_per_s:,.0f} vs {rtb.solves_per_s:,.0f}/s, "
            f"{batch.solves_per_s / rtb.solves_per_s:.2f}×; success {batch.success:.1f} %)",
        )
    else:
        check(None, "lm vs rtb ik_LM (roboticstoolbox-python not installed)")
    if robot == "ur5":
        a = rows.get("analytic")
        if a is not None:
            check(
                a.success == 100.0 and a.median_us <= 50,
                f"analytic 100 % with median <= 50 µs ({a.success:.1f} %, {a.median_us:.0f} µs)",
            )
    out += closed_form_checks(robot, rows)
    if robot == "panda":
        kdl = rows.get("kdl-nr-jl")
        if kdl is not None:
            check(
                abs(kdl.success - KDL_PUBLISHED_PANDA) <= 3,
                f"kdl-nr-jl success within 3 points of {KDL_PUBLISHED_PANDA:.0f} % ({kdl.success:.1f} %)",
            )
    return out


MIN_BATCH_VS_EAIK = 5.0  # issue 29: analytic's batch >= 5x EAIK's single-threaded IK_batched


def closed_form_checks(robot: str, rows: dict[str, Row]) -> list[tuple[str, str]]:
    """Issue 29's targets where EAIK solves the arm: analytic's median <= EAIK's in every round, its
    batch >= 5x EAIK's single-threaded batch throughput, no solution of the other closed forms missing."""
    eaik, analytic = rows.get("eaik"), rows.get("analytic")
    if eaik is None or analytic is None:
        return []
    out: list[tuple[str, str]] = []

    def check(ok: bool | None, text: str) -> None:
        out.append(("SKIP" if ok is None else "PASS" if ok else "FAIL", f"{robot}: {text}"))

    rounds = list(zip(analytic.round_medians_us, eaik.round_medians_us))
    check(
        all(a <= b for a, b in rounds),
        "analytic median <= 1.0× EAIK's in every round ("
        + ", ".join(f"{a:.1f} vs {b:.1f} µs, {a / b:.2f}×" for a, b in rounds)
        + ")",
    )
    check(
        analytic.success >= 100.0 and analytic.missing == 0,
        f"analytic solves every target with no solution missing ({analytic.success:.1f} %, "
        f"{analytic.missing} missing, {analytic.solutions:.2f} vs EAIK's {eaik.solutions:.2f} per target)"
        if analytic.solutions is not None and eaik.solutions is not None
        else f"analytic solves every target with no solution missing ({analytic.success:.1f} %)",
    )
    batch, eaik_batch = rows.get("analytic (batch)"), rows.get("eaik (batch)")
    if batch is None or eaik_batch is None:
        check(None, "analytic batch >= 5× EAIK's IK_batched (one of them has no batch row)")
    else:
        per_round = [a / b for a, b in zip(batch.round_solves_per_s, eaik_batch.round_solves_per_s) if b > 0]
        check(
            bool(per_round) and min(per_round) >= MIN_BATCH_VS_EAIK,
            f"analytic batch >= {MIN_BATCH_VS_EAIK:g}× EAIK's single-threaded IK_batched in every round ("
            + ", ".join(f"{r:.2f}×" for r in per_round)
            + ")",
        )
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    parser.add_argument("--samples", type=int, default=1000, help="targets per robot (default 1000)")
    parser.add_argument("--timeout", type=float, default=0.005, help="seconds per solve (default 0.005)")
    parser.add_argument("--robots", default=",".join(ROBOTS), help="comma-separated, from: " + ", ".join(ROBOTS))
    parser.add_argument("--solvers", default="", help="armtool solvers to run, comma-separated (default: all)")
    parser.add_argument(
        "--peers", default=",".join(PEERS), help="peers to run, comma-separated (default: " + ", ".join(PEERS) + ")"
    )
    parser.add_argument(
        "--corpus",
        type=Path,
        default=DEFAULT_CORPUS,
        help="the real-repository corpus (default: ../shared/realworld beside the checkout)",
    )
    parser.add_argument(
        "--ikpy-samples", type=int, default=100, help="targets for ikpy, the first of the same set (default 100)"
    )
    parser.add_argument(
        "--rounds", type=int, default=3, help="run every solver this many times; report medians (default 3)"
    )
    parser.add_argument(
        "--warmup",
        type=int,
        default=100,
        help="untimed solves per solver on the first targets before round 1, 0 for none (default 100)",
    )
    parser.add_argument(
        "--block",
        type=int,
        default=50,
        help="targets per block: the solvers take turns block by block within each round (default 50)",
    )
    parser.add_argument(
        "--batch-calls",
        type=int,
        default=4,
        help="lm's batch calls per round, spread over its blocks; the row shows their mean (default 4)",
    )
    parser.add_argument("--strict", action="store_true", help="exit 1 when a target is missed")
    args = parser.parse_args()
    robots = [r.strip() for r in args.robots.split(",") if r.strip()]
    args.solvers = [s.strip() for s in args.solvers.split(",") if s.strip()]
    args.peers = list(dict.fromkeys(p.strip() for p in args.peers.split(",") if p.strip()))  # each once
    unknown = [r for r in robots if r not in ROBOTS] + [p for p in args.peers if p not in PEERS]
    if (
        unknown
        or args.samples < 1
        or args.rounds < 1
        or args.block < 1
        or args.batch_calls < 1
        or args.ikpy_samples < 1
        or args.warmup < 0
        or not args.timeout > 0
    ):
        parser.error(
            f"robots must be among {', '.join(ROBOTS)}, peers among {', '.join(PEERS)}; --samples, --rounds, --block, --batch-calls, --ikpy-samples >= 1; --warmup >= 0; --timeout > 0"
        )

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(
        f"armtool IK benchmark: {args.samples} targets per robot (ikpy {min(args.ikpy_samples, args.samples)}), seed mid-range, "
        f"timeout {args.timeout * 1e3:g} ms, tolerance {TOLERANCE:g}, {args.rounds} round(s), medians over rounds; "
        f"Python {platform.python_version()}, {os.cpu_count()} CPUs, load average {load:.1f} at start\n"
    )
    results: list[tuple[str, str]] = []
    for robot in robots:
        done = bench_robot(robot, args)
        if done is None:
            results.append(("SKIP", f"{robot}: not benchmarked (files absent)"))
            continue
        title, rows, not_applicable = done
        print_table(title, rows, not_applicable)
        results += checks(robot, rows)
        sys.stdout.flush()
    print("Targets of the IK-speed issue (medians of the rounds, same process as the peers):")
    for verdict, text in results:
        print(f"  {verdict}  {text}")
    if hasattr(os, "getloadavg"):
        print(f"\n(load average {os.getloadavg()[0]:.1f} at the end: timings are noisy when it exceeds the CPU count)")
    failed = any(verdict == "FAIL" for verdict, _ in results)
    return 1 if failed and args.strict else 0


if __name__ == "__main__":
    sys.exit(main())
