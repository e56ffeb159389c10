"""`analytic`: closed-form IK for 6R arms, detected from the chain's geometry; every solution, no code generation.

Families (armtool.ik.closed_form.families, checked on the joint axes at q = 0): EAIK's 6R
spherical-wrist classes — axes 4, 5, 6 meeting in one point, and the first three axes with 1∥2,
2∥3, 1 and 2 intersecting, 2 and 3 intersecting, or in general position (IK-Geo's subproblem 5,
a quartic) — and the UR-type (axes 2∥3∥4, axes 5 and 6 intersecting: UR3/5/10/e, Unitree Z1),
each also with the chain reversed (the wrist or the UR-type triple at the base end). A 7-DOF arm
is solved at a given value of one joint: `Chain.locked({"panda_joint7": 0.3})` folds it into the
chain, and a Franka Panda locked at any of joints 4 to 7 is one of these families. Up to 8
solutions.

How. IK-Geo's decomposition (Elias & Wen 2022), as EAIK runs it: the target's wrist centre (or
the point where axes 5 and 6 meet) leaves a position problem for θ1..θ3 (UR-type: θ1, then θ5,
θ2 + θ3 + θ4, θ6, the planar elbow), solved by the family's chain of Paden–Kahan subproblems
(`closed_form/subproblems.py`), then the wrist's orientation. Compiled with Numba
(`closed_form/kernel.py`): one call solves one target (`call`) or a whole batch (`call_batch`).
Near a wrist singularity θ5 comes from 1 ∓ cos(θ5 − φ) written as products of sines, not acos
(~1e-15 rad instead of ~1e-8), and θ6 from a vector normal to axis 6, so it absorbs what θ4
cannot fix there. At a singularity the free angle comes from the seed: θ4 of a spherical wrist;
θ6 of a UR-type arm if the elbow can then reach, else the nearest θ6 it can. A wrist centre on
axis 1 leaves θ1 to the seed. Two roots of a position angle closer than 1e-5 rad (elbow
stretched, wrist centre on its reach cylinder) are merged, at a second-order cost (≤ 5e-11 m per metre).

Near-closed-form arms. When a family's conditions hold only within NEAR_TOL (Kinova Gen3 6-DOF:
axis 6 misses the 4,5 intersection by 0.35 mm), the family's model (the chain's axes with the
structure made exact) solves, each of its answers gets up to POLISH_STEPS Newton steps (6×6
Jacobian of the real chain, Pinocchio) and is checked with the chain's own FK. `polished` says a
solver takes that path; an exact arm never does, and keeps its exact solutions.

Solutions. One representation per geometric solution: each revolute angle is moved by a
multiple of 2π to the value nearest the seed's (continuous joints too), then by whole turns into
the limits if that one is outside; a solution with a joint that cannot be placed within its
limits is dropped. UR joints with ±2π limits therefore give at most 8 solutions, not 8·2⁵: add
±2π to a joint yourself for its other in-limit representation. `solutions` holds every one that
passes the in-call FK check, at least as strict as `verify()`: each position component within the
tolerance, and two columns of R_target − R within a bound that caps the rotation angle, hence
every component of log(R_target·Rᵀ), at the tolerance. That check runs compiled, by the chain's
Denavit–Hartenberg model (checked against the chain's FK to 1e-9 when the solver is built) from
the cosines and sines the solve already has. They are sorted by Euclidean distance to the seed;
`q` is the first, claimed iff there is one (`verify()` then judges it outside the solve, as
every solver's answer); `iterations` is 0.

Timing (the `call` that ik-bench times does the whole solve; `prepare` converts the target and
the seed to contiguous arrays and allocates the output buffer, as KDL's JntArray result):
measured by benchmarks/ik_closed_form.py beside EAIK, see docs/ik-bench.md.

Throughput: `all_solutions(targets, seeds)` returns arrays (counts, every solution) from one
compiled call over the batch, on one thread; `solve_batch` builds an IKResult per target and
judges each first answer with armtool's FK on top. An exact arm's batch runs on the vectorized
lanes (`closed_form/lanes.py`; the special cases on the kernel) in every family but the spherical
wrist with the first three axes in general position (SP5's quartic), which stays on the kernel.
Compiled on first use and cached by Numba: the kernel when the solver is built (59 s measured here
at load 6, 2 s to load from the cache), a family's lanes at its first batch (52-81 s per family at
load 4-6, 0.1 s from the cache); each first compile is logged as a warning.
"""

from __future__ import annotations

import logging
import math
import os
import time
from typing import Any, ClassVar, NoReturn

import numpy as np
from numpy.typing import NDArray

from armtool.errors import ArmtoolError
from armtool.ik.closed_form import kernel, lanes
from armtool.ik.closed_form.families import Geometry, detect, dh_checkable, pack
from armtool.ik.solver import Answer, Array, Solver
from armtool.model.chain import Chain

log = logging.getLogger(__name__)

POLISH_STEPS = 12  # Newton steps per closed-form candidate on the real chain (2.5 on average on Gen3 6-DOF)
NEAR_DUPLICATE = 1e-7  # rad: two polished answers this close are one solution
TAU = 2.0 * math.pi

Raw = Array  # kernel.solve_one's out vector (see kernel's docstring)


class Analytic(Solver):
    name = "analytic"
    summary = "closed form (subproblem decomposition) for UR-type and spherical-wrist 6R arms, the wrist at either end (detected from the URDF; near ones polished by Newton): every solution"
    options: ClassVar[dict[str, Any]] = {}
    position_only_capable: ClassVar[bool] = False
    returns_all_solutions: ClassVar[bool] = True
    # The compiled module that solves (closed_form/kernel.py; `search` runs closed_form/search.py,
    # whose output has the kernel's layout) and what its answers are called in failure reasons.
    _entry: ClassVar[Any] = kernel
    _what: ClassVar[str] = "closed form"

    def __init__(
        self, chain: Chain, timeout: float = 0.005, tolerance: float = 1e-5, seed: int | None = 0, **options: Any
    ) -> None:
        super().__init__(chain, timeout=timeout, tolerance=tolerance, seed=seed, **options)
        try:
            self.geometry: Geometry = detect(chain)
        except ArmtoolError as none:
            raise ArmtoolError(none.what, none.where, _other_way(chain) or none.hint) from None
        self._model = pack(self.geometry, chain, self.tolerance)
        # The in-call check runs on the chain's DH model; where that model is not the chain (a
        # near-closed-form arm, or DH frames that lose digits), the answers are checked here instead.
        self._checked_here = self.geometry.near or not dh_checkable(chain, self.geometry)
        if self._checked_here:
            self._model[kernel.CHECK] = 0.0
        self._set_limits()
        # The batch runs on the vectorized lanes where they cover the family (exact models, checked in call).
        family = int(self._model[kernel.FAMILY])
        self._lanes = family if family in lanes.FAMILIES and not self._checked_here else None
        self._lanes_ready = False
        self._batch_out: Raw = kernel.empty_out(0)  # all_solutions' output buffer, kept for the next batch
        g = self.geometry
        self.method = f"closed form: {g.title}" + (
            f"; nearest closed-form model (off the chain by {g.model_error:.1e}) + Newton polish" if g.near else ""
        )
        self._load_kernel()

    def _set_limits(self) -> None:
        lo = [-math.inf if c else float(v) for v, c in zip(self.chain.lower, self.chain.continuous)]
        hi = [math.inf if c else float(v) for v, c in zip(self.chain.upper, self.chain.continuous)]
        self._limits = tuple(zip(lo, hi))
        self._rot_tol2 = 4.0 * math.sin(self.tolerance / 2.0) ** 2

    @property
    def polished(self) -> bool:
        """Whether answers come from the nearest closed-form model polished by Newton steps (a near arm)."""
        return self.geometry.near

    def _load_kernel(self) -> None:
        """Call both compiled entry points (and the batch's gather) once, so that loading (or, on the
        very first run, compiling) their machine code happens here, not inside a solve."""
        entry = self._entry
        on_disk = compiled_on_disk(entry.solve_one)
        if on_disk is False:
            log.warning(
                f"compiling {self.name}'s kernel with Numba (once: ~20-60 s; later runs load it from its cache)"
            )
        start = time.perf_counter()
        target = np.ascontiguousarray(self.chain.fk(self.chain.mid()))
        mid = self.chain.mid()
        entry.solve_one(self._model, target, mid, kernel.empty_out())
        out = kernel.empty_out(1)
        entry.solve_many(self._model, target[None], mid[None], out)
        kernel.gather_solutions(out, np.empty(1, dtype=np.int64), np.empty((1, kernel.MAX_SOLUTIONS, 6)))
        log.debug(
            f"{self.name}'s kernel ready in %.2f s (compiled on disk before: %s)", time.perf_counter() - start, on_disk
        )

    def _load_lanes(self) -> None:
        """Load (on the very first run: compile) the family's batch lanes, on the first batch only:
        single calls never need them."""
        assert self._lanes is not None
        if compiled_on_disk(lanes.LOOPS[self._lanes]) is False:
            log.warning(
                "compiling analytic's batch lanes for this family with Numba (once: ~1-2 min; later runs load them from its cache)"
            )
        start = time.perf_counter()
        target = np.ascontiguousarray(self.chain.fk(self.chain.mid()))[None]
        lanes.solve(self._lanes, self._model, target, self.chain.mid()[None], kernel.empty_out(1))
        self._lanes_ready = True
        took = time.perf_counter() - start
        (log.info if took > 1.0 else log.debug)("analytic's batch lanes ready in %.2f s (%s)", took, self.geometry.name)

    # ---- one target -----------------------------------------------------------------------------
    def prepare(self, target: Array, seed: Array) -> tuple[Array, Array, Raw]:
        """The target and seed as contiguous float arrays, and the output buffer (as KDL's result
        JntArray): a conversion only, `call` checks them."""
        return np.ascontiguousarray(target, dtype=float), np.ascontiguousarray(seed, dtype=float), kernel.empty_out()

    def call(self, prepared: tuple[Array, Array, Raw]) -> Raw:
        """The whole solve, compiled: every solution placed, checked and sorted into `out` (see
        closed_form/kernel.py); a near arm's answers then polished and checked (`_finish`)."""
        target, seed, out = prepared
        try:
            status = self._entry.solve_one(self._model, target, seed, out)
        except TypeError:  # Numba found no compiled version for these arguments: not 2-D and 1-D floats
            status = kernel.BAD_INPUT
        if status == kernel.BAD_INPUT:
            self._refuse(target, seed)
        if self._checked_here:
            self._finish(out, target, seed)
        return out

    def answer(self, raw: Raw) -> Answer:
        count = int(raw[0])
        if count:
            rows = raw[kernel.OUT_HEAD : kernel.OUT_HEAD + kernel.ROW * count].reshape(count, kernel.ROW)
            solutions = tuple(row[:6].copy() for row in rows)
            return Answer(solutions[0], True, 0, "", solutions)
        candidates, in_limits = int(raw[1]), int(raw[2])
        if not candidates:
            why = f"out of reach: the {self._what} has no real solution"
        elif not in_limits:
            why = f"{candidates} solution(s) of the {self._what}, none within the joint limits"
        else:
            why = f"{in_limits} solution(s) of the {self._what} within the limits, none passed the FK check (tolerance {self.tolerance:g})"
        seed = raw[kernel.SEED : kernel.SEED + 6]
        return Answer(self.chain.clamp(seed.copy()), False, 0, why)

    def _refuse(self, target: Array, seed: Array) -> NoReturn:
        if seed.shape != (6,) or not np.all(np.isfinite(seed)):
            raise ArmtoolError(
                f"seed must be 6 finite joint values, got {np.asarray(seed).tolist()}",
                hint="pass a configuration of the chain, e.g. chain.mid()",
            )
        raise ArmtoolError(
            f"target must be a finite 4x4 pose, got shape {np.shape(target)}"
            + ("" if np.shape(target) != (4, 4) else " with a NaN or an infinity"),
            hint="a homogeneous transform of the tip in the base frame",
        )

    # ---- many targets ---------------------------------------------------------------------------
    def prepare_batch(self, targets: Array, seeds: Array) -> tuple[Array, Array, Raw]:
        """Contiguous arrays and the output buffer (and, the first time, the lanes' machine code loaded)."""
        targets, seeds = self._contiguous_batch(targets, seeds)
        return targets, seeds, kernel.empty_out(len(targets))

    def _contiguous_batch(self, targets: Array, seeds: Array) -> tuple[Array, Array]:
        targets, seeds = self._batch_arrays(targets, seeds)
        if self._lanes is not None and not self._lanes_ready:
            self._load_lanes()
        return np.ascontiguousarray(targets), np.ascontiguousarray(seeds)

    def call_batch(self, prepared: tuple[Array, Array, Raw]) -> Raw:
        """Every target's solve in one compiled call (one thread); rows of `out` as `call`'s. The lanes
        (closed_form/lanes.py) where they cover the family, the general kernel otherwise and for a
        target the lanes leave to it."""
        targets, seeds, out = prepared
        if self._lanes is not None:
            status = lanes.solve(self._lanes, self._model, targets, seeds, out)
        else:
            status = self._entry.solve_many(self._model, targets, seeds, out)
        if status == kernel.BAD_INPUT:
            bad = int(np.flatnonzero(out[:, 3] == kernel.BAD_INPUT)[0]) if len(out) else 0
            self._refuse(targets[bad], seeds[bad])
        if self._checked_here:
            for row, target, seed in zip(out, targets, seeds):
                self._finish(row, target, seed)
        return out

    def answer_batch(self, raw: Raw) -> list[Answer]:
        return [self.answer(row) for row in raw]

    def all_solutions(self, targets: Array, seeds: Array) -> tuple[NDArray[np.int64], Array]:
        """Every solution of every target, as arrays: counts (N,) and Q (N, MAX_SOLUTIONS, 6), each target's
        solutions nearest its seed first (rows past its count are NaN). The throughput call: one
        compiled call over the batch, one thread, every solution checked as `call`'s. Its output
        buffer is kept for the next call (a fresh 1 MB per 1000 targets costs its page faults, ~0.1 µs
        per target, measured here), as the answers are copied out of it."""
        targets, seeds = self._contiguous_batch(targets, seeds)
        if len(self._batch_out) < len(targets):
            self._batch_out = kernel.empty_out(len(targets))
        out = self.call_batch((targets, seeds, self._batch_out[: len(targets)]))
        counts = np.empty(len(out), dtype=np.int64)
        Q = np.empty((len(out), kernel.MAX_SOLUTIONS, 6))
        kernel.gather_solutions(out, counts, Q)
        return counts, Q

    # ---- answers checked (and near ones polished) here ---------------------------------------------
    def _finish(self, out: Raw, target: Array, seed: Array) -> None:
        """The kernel's unchecked candidates in `out` polished (near arms), placed within the strict
        limits and checked with the chain's own FK; written back into `out` nearest the seed first."""
        count = int(out[0])
        rows = out[kernel.OUT_HEAD : kernel.OUT_HEAD + kernel.ROW * count].reshape(count, kernel.ROW)
        qs = [tuple(row[:6].tolist()) for row in rows]
        if self.polished:
            qs = self._polish(qs, target)
        sd = seed.tolist()
        tol, rot_tol2 = self.tolerance, self._rot_tol2
        (t00, t01, _, tx), (t10, t11, _, ty), (t20, t21, _, tz), _ = target.tolist()
        found: list[tuple[float, Array]] = []
        in_limits = 0
        for q in qs:
            fitted = _into_limits(q, self._limits)
            if fitted is None:
                continue
            in_limits += 1
            qa = np.array(fitted)
            (m00, m01, _, x), (m10, m11, _, y), (m20, m21, _, z), _ = self.chain.fk(qa).tolist()
            if not (abs(tx - x) <= tol and abs(ty - y) <= tol and abs(tz - z) <= tol):
                continue
            u = (t00 - m00, t10 - m10, t20 - m20, t01 - m01, t11 - m11, t21 - m21)
            if sum(v * v for v in u) > rot_tol2:
                continue
            if any(float(np.abs(qa - other).max()) <= NEAR_DUPLICATE for _, other in found):
                continue
            found.append((sum((a - b) ** 2 for a, b in zip(fitted, sd)), qa))
        found.sort(key=lambda item: item[0])
        out[0], out[2] = len(found), in_limits
        for k, (dist, qa) in enumerate(found):
            row = kernel.OUT_HEAD + kernel.ROW * k
            out[row : row + 6] = qa
            out[row + 6] = dist

    def _polish(self, qs: list[tuple[float, ...]], target: Array) -> list[tuple[float, ...]]:
        """Newton steps on the real chain from a near-closed-form model's answers (Pinocchio's 6×6 Jacobian,
        full steps; one candidate at a time: 2.8× faster than numpy over all of them, measured on Gen3)."""
        pin, model, data, frame = self.chain._model()
        jacobian, place, log3, world = (
            pin.computeFrameJacobian,
            pin.updateFramePlacement,
            pin.log3,
            pin.LOCAL_WORLD_ALIGNED,
        )
        solve, goal = np.linalg.solve, 0.1 * self.tolerance
        R_t, p_t = target[:3, :3], target[:3, 3]
        out = []
        for q in qs:
            qa = np.array(q)
            for _ in range(POLISH_STEPS):
                J = jacobian(model, data, qa, frame, world)
                M = place(model, data, frame)
                e = np.concatenate([p_t - M.translation, log3(R_t @ M.rotation.T)])
                err = float(np.abs(e).max())
                # Done, or lost. A full step near a stretched elbow may first raise the error (0.2 from
                # 2e-4, measured on Gen3) and still converge quadratically after: no line search.
                if err <= goal or not err < 1.0:
                    break
                try:
                    qa = qa + solve(J, e)
                except np.linalg.LinAlgError:  # singular: least squares
                    qa = qa + np.linalg.lstsq(J, e, rcond=None)[0]
            out.append(tuple(qa.tolist()))
        return out


def _other_way(chain: Chain) -> str:
    """The hint for an arm with no closed form that the 1-D search takes (solvers/search.py)."""
    from armtool.ik.closed_form import search

    try:
        search.plan(chain)
    except ArmtoolError:
        return ""
    return "every solution by a 1-D search: `--solvers search` (Python: make_solver('search', chain)); or an iterative solver such as lm"


def _into_limits(q: tuple[float, ...], limits: tuple[tuple[float, float], ...]) -> tuple[float, ...] | None:
    """q with each angle moved by whole turns into its limits (clamped within 1e-9), or None."""
    out = []
    for v, (lo, hi) in zip(q, limits):
        if not lo - 1e-9 <= v <= hi + 1e-9:
            if v < lo:
                v += TAU * math.ceil((lo - v) / TAU)
            elif v > hi:
                v -= TAU * math.ceil((v - hi) / TAU)
            if not lo - 1e-9 <= v <= hi + 1e-9:  # also NaN
                return None
        out.append(min(max(v, lo), hi))
    return tuple(out)


def compiled_on_disk(function: Any) -> bool | None:
    """Whether Numba's cache holds a compiled function's machine code (None: this Numba does not say)."""
    try:
        index: str = getattr(function, "_cache")._cache_file._index_path  # noqa: B009 (private to Numba)
    except AttributeError:
        return None
    return os.path.exists(index)
