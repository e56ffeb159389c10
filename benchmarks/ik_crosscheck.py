"""A cross-check of `benchmarks/ik_bench.py` that shares none of its timing or checking code.

Each solver's raw call is timed with `time.perf_counter` around that call alone: armtool's `lm`
through `solver.call` (its own check of its inputs included) on inputs converted beforehand
(`solver.prepare`), roboticstoolbox's C++ `ETS.ik_LM` and TRAC-IK's `pytracik.ik` directly, with the
settings and the input form of armtool's adapters (`RtbLM.ILIMIT`, `SLIMIT` and its tolerance;
`PyTracIK.prepare`'s position and quaternion, computed beforehand), so that the two cannot drift
apart. The answer is each call's own raw output; nothing of armtool reads it inside the timing.
Answers are checked
afterwards by Pinocchio's own model of the whole URDF (`pin.buildModelFromXML`, the tip's frame
relative to the base's), not by armtool's chain: every component of [Δp; log(R* Rᵀ)] within 1e-5
and every joint within the URDF's limits. The solvers take turns on blocks of 50 targets (the
order rotating), as the CPU's speed may change during a run. TRAC-IK's protocol: targets are FK of
uniform random configurations, every solve from the mid-range seed, 5 ms timeout for the solvers
that have one, tolerance 1e-5.

One run prints, per arm: each solver's median µs and success %, and lm's median over rtb's and
over TRAC-IK's. Run it three times to see how steady the ratios are.

    python benchmarks/ik_crosscheck.py [--robots panda,ur5,xarm6,xarm7,kinova,so101] [--samples 1000]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ik_bench  # the arms' files and chains only

TOLERANCE = 1e-5
TIMEOUT = 0.005
BLOCK = 50


class IndependentCheck:
    """Pinocchio's own model of the URDF: the tip's pose in the base frame, and the joint limits."""

    def __init__(self, root: Any, chain: Any) -> None:
        import pinocchio as pin
        from lxml import etree

        self.pin = pin
        self.model = pin.buildModelFromXML(etree.tostring(root, encoding="unicode"))
        self.data = self.model.createData()
        self.base = self.model.getFrameId(chain.base)
        self.tip = self.model.getFrameId(chain.tip)
        joints = [self.model.joints[self.model.getJointId(name)] for name in chain.joint_names]
        self.index = [j.idx_q for j in joints]
        self.unbounded = [j.nq == 2 for j in joints]  # continuous: Pinocchio's q is (cos θ, sin θ)
        self.q = pin.neutral(self.model)

    def ok(self, q: np.ndarray, target: np.ndarray) -> bool:
        pin, model, data = self.pin, self.model, self.data
        if not np.all(np.isfinite(q)):
            return False
        full = self.q.copy()
        for value, i, unbounded in zip(q.tolist(), self.index, self.unbounded):
            if unbounded:
                full[i], full[i + 1] = np.cos(value), np.sin(value)
            elif not model.lowerPositionLimit[i] - 1e-9 <= value <= model.upperPositionLimit[i] + 1e-9:
                return False
            else:
                full[i] = value
        pin.framesForwardKinematics(model, data, full)
        pose = data.oMf[self.base].inverse() * data.oMf[self.tip]
        e = np.concatenate([target[:3, 3] - pose.translation, pin.log3(target[:3, :3] @ pose.rotation.T)])
        return bool(np.abs(e).max() <= TOLERANCE)


def callers(root: Any, chain: Any, targets: np.ndarray, seed: np.ndarray) -> dict[str, Any]:
    """Per solver: a function of the target index that makes the raw call and returns its raw output."""
    from armtool.ik.peers import make_peer
    from armtool.ik.registry import make_solver

    lm = make_solver("lm", chain, timeout=TIMEOUT, tolerance=TOLERANCE)
    lm_inputs = [lm.prepare(t, seed) for t in targets]  # contiguous arrays only: lm checks them in its call
    out: dict[str, Any] = {"lm": lambda i: lm.call(lm_inputs[i])}
    rtb = make_peer("rtb-lm", chain, root, timeout=TIMEOUT, tolerance=TOLERANCE)
    if not isinstance(rtb, str):
        ets, tol = rtb._ets, rtb._tol  # type: ignore[attr-defined]
        ilimit, slimit = type(rtb).ILIMIT, type(rtb).SLIMIT  # type: ignore[attr-defined]
        out["rtb-lm"] = lambda i: ets.ik_LM(
            targets[i], q0=seed, ilimit=ilimit, slimit=slimit, tol=tol, joint_limits=True
        )
    trac = make_peer("pytracik", chain, root, timeout=TIMEOUT, tolerance=TOLERANCE)
    if not isinstance(trac, str):
        ik, handle = trac._ik, trac._solver  # type: ignore[attr-defined]
        args = [trac.prepare(t, seed) for t in targets]  # (seed, x, y, z, quaternion x, y, z, w)
        out["pytracik"] = lambda i: ik(handle, *args[i])
    return out


def answer_q(label: str, chain: Any, raw: Any) -> np.ndarray:
    """q from a call's raw output (untimed): lm's out vector, rtb's IKSolution, pytracik's [rc, q...]."""
    if label == "lm":
        from armtool.ik.solvers.lm_kernel import OUT_HEAD

        return np.asarray(raw[OUT_HEAD : OUT_HEAD + chain.n], dtype=float)
    if label == "rtb-lm":
        return np.asarray(raw.q, dtype=float)
    return np.asarray(raw, dtype=float)[1:]


def run_arm(name: str, samples: int, corpus: Path) -> dict[str, tuple[float, float]] | None:
    loaded = ik_bench.load_robot(name, corpus)
    if loaded is None:
        return None
    root, chain = loaded
    check = IndependentCheck(root, chain)
    rng = np.random.default_rng(11)
    targets = np.ascontiguousarray(chain.fk_batch(chain.random(rng, samples)))
    seed = chain.mid()
    calls = callers(root, chain, targets, seed)
    for f in calls.values():  # untimed first calls (no solver here keeps anything per target)
        for i in range(min(100, samples)):
            f(i)
    times: dict[str, list[float]] = {label: [] for label in calls}
    answers: dict[str, list[Any]] = {label: [None] * samples for label in calls}
    labels = list(calls)
    for k, start in enumerate(range(0, samples, BLOCK)):
        for label in labels[k % len(labels) :] + labels[: k % len(labels)]:
            f = calls[label]
            for i in range(start, min(start + BLOCK, samples)):
                t0 = time.perf_counter()
                raw = f(i)
                times[label].append(time.perf_counter() - t0)
                answers[label][i] = raw
    return {
        label: (
            statistics.median(times[label]) * 1e6,
            100.0
            * sum(check.ok(answer_q(label, chain, raw), targets[i]) for i, raw in enumerate(answers[label]))
            / samples,
        )
        for label in calls
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    parser.add_argument("--robots", default=",".join(ik_bench.ROBOTS))
    parser.add_argument("--samples", type=int, default=1000)
    parser.add_argument("--corpus", type=Path, default=ik_bench.DEFAULT_CORPUS)
    args = parser.parse_args()
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"IK cross-check: {args.samples} targets per arm, {os.cpu_count()} CPUs, load average {load:.1f} at start\n")
    print("| arm | lm µs (success %) | rtb-lm µs (success %) | pytracik µs (success %) | lm / rtb-lm | lm / pytracik |")
    print("|---|---|---|---|---|---|")
    for name in [r.strip() for r in args.robots.split(",") if r.strip()]:
        res = run_arm(name, args.samples, args.corpus)
        if res is None:
            continue
        cells = [f"{res[k][0]:.1f} ({res[k][1]:.1f})" if k in res else "-" for k in ("lm", "rtb-lm", "pytracik")]
        ratios = [f"{res['lm'][0] / res[k][0]:.2f}" if k in res else "-" for k in ("rtb-lm", "pytracik")]
        print(f"| {name} | " + " | ".join(cells + ratios) + " |")
        sys.stdout.flush()
    if hasattr(os, "getloadavg"):
        print(f"\n(load average {os.getloadavg()[0]:.1f} at the end)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
