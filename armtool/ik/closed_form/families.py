"""Which closed-form family a 6R chain belongs to, and its model as the compiled solve reads it.

The families are EAIK's 6R spherical-wrist classes and today's UR-type (kernel.py names them), each
also with the chain reversed (the spherical wrist, or the UR-type triple, at the base end: a
Franka Panda with joint 7 locked has its three intersecting axes at the shoulder). The conditions
are checked on the chain's own axis lines at q = 0 (`geometry.axis_lines`), in this order:

| family | conditions (on the chain, or on it reversed) |
|---|---|
| UR-type | axes 2∥3∥4, distinct; axes 5, 6 intersect; axis 1 ∦ 2, axis 4 ∦ 5 |
| spherical wrist, axes 1∥2 | axes 4, 5, 6 meet in one point; axes 1∥2, 2 ∦ 3 |
| spherical wrist, axes 2∥3 | the wrist; axes 2∥3, distinct; 1 ∦ 2; the wrist centre off axis 3 |
| spherical wrist, axes 1, 2 intersect | the wrist; axes 1 and 2 intersect |
| spherical wrist, axes 2, 3 intersect | the wrist; axes 2 and 3 intersect |
| spherical wrist, general first three | the wrist (SP5: a quartic) |

A family's model is the chain's lines with its structure made exact ("snapped": a parallel axis
given exactly the other's direction, intersecting axes both through the midpoint of their common
normal, axis 6 through the 4, 5 intersection). Exact chains (EXACT_TOL, and a model within
MODEL_TOL of the chain's FK) keep their exact solutions; chains that fit only within NEAR_TOL
(Kinova Gen3 6-DOF: axis 6 misses the wrist centre by 0.35 mm) get the model's solutions, which
`analytic` polishes by Newton steps on the real chain.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np

from armtool.errors import ArmtoolError
from armtool.ik.closed_form import kernel as K
from armtool.ik.closed_form.geometry import (
    DHJoint,
    Line,
    angle_deg,
    any_normal,
    axis_lines,
    closest,
    denavit_hartenberg,
    distance,
    model_error,
    parallel,
)
from armtool.ik.solver import Array
from armtool.model.chain import Chain, looks_like_gripper_joint

EXACT_TOL = 1e-9  # rad / m: axes parallel, lines intersecting (EAIK 1.2's AXIS_INTERSECT_THRESHOLD)
MODEL_TOL = 1e-9  # max FK difference (m, or rotation-matrix entry) between an exact family's model and the chain
NEAR_TOL = 1e-3  # rad / m: a chain this close to a family is solved on its model and polished
NEAR_MODEL_TOL = 1e-2  # max FK difference of a near model: beyond it Newton would start too far away
ROOT_TOL = 1e-10  # a cosine beyond ±1 by less than this is rounding: the double root is taken
NEAR_OVER = 1e-2  # near model: cosines beyond ±1 by up to this are clamped (the chain may reach what the model misses)
DOUBLE_ROOT = 0.5e-10  # = (1e-5 rad)²/2: position roots closer than 1e-5 rad merge (a second-order error)
NEAR_LIMIT_MARGIN = 0.02  # rad: near-model answers this far outside a limit are still polished (they may end inside)

Kind = Literal["ur", "spherical-wrist"]
# code: (kind, EAIK's class name, the family in words)
FAMILIES: dict[int, tuple[Kind, str, str]] = {
    K.UR: ("ur", "THREE_INNER_PARALLEL", "UR-type (axes 2∥3∥4, axes 5, 6 intersecting)"),
    K.WRIST_12_PARALLEL: ("spherical-wrist", "SPHERICAL_FIRST_TWO_PARALLEL", "spherical wrist, axes 1∥2"),
    K.WRIST_23_PARALLEL: ("spherical-wrist", "SPHERICAL_SECOND_TWO_PARALLEL", "spherical wrist, axes 2∥3"),
    K.WRIST_12_INTERSECTING: (
        "spherical-wrist",
        "SPHERICAL_FIRST_TWO_INTERSECTING",
        "spherical wrist, axes 1, 2 intersecting",
    ),
    K.WRIST_23_INTERSECTING: (
        "spherical-wrist",
        "SPHERICAL_SECOND_TWO_INTERSECTING",
        "spherical wrist, axes 2, 3 intersecting",
    ),
    K.WRIST_GENERAL: (
        "spherical-wrist",
        "SPHERICAL_NO_PARALLEL_NO_INTERSECTING",
        "spherical wrist, first three axes general (SP5)",
    ),
}


@dataclass(frozen=True)
class Geometry:
    """What detection found: the family, its model, and the chain's DH model (the in-call check's FK)."""

    kind: Kind
    code: int  # kernel.UR, kernel.WRIST_…
    reversed: bool  # solved on the reversed chain (the wrist or the UR-type triple at the base end)
    lines: tuple[Line, ...]  # the family's model: the chain's axis lines with its structure snapped, chain order
    tip0: Array  # the tip's pose at q = 0
    joints: tuple[DHJoint, ...]  # the chain's DH model (6); the last is Rz(θ6) alone
    base: Array  # B: DH frame 0 in the chain's base frame
    tool: Array  # E: the chain's tip in DH frame 6
    model_error: float  # max |FK_model − FK_chain| entry over random configurations
    near: bool = False  # the chain is this family only within NEAR_TOL: answers are polished on the real chain

    @property
    def name(self) -> str:
        """EAIK's name for the family (its kinematic class)."""
        return FAMILIES[self.code][1]

    @property
    def title(self) -> str:
        words = FAMILIES[self.code][2]
        return f"{words}, solved reversed (from the tip)" if self.reversed else words


# ---- conditions ----------------------------------------------------------------------------------------

Condition = tuple[str, bool, str]  # label, holds, measured value


class _Axes:
    """The conditions on six axis lines (numbered 1..6 here; `label` maps them to the chain's numbers)."""

    def __init__(self, lines: list[Line], tol: float, label: Callable[[int], int]) -> None:
        self.lines, self.tol, self.label = lines, tol, label
        self.w = [d for _, d in lines]

    def _pair(self, i: int, j: int) -> str:
        a, b = sorted((self.label(i), self.label(j)))
        return f"{a},{b}"

    def par(self, i: int, j: int) -> Condition:
        a, b = sorted((self.label(i), self.label(j)))
        w1, w2 = self.w[i - 1], self.w[j - 1]
        return f"axis {a}∥{b}", parallel(w1, w2, self.tol), f"{angle_deg(w1, w2):.3g}°"

    def nonpar(self, i: int, j: int) -> Condition:
        a, b = sorted((self.label(i), self.label(j)))
        w1, w2 = self.w[i - 1], self.w[j - 1]
        return f"axis {a}∦{b}", not parallel(w1, w2, self.tol), f"{angle_deg(w1, w2):.3g}°"

    def meet(self, i: int, j: int) -> Condition:
        dist = distance(self.lines[i - 1], self.lines[j - 1], self.tol)
        ok = not parallel(self.w[i - 1], self.w[j - 1], self.tol) and dist < self.tol
        return f"axes {self._pair(i, j)} intersect", ok, f"{dist:.3g} m apart"

    def apart(self, i: int, j: int) -> Condition:
        dist = distance(self.lines[i - 1], self.lines[j - 1], self.tol)
        return f"axes {self._pair(i, j)} distinct", dist > self.tol, f"{dist:.3g} m apart"

    def meeting_point(self, i: int, j: int) -> Array:
        c1, c2 = closest(self.lines[i - 1][0], self.w[i - 1], self.lines[j - 1][0], self.w[j - 1], self.tol)
        return (c1 + c2) / 2.0

    def through(self, k: int, point: Array, what: str) -> Condition:
        p, w = self.lines[k - 1]
        off = float(np.linalg.norm(np.cross(point - p, w)))
        return f"axis {self.label(k)} through the {what}", off < self.tol, f"{off:.3g} m off"

    def wrist(self) -> list[Condition]:
        found = [self.meet(4, 5)]
        if found[0][1]:
            a, b = sorted((self.label(4), self.label(5)))
            found.append(self.through(6, self.meeting_point(4, 5), f"{a},{b} intersection"))
        return found


def conditions(lines: list[Line], code: int, tol: float, reverse: bool = False) -> list[Condition]:
    """The family's conditions on the chain's lines (reversed: on the chain read from the tip), each checked."""
    axes = _Axes(lines[::-1] if reverse else lines, tol, (lambda i: 7 - i) if reverse else (lambda i: i))
    if code == K.UR:
        return [
            axes.par(2, 3),
            axes.par(3, 4),
            axes.apart(2, 3),
            axes.apart(3, 4),
            axes.nonpar(1, 2),
            axes.meet(5, 6),
            axes.nonpar(4, 5),
        ]
    wrist = axes.wrist()
    if code == K.WRIST_12_PARALLEL:
        return wrist + [axes.par(1, 2), axes.nonpar(2, 3)]
    if code == K.WRIST_23_PARALLEL:
        first3 = [axes.nonpar(1, 2), axes.par(2, 3), axes.apart(2, 3)]
        if wrist[0][1]:
            centre = axes.meeting_point(4, 5)
            dist3 = float(np.linalg.norm(np.cross(centre - axes.lines[2][0], axes.w[2])))
            first3.append(("wrist centre off axis 3", dist3 > tol, f"{dist3:.3g} m"))
        return wrist + first3
    if code == K.WRIST_12_INTERSECTING:
        return wrist + [axes.meet(1, 2)]
    if code == K.WRIST_23_INTERSECTING:
        return wrist + [axes.meet(2, 3)]
    return wrist


def _snapped(lines: list[Line], code: int, tol: float) -> list[Line]:
    """The lines (solver order) with the family's structure made exact."""
    axes = _Axes(lines, tol, lambda i: i)
    pts = [p.copy() for p, _ in lines]
    dirs = [d.copy() for _, d in lines]

    def same_direction(i: int, j: int) -> None:  # axis j given axis i's direction exactly
        dirs[j - 1] = dirs[i - 1] * (1.0 if float(dirs[i - 1] @ dirs[j - 1]) > 0 else -1.0)

    def through(point: Array, *ks: int) -> None:
        for k in ks:
            pts[k - 1] = point

    if code == K.UR:
        same_direction(2, 3)
        same_direction(2, 4)
        through(axes.meeting_point(5, 6), 5, 6)
        return list(zip(pts, dirs))
    through(axes.meeting_point(4, 5), 4, 5, 6)
    if code == K.WRIST_12_PARALLEL:
        same_direction(1, 2)
    elif code == K.WRIST_23_PARALLEL:
        same_direction(2, 3)
    elif code == K.WRIST_12_INTERSECTING:
        through(axes.meeting_point(1, 2), 1, 2)
    elif code == K.WRIST_23_INTERSECTING:
        through(axes.meeting_point(2, 3), 2, 3)
    return list(zip(pts, dirs))


def lines_fk(lines: list[Line] | tuple[Line, ...], tip0: Array, Q: Array) -> Array:
    """(N,4,4) poses of the product of rotations about the lines (by q_i, at q = 0 as given) times tip0."""
    N = Q.shape[0]
    T = np.broadcast_to(np.eye(4), (N, 4, 4)).copy()
    for i, (p, w) in enumerate(lines):
        K_ = np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])
        s, c = np.sin(Q[:, i])[:, None, None], np.cos(Q[:, i])[:, None, None]
        R = np.eye(3) + s * K_ + (1.0 - c) * (K_ @ K_)
        M = np.broadcast_to(np.eye(4), (N, 4, 4)).copy()
        M[:, :3, :3] = R
        M[:, :3, 3] = p - R @ p
        T = T @ M
    poses: Array = T @ tip0
    return poses


def _lines_error(chain: Chain, lines: list[Line], tip0: Array) -> float:
    rng = np.random.default_rng(0)
    Q = np.vstack([np.zeros(6), rng.uniform(-math.pi, math.pi, size=(24, 6))])
    return float(np.abs(lines_fk(lines, tip0, Q) - chain.fk_batch(Q)).max())


ORDER = (
    K.UR,
    K.WRIST_12_PARALLEL,
    K.WRIST_23_PARALLEL,
    K.WRIST_12_INTERSECTING,
    K.WRIST_23_INTERSECTING,
    K.WRIST_GENERAL,
)


def _fit(
    chain: Chain, lines: list[Line], tip0: Array, tol: float, limit: float
) -> tuple[int, bool, list[Line], float] | None:
    """The first family (in ORDER, the chain read from its base, then from its tip) whose conditions
    hold within tol and whose snapped model is within limit of the chain: (code, reversed, model lines in
    chain order, model error)."""
    for reverse in (False, True):
        for code in ORDER:
            if not all(ok for _, ok, _ in conditions(lines, code, tol, reverse)):
                continue
            model = _snapped(lines[::-1] if reverse else lines, code, tol)
            if reverse:
                model = model[::-1]
            error = _lines_error(chain, model, tip0)
            if error <= limit:
                return code, reverse, model, error
    return None


def detect(chain: Chain) -> Geometry:
    """The closed-form family of a chain and its model, or ArmtoolError naming what was checked."""
    need = "closed form needs 6R with a spherical wrist or three parallel axes (UR-type), at either end of the chain"
    hint = "use a numerical solver such as lm (`--solvers lm`)"
    where = f"{chain.base} → {chain.tip}"
    if chain.n != 6:
        extra = chain.joint_names[6:]
        if extra and all(looks_like_gripper_joint(name) for name in extra):
            hint = f"joints {', '.join(extra)} look like a gripper's: end the chain before them (--tip); else {hint}"
        elif chain.n == 7:
            hint = f"lock one joint to solve the other six in closed form (--lock JOINT=VALUE in ik-bench and traj cartesian, Chain.locked in Python); else {hint}"
        raise ArmtoolError(f"the chain has {chain.n} joints; {need}", where=where, hint=hint)
    prismatic = [j.name for j in chain.joints if j.kind == "prismatic"]
    if prismatic:
        raise ArmtoolError(f"the chain's joint '{prismatic[0]}' is prismatic; {need}", where=where, hint=hint)
    lines, tip0 = axis_lines(chain)
    joints, base, tool = denavit_hartenberg(lines, tip0, EXACT_TOL, EXACT_TOL)
    for tol, limit, near in ((EXACT_TOL, MODEL_TOL, False), (NEAR_TOL, NEAR_MODEL_TOL, True)):
        fit = _fit(chain, lines, tip0, tol, limit)
        if fit is not None:
            code, reverse, model, error = fit
            kind = FAMILIES[code][0]
            return Geometry(kind, code, reverse, tuple(model), tip0, joints, base, tool, error, near)
    failed = "; ".join(
        f"{title}: "
        + ", ".join(
            f"{label}: no ({value})" for label, ok, value in conditions(lines, code, EXACT_TOL, reverse) if not ok
        )
        for title, code, reverse in (
            ("UR-type", K.UR, False),
            ("spherical wrist", K.WRIST_GENERAL, False),
            ("UR-type from the tip", K.UR, True),
            ("spherical wrist at the base", K.WRIST_GENERAL, True),
        )
    )
    raise ArmtoolError(
        f"the chain (6R) has no supported closed form, not even within {NEAR_TOL:g} rad / {NEAR_TOL:g} m; {need}: {failed}",
        where=where,
        hint=hint,
    )


# ---- the kernel's model ------------------------------------------------------------------------------------


def reversed_lines(lines: list[Line] | tuple[Line, ...], tip0: Array) -> tuple[list[Line], Array]:
    """The chain read from its tip: T(q)⁻¹ = Π_{i=6..1} R(−M⁻¹·line_i, q_i) · M⁻¹ with M = tip0 (the same q)."""
    inv = np.asarray(np.linalg.inv(tip0), dtype=np.float64)
    R, t = inv[:3, :3], inv[:3, 3]
    return [(R @ p + t, -(R @ w)) for p, w in reversed(lines)], inv


def pack(geometry: Geometry, chain: Chain, tolerance: float) -> Array:
    """The model array kernel.solve_one reads (its layout: kernel's constants)."""
    g = geometry
    m = np.zeros(K.MODEL_SIZE)
    lines, tip = reversed_lines(g.lines, g.tip0) if g.reversed else (list(g.lines), g.tip0)
    h = [w / np.linalg.norm(w) for _, w in lines]
    axes = _Axes(lines, NEAR_TOL if g.near else EXACT_TOL, lambda i: i)
    pts = [p for p, _ in lines]
    if g.kind == "spherical-wrist":
        pts[3] = pts[4] = pts[5] = axes.meeting_point(4, 5)
        if g.code == K.WRIST_12_INTERSECTING:
            pts[0] = pts[1] = axes.meeting_point(1, 2)
        elif g.code == K.WRIST_23_INTERSECTING:
            pts[1] = pts[2] = axes.meeting_point(2, 3)
    else:
        pts[4] = pts[5] = axes.meeting_point(5, 6)
    P = [pts[0]] + [pts[i] - pts[i - 1] for i in range(1, 6)] + [tip[:3, 3] - pts[5]]
    m[K.FAMILY], m[K.REVERSED], m[K.CHECK] = g.code, float(g.reversed), 0.0 if g.near else 1.0
    m[K.OVER], m[K.FLAT] = NEAR_OVER if g.near else ROOT_TOL, DOUBLE_ROOT
    m[K.TOL], m[K.ROT_TOL2] = tolerance, 4.0 * math.sin(tolerance / 2.0) ** 2
    m[K.H : K.H + 18] = np.concatenate(h)
    m[K.P : K.P + 21] = np.concatenate(P)
    m[K.R6T : K.R6T + 9] = tip[:3, :3].reshape(9)
    m[K.N6 : K.N6 + 3] = any_normal(h[5])
    m[K.N2 : K.N2 + 3] = any_normal(h[1])
    margin = NEAR_LIMIT_MARGIN if g.near else 0.0
    m[K.LO : K.LO + 6] = np.where(chain.continuous, -math.inf, chain.lower - margin)
    m[K.HI : K.HI + 6] = np.where(chain.continuous, math.inf, chain.upper + margin)
    m[K.DH_BASE : K.DH_BASE + 9] = g.base[:3, :3].reshape(9)
    m[K.DH_BASE + 9 : K.DH_BASE + 12] = g.base[:3, 3]
    for i, j in enumerate(g.joints):
        m[K.DH_JOINTS + 7 * i : K.DH_JOINTS + 7 * i + 7] = (
            j.sign,
            math.cos(j.offset),
            math.sin(j.offset),
            j.d,
            j.a,
            math.cos(j.alpha),
            math.sin(j.alpha),
        )
    m[K.DH_TOOL : K.DH_TOOL + 9] = g.tool[:3, :3].reshape(9)
    m[K.DH_TOOL + 9 : K.DH_TOOL + 12] = g.tool[:3, 3]
    if g.code == K.UR:
        m[K.CONST : K.CONST + 3] = (float(h[1] @ (P[1] + P[2] + P[3] + P[4])), float(h[2] @ h[1]), float(h[3] @ h[1]))
    elif g.code == K.WRIST_23_PARALLEL:
        m[K.CONST] = float(h[1] @ (P[1] + P[2] + P[3]))
    elif g.code == K.WRIST_12_PARALLEL:
        m[K.CONST] = float(h[0] @ (P[1] + P[2]))
    return m


def dh_checkable(chain: Chain, geometry: Geometry) -> bool:
    """Whether the chain's DH model (the in-call check's FK) is within MODEL_TOL of the chain."""
    return model_error(chain, geometry.joints, geometry.base, geometry.tool) <= MODEL_TOL
