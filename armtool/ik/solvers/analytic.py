"""`analytic`: closed-form IK for 6R arms, detected from the chain's geometry; every solution, no code generation.

Supported geometries (checked on the joint axes at q = 0, as lines in the base frame, with
ANGLE_TOL / LENGTH_TOL):

* UR-type, "three parallel axes": axes 2, 3, 4 parallel (two distinct links between them),
  axes 5 and 6 intersect, axis 1 not parallel to 2, axis 5 parallel to neither 4 nor 6.
  UR3/5/10/e and Unitree Z1 (whose wrist has an offset between axes 4 and 5). Up to 8 solutions.
* Spherical wrist: axes 4, 5, 6 meet in one point (the wrist centre), axes 2 and 3 parallel,
  axis 1 not parallel to 2 (the "elbow manipulator": PUMA, Kinova Jaco j2s6s, ABB/KUKA/Fanuc-style
  arms with shoulder and elbow offsets). Up to 8 solutions. Other first-three-joint geometries
  have no closed form here and are rejected, never approximated.

How. The six axis lines are turned into Denavit–Hartenberg frames by their common normals
(frame i-1 on axis i; along parallel axes the normal through the previous origin, so d2 = d3 = 0).
Axis signs, joint-zero offsets (θ_i = sign_i·q_i + offset_i), the base frame B and the tool
transform E are measured from the chain, never assumed: FK(q) = B·A1(θ1)…A5(θ5)·Rz(θ6)·E,
A_i = Rz(θ)·Tz(d)·Tx(a)·Rx(α). The model is checked against the chain's FK at random
configurations when the solver is built. A target T becomes T' = B⁻¹·T·E⁻¹ (frame 6 in frame 0).

UR-type: the point P where axes 5 and 6 meet keeps a constant offset along the parallel
direction u = z1 (z1·(P − o1) = d4 + d5·cos α4): one sinusoid in θ1, 2 roots. The angle ψ between
u and axis 6 (from w = R'ᵀu) fixes θ5 through cos ψ = cos α4 cos α5 − sin α4 sin α5 cos θ5, 2 roots;
the direction of w in the tool's xy-plane gives θ6; the point on axis 4 and the x-axis of frame 4,
in frame 1, leave a planar 2-link problem for θ2, θ3 (2 roots) and θ4 = θ234 − θ2 − θ3.
Spherical wrist: the wrist centre's offset along z1 gives θ1 (2 roots), its planar distance θ3
(2 roots) and θ2; M = R03ᵀR' = Rz(θ4)Rx(α4)Rz(θ5)Rx(α5)Rz(θ6) gives θ5 from the angle between axes
4 and 6 (2 roots), θ4 from M's third column and θ6 from its third row: the Euler decomposition for
the actual twists α4, α5. θ5 is taken from 1 ∓ cos θ5 written as products of sines, not acos,
which keeps it to ~1e-15 rad near a wrist singularity (acos would lose half the digits).

Near-closed-form arms. When the conditions hold only within NEAR_ANGLE_TOL / NEAR_LENGTH_TOL
(Kinova Gen3 6-DOF: axis 6 misses the 4,5 intersection by 0.35 mm; axes 2/3 off parallel by 7e-6
rad), the DH extraction runs with those tolerances, which snaps the offending offsets and twists
to zero: the nearest model of the family. Each of its solutions then gets up to POLISH_STEPS
Newton steps (6×6 Jacobian of the real chain, Pinocchio) and is checked like any other answer.
An exact arm never takes this path, and keeps its exact solutions.

Degenerate cases. At a wrist singularity (axis 6 ∥ u for UR-type, axis 6 ∥ axis 4 for a
spherical wrist; sine below SINGULAR_TOL) one angle is free: a spherical wrist takes θ4 from the
seed; a UR-type arm takes θ6 from the seed if the elbow can then reach, else the nearest θ6 it
can (turning θ6 there moves the point on axis 4 on a circle). Close to a spherical-wrist
singularity θ6 is solved from θ4 rather than on its own, so their rounding cannot add up. The
point P on axis 1 leaves θ1 to the seed. Two roots of θ1 or θ3 closer than 1e-5 rad (elbow
stretched, P on its reach cylinder) are merged, at a second-order cost (≤ 5e-11 m per metre).

Solutions. One representation per geometric solution: each revolute angle is moved by a
multiple of 2π to the value nearest the seed's (continuous joints too), then by whole turns into
the limits if that one is outside; a solution with a joint that cannot be placed within its
limits is dropped. UR joints with ±2π limits therefore give at most 8 solutions, not 8·2⁵: add
±2π to a joint yourself for its other in-limit representation. `solutions` holds every one that
passes an FK check with the chain's own FK (Pinocchio) at least as strict as `verify()`: each
position component within the tolerance, and two columns of R_target − R within a bound that
caps the rotation angle, hence every component of log(R_target·Rᵀ), at the tolerance. They are
sorted by Euclidean distance to the seed; `q` is the first, claimed iff there is one (`verify()`
then judges it outside the solve, as every solver's answer); `iterations` is 0. This check
costs ~2 µs per solution where `verify()` costs ~20 µs: a whole solve on UR5 takes ~42 µs (median,
7.1 solutions on average), a third of it in the FK checks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np

from armtool.errors import ArmtoolError
from armtool.ik.solver import Answer, Array, Solver
from armtool.model.chain import Chain, looks_like_gripper_joint

ANGLE_TOL = 1e-6  # rad: axes parallel
LENGTH_TOL = 1e-6  # m: lines intersect, offsets vanish
ROOT_TOL = 1e-10  # |cos| or |sin| beyond 1 by less than this is rounding: clamp
SINGULAR_TOL = 1e-11  # sine of a wrist angle below this: the angle it would fix is free (pose error ≤ π·1e-11)
NEAR_SINGULAR = 1e-4  # spherical wrist closer than this to a singularity: θ6 from θ4, not independently
MODEL_TOL = 1e-9  # max FK difference (m, or rotation-matrix entry) between the DH model and the chain
# Near-closed-form arms (Kinova Gen3 6-DOF: axis 6 misses the wrist centre by 0.35 mm, axes 2/3 off parallel
# by 7e-6 rad): the nearest model with the conditions snapped solves, Newton steps on the real chain polish.
NEAR_ANGLE_TOL = 1e-3  # rad
NEAR_LENGTH_TOL = 1e-3  # m
NEAR_MODEL_TOL = 1e-2  # max FK difference of the snapped model: beyond it Newton would start too far away
NEAR_OVER = 1e-2  # near model: cosines beyond ±1 by up to this are clamped (the chain may reach what the model misses)
NEAR_LIMIT_MARGIN = 0.02  # rad: near-model answers this far outside a limit are still polished (they may end inside)
POLISH_STEPS = 12  # Newton steps per closed-form candidate on the real chain (2.5 on average on Gen3 6-DOF)
DOUBLE_ROOT = 0.5e-10  # = (1e-5 rad)²/2: merge roots ±b of θ1 and θ3 closer than 1e-5 rad
TAU = 2.0 * math.pi

GeometryKind = Literal["ur", "spherical-wrist"]
_TITLES: dict[GeometryKind, str] = {"ur": "UR-type", "spherical-wrist": "spherical wrist"}


@dataclass(frozen=True)
class DHJoint:
    """One Denavit–Hartenberg link: A = Rz(θ)·Tz(d)·Tx(a)·Rx(α), with θ = sign·q + offset."""

    sign: float
    offset: float
    d: float
    a: float
    alpha: float


@dataclass(frozen=True)
class Geometry:
    """What detection found: the family, the DH model of the chain and its error against the chain's FK."""

    kind: GeometryKind
    joints: tuple[DHJoint, ...]  # 6; the last is Rz(θ6) alone (d = a = α = 0)
    base: Array  # B: frame 0 in the chain's base frame
    tool: Array  # E: the chain's tip in frame 6
    model_error: float  # max |FK_dh − FK_chain| entry over random configurations
    near: bool = False  # the chain is this family only within NEAR_*_TOL: answers are polished on the real chain


# ---- geometry --------------------------------------------------------------------------------------------


def axis_lines(chain: Chain) -> tuple[list[tuple[Array, Array]], Array]:
    """Each joint axis at q = 0 as (point, unit direction) in the base frame, and the tip pose at q = 0."""
    T = np.eye(4)
    lines = []
    for joint in chain.joints:
        T = T @ joint.origin
        lines.append((T[:3, 3].copy(), T[:3, :3] @ joint.axis))
    return lines, T @ chain.tip_offset


def _parallel(w1: Array, w2: Array, angle_tol: float = ANGLE_TOL) -> bool:
    return float(np.linalg.norm(np.cross(w1, w2))) < angle_tol


def _angle_deg(w1: Array, w2: Array) -> float:
    return math.degrees(math.atan2(float(np.linalg.norm(np.cross(w1, w2))), abs(float(w1 @ w2))))


def _closest(p1: Array, w1: Array, p2: Array, w2: Array, angle_tol: float = ANGLE_TOL) -> tuple[Array, Array]:
    """Closest points of two lines (for parallel lines: p1 and its foot on line 2)."""
    r = p1 - p2
    b, e, f = float(w1 @ w2), float(w1 @ r), float(w2 @ r)
    den = 1.0 - b * b
    t = 0.0 if den < angle_tol**2 else (b * f - e) / den
    return p1 + t * w1, p2 + (f + t * b) * w2


def _distance(l1: tuple[Array, Array], l2: tuple[Array, Array], angle_tol: float = ANGLE_TOL) -> float:
    c1, c2 = _closest(l1[0], l1[1], l2[0], l2[1], angle_tol)
    return float(np.linalg.norm(c2 - c1))


def _checks(
    lines: list[tuple[Array, Array]], angle_tol: float = ANGLE_TOL, length_tol: float = LENGTH_TOL
) -> dict[GeometryKind, list[tuple[str, bool, str]]]:
    """Per family, the conditions checked: (label, holds, measured value)."""
    w = [d for _, d in lines]

    def par(i: int, j: int) -> tuple[str, bool, str]:
        return f"axis {i}∥{j}", _parallel(w[i - 1], w[j - 1], angle_tol), f"{_angle_deg(w[i - 1], w[j - 1]):.3g}°"

    def nonpar(i: int, j: int) -> tuple[str, bool, str]:
        return f"axis {i}∦{j}", not _parallel(w[i - 1], w[j - 1], angle_tol), f"{_angle_deg(w[i - 1], w[j - 1]):.3g}°"

    def meet(i: int, j: int) -> tuple[str, bool, str]:
        dist = _distance(lines[i - 1], lines[j - 1], angle_tol)
        ok = not _parallel(w[i - 1], w[j - 1], angle_tol) and dist < length_tol
        return f"axes {i},{j} intersect", ok, f"{dist:.3g} m apart"

    def apart(i: int, j: int) -> tuple[str, bool, str]:
        dist = _distance(lines[i - 1], lines[j - 1], angle_tol)
        return f"axes {i},{j} distinct", dist > length_tol, f"{dist:.3g} m apart"

    ur = [par(2, 3), par(3, 4), apart(2, 3), apart(3, 4), nonpar(1, 2), meet(5, 6), nonpar(4, 5)]
    wrist = [meet(4, 5), meet(5, 6)]
    if wrist[0][1]:
        c4, c5 = _closest(lines[3][0], w[3], lines[4][0], w[4], angle_tol)
        centre = (c4 + c5) / 2
        foot = lines[5][0] + float((centre - lines[5][0]) @ w[5]) * w[5]
        off = float(np.linalg.norm(centre - foot))
        wrist.append(("axis 6 through the 4,5 intersection", off < length_tol, f"{off:.3g} m off"))
        dist3 = float(np.linalg.norm(np.cross(centre - lines[2][0], w[2])))
        first3 = [
            nonpar(1, 2),
            par(2, 3),
            apart(2, 3),
            ("wrist centre off axis 3", dist3 > length_tol, f"{dist3:.3g} m"),
        ]
    else:
        first3 = [nonpar(1, 2), par(2, 3), apart(2, 3)]
    return {"ur": ur, "spherical-wrist": wrist + first3}


def detect(chain: Chain) -> Geometry:
    """The closed-form family of a chain and its DH model, or ArmtoolError naming what was checked."""
    need = "closed form needs 6R with a spherical wrist or three parallel axes (UR-type)"
    hint = "use a numerical solver such as lm (`--solvers lm`)"
    where = f"{chain.base} → {chain.tip}"
    if chain.n != 6:
        extra = chain.joint_names[6:]
        if extra and all(looks_like_gripper_joint(name) for name in extra):
            hint = f"joints {', '.join(extra)} look like a gripper's: end the chain before them (--tip); else {hint}"
        raise ArmtoolError(f"the chain has {chain.n} joints; {need}", where=where, hint=hint)
    prismatic = [j.name for j in chain.joints if j.kind == "prismatic"]
    if prismatic:
        raise ArmtoolError(f"the chain's joint '{prismatic[0]}' is prismatic; {need}", where=where, hint=hint)
    lines, tip0 = axis_lines(chain)
    checks = _checks(lines)
    kinds: tuple[GeometryKind, ...] = ("ur", "spherical-wrist")
    for kind in kinds:  # exact: the model is the chain
        if all(ok for _, ok, _ in checks[kind]):
            joints, base, tool = _denavit_hartenberg(lines, tip0)
            error = _model_error(chain, joints, base, tool)
            if error <= MODEL_TOL:
                return Geometry(kind, joints, base, tool, error)
    near_checks = _checks(lines, NEAR_ANGLE_TOL, NEAR_LENGTH_TOL)
    for kind in kinds:  # near: the nearest model of the family, answers polished on the chain
        if all(ok for _, ok, _ in near_checks[kind]):
            joints, base, tool = _denavit_hartenberg(lines, tip0, NEAR_ANGLE_TOL, NEAR_LENGTH_TOL)
            error = _model_error(chain, joints, base, tool)
            if error <= NEAR_MODEL_TOL:
                return Geometry(kind, joints, base, tool, error, near=True)
    failed = "; ".join(
        f"{_TITLES[kind]}: " + ", ".join(f"{label}: no ({value})" for label, ok, value in checks[kind] if not ok)
        for kind in kinds
    )
    raise ArmtoolError(
        f"the chain (6R) has no supported closed form, not even within {NEAR_ANGLE_TOL:g} rad / {NEAR_LENGTH_TOL:g} m; {need}: {failed}",
        where=f"{chain.base} → {chain.tip}",
        hint=hint,
    )


def _denavit_hartenberg(
    lines: list[tuple[Array, Array]], tip0: Array, angle_tol: float = ANGLE_TOL, length_tol: float = LENGTH_TOL
) -> tuple[tuple[DHJoint, ...], Array, Array]:
    """DH frames from the axis lines by common normals: joints, base frame B and tool transform E."""
    p1, w1 = lines[0]
    z_prev = w1 / np.linalg.norm(w1)
    o_prev = _closest(p1, z_prev, lines[1][0], lines[1][1], angle_tol)[0]  # so d1 = 0
    origins: list[Array] = [o_prev]
    xs: list[Array] = []
    zs: list[Array] = [z_prev]
    params: list[tuple[float, float, float, float]] = []  # sign, d, a, alpha of joints 1..5
    sign = 1.0
    for p, w in lines[1:]:
        if _parallel(z_prev, w, angle_tol):
            sign_next = 1.0 if float(z_prev @ w) > 0 else -1.0
            z = sign_next * w
            o = p + float((o_prev - p) @ z) * z
            d = 0.0
            v = o - o_prev
        else:
            sign_next = 1.0
            z = w
            c, o = _closest(o_prev, z_prev, p, w, angle_tol)
            d = float((c - o_prev) @ z_prev)
            v = o - c
        a = float(np.linalg.norm(v))
        if a > length_tol:
            x = v / a
        elif not _parallel(z_prev, z, angle_tol):
            x = np.cross(z_prev, z)
            x /= np.linalg.norm(x)
            a = 0.0
        else:
            x = xs[-1] if xs else _any_normal(z_prev)
            a = 0.0
        if abs(d) < length_tol:
            d = 0.0
        alpha = math.atan2(float(np.cross(z_prev, z) @ x), float(z_prev @ z))
        if abs(alpha) < angle_tol:
            alpha = 0.0
        params.append((sign, d, a, alpha))
        xs.append(x)
        origins.append(o)
        zs.append(z)
        o_prev, z_prev, sign = o, z, sign_next
    sign6 = sign
    x0 = xs[0]
    base = np.eye(4)
    base[:3, :3] = np.column_stack([x0, np.cross(zs[0], x0), zs[0]])
    base[:3, 3] = origins[0]
    xs = [x0, *xs]
    joints = []
    for i, (s, d, a, alpha) in enumerate(params):
        offset = math.atan2(float(np.cross(xs[i], xs[i + 1]) @ zs[i]), float(xs[i] @ xs[i + 1]))
        joints.append(DHJoint(s, 0.0 if abs(offset) < 1e-12 else offset, d, a, alpha))
    joints.append(DHJoint(sign6, 0.0, 0.0, 0.0, 0.0))
    zero = _dh_fk(tuple(joints), base, np.eye(4), [0.0] * 6)
    tool = np.asarray(np.linalg.solve(zero, tip0), dtype=np.float64)
    return tuple(joints), base, tool


def _any_normal(z: Array) -> Array:
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x: Array = np.cross(z, helper)
    unit: Array = x / np.linalg.norm(x)  # numpy's stubs: Any for an array divided by a numpy scalar
    return unit


def _dh_fk(joints: tuple[DHJoint, ...], base: Array, tool: Array, q: list[float]) -> Array:
    T: Array = base.copy()
    for j, qi in zip(joints, q):
        th = j.sign * qi + j.offset
        ct, st, ca, sa = math.cos(th), math.sin(th), math.cos(j.alpha), math.sin(j.alpha)
        A: Array = np.array(
            [
                [ct, -st * ca, st * sa, j.a * ct],
                [st, ct * ca, -ct * sa, j.a * st],
                [0.0, sa, ca, j.d],
                [0.0, 0.0, 0.0, 1.0],
            ]
        )
        T = T @ A
    return T @ tool


def _model_error(chain: Chain, joints: tuple[DHJoint, ...], base: Array, tool: Array) -> float:
    rng = np.random.default_rng(0)
    Q = np.vstack([np.zeros(6), rng.uniform(-math.pi, math.pi, size=(24, 6))])
    T_chain = chain.fk_batch(Q)
    return max(float(np.abs(_dh_fk(joints, base, tool, list(q)) - T).max()) for q, T in zip(Q, T_chain))


# ---- solver ------------------------------------------------------------------------------------------------


def _roots_acos(c: float, flat: float = 0.0, over: float = ROOT_TOL) -> tuple[float, ...] | None:
    """Both angles with cosine c, None if |c| > 1 beyond rounding; one root (0 or π) if |c| ≥ 1 − flat.

    A positive `flat` merges the two roots near a double root where that costs only a second-order
    error (elbow stretched, wrist centre on the reach cylinder): flat = b²/2 merges roots ±b.
    """
    if c >= 1.0 - flat:
        return (0.0,) if c < 1.0 + over else None
    if c <= -1.0 + flat:
        return (math.pi,) if c > -1.0 - over else None
    b = math.acos(c)
    return (b, -b)


def _theta5(
    h: float, c: float, half_sum: float, half_diff: float, inv45: float, over: float = ROOT_TOL
) -> float | None:
    """θ5 ≥ 0 from the angle ψ = atan2(h, c) between axis 6 and axis 4 (h, c: its sine and cosine).

    cos ψ = cos α4 cos α5 − sin α4 sin α5 cos θ5. Near a wrist singularity acos(cos θ5) would lose
    half the digits (1e-8 rad from rounding); instead 1 ∓ cos θ5 come as products of sines:
    (1 − cos θ5)·sin α4 sin α5 = cos ψ − cos(α4 + α5), (1 + cos θ5)·sin α4 sin α5 = cos(α4 − α5) − cos ψ.
    """
    half = math.atan2(h, c) / 2.0
    one_minus = -2.0 * math.sin(half + half_sum) * math.sin(half - half_sum) * inv45
    one_plus = -2.0 * math.sin(half_diff + half) * math.sin(half_diff - half) * inv45
    if one_minus < -over or one_plus < -over:
        return None  # this tool direction is beyond what the wrist's twists allow
    return 2.0 * math.atan2(math.sqrt(max(one_minus, 0.0)), math.sqrt(max(one_plus, 0.0)))


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


class Analytic(Solver):
    name = "analytic"
    summary = "closed form for UR-type and spherical-wrist 6R arms (detected from the URDF; near ones polished by Newton): every solution, ~45 µs"
    options: ClassVar[dict[str, Any]] = {}
    position_only_capable: ClassVar[bool] = False

    def __init__(
        self, chain: Chain, timeout: float = 0.005, tolerance: float = 1e-5, seed: int | None = 0, **options: Any
    ) -> None:
        super().__init__(chain, timeout=timeout, tolerance=tolerance, seed=seed, **options)
        self.geometry = detect(chain)
        g = self.geometry
        # T' = B⁻¹·T·E⁻¹ as one product on the row-major entries: vec(A·X·C) = (A ⊗ Cᵀ)·vec(X); top 3 rows only.
        self._to_dh = np.kron(np.linalg.inv(g.base), np.linalg.inv(g.tool).T)[:12].copy()
        # q_i = sign_i·θ_i + k_i (sign = ±1), so θ_i = sign_i·q_i − sign_i·k_i for joints taken from the seed.
        self._gk = tuple((j.sign, -j.sign * j.offset) for j in g.joints)
        lo = [-math.inf if c else float(v) for v, c in zip(chain.lower, chain.continuous)]
        hi = [math.inf if c else float(v) for v, c in zip(chain.upper, chain.continuous)]
        self._limits = tuple(zip(lo, hi))
        self._rot_tol2 = 4.0 * math.sin(self.tolerance / 2.0) ** 2  # bound on two columns of R_t − R, see solve
        # A near model misses the chain by up to model_error: a target the chain just reaches may be just beyond
        # the model's reach (a cosine of 1 + ε). Take the boundary solution then, and let Newton finish.
        self._over = NEAR_OVER if g.near else ROOT_TOL
        self._near_limits = tuple((lo - NEAR_LIMIT_MARGIN, hi + NEAR_LIMIT_MARGIN) for lo, hi in self._limits)
        j1, j2, j3, j4, j5, _ = g.joints
        if g.kind == "ur":
            rx, ry = j3.a, 0.0
            k = j4.d + j5.d * math.cos(j4.alpha)  # offset along z1 from o1 to the point where axes 5 and 6 meet
        else:
            rx, ry = j3.a, -j4.d * math.sin(j3.alpha)  # wrist centre in frame 2, before Rz(θ3)
            k = j3.d + j4.d * math.cos(j3.alpha)  # offset along z1 from o1 to the wrist centre
        rr = math.hypot(rx, ry)
        s4, s5 = math.sin(j4.alpha), math.sin(j5.alpha)
        self._const = (
            math.sin(j1.alpha), math.cos(j1.alpha), j1.a, j1.d, k,
            j2.a, rr, math.atan2(ry, rx), j2.a * j2.a + rr * rr, 1.0 / (2.0 * j2.a * rr),
            math.sin(j3.alpha), math.cos(j3.alpha),
            j4.a, j4.d, s4, math.cos(j4.alpha), j5.d, s5, math.cos(j5.alpha),
            (j4.alpha + j5.alpha) / 2.0, (j4.alpha - j5.alpha) / 2.0, 1.0 / (s4 * s5),
        )  # fmt: skip

    # ---- per target --------------------------------------------------------------------------------------
    def call(self, prepared: tuple[Array, Array]) -> tuple[list[tuple[float, Array]], int, int, Array]:
        """(the solutions that pass, as (squared distance to the seed, q), nearest first; how many
        closed-form solutions were checked (-1: the closed form has none, the target is out of
        reach); how many of those were within the limits; the seed). `answer` reads them."""
        target, seed = prepared
        chain = self.chain
        t = target
        tp = self._to_dh.dot(t.ravel()).tolist()
        sd = np.asarray(seed, dtype=float).tolist()
        if len(sd) != 6 or not math.isfinite(sum(sd)):
            raise ArmtoolError(
                f"seed must be 6 finite joint values, got {sd}",
                hint="pass a configuration of the chain, e.g. chain.mid()",
            )
        qs = self._candidates_ur(tp, sd) if self.geometry.kind == "ur" else self._candidates_wrist(tp, sd)
        if not qs:
            return [], -1, 0, seed
        fk = chain.fk
        tol, rot_tol2, limits = self.tolerance, self._rot_tol2, self._limits
        (lo0, hi0), (lo1, hi1), (lo2, hi2), (lo3, hi3), (lo4, hi4), (lo5, hi5) = limits
        s0, s1, s2, s3, s4, s5 = sd
        (t00, t01, _, tx), (t10, t11, _, ty), (t20, t21, _, tz), _ = t.tolist()
        found: list[tuple[float, Array]] = []
        in_limits = 0
        if self.geometry.near:  # polish only what may end within the limits
            qs = self._polish(
                [near for near in (_into_limits(q, self._near_limits) for q in qs) if near is not None], t
            )
        for q in qs:
            a, b, c, d, e, f = q
            if not (
                lo0 <= a <= hi0
                and lo1 <= b <= hi1
                and lo2 <= c <= hi2
                and lo3 <= d <= hi3
                and lo4 <= e <= hi4
                and lo5 <= f <= hi5
            ):
                fitted = _into_limits(q, limits)
                if fitted is None:
                    continue
                q = fitted
                a, b, c, d, e, f = q
            in_limits += 1
            qa = np.array(q)
            H = fk(qa).tolist()
            (m00, m01, _, x), (m10, m11, _, y), (m20, m21, _, z), _ = H
            if -tol <= tx - x <= tol and -tol <= ty - y <= tol and -tol <= tz - z <= tol:
                # Two columns suffice: ‖ΔR·e0‖² + ‖ΔR·e1‖² ≥ 4 sin²(angle/2) for any rotation error.
                u0, u1, u2, v0, v1, v2 = t00 - m00, t10 - m10, t20 - m20, t01 - m01, t11 - m11, t21 - m21
                if u0 * u0 + u1 * u1 + u2 * u2 + v0 * v0 + v1 * v1 + v2 * v2 <= rot_tol2:
                    u0, u1, u2, v0, v1, v2 = a - s0, b - s1, c - s2, d - s3, e - s4, f - s5
                    found.append((u0 * u0 + u1 * u1 + u2 * u2 + v0 * v0 + v1 * v1 + v2 * v2, qa))
        if not found:
            return found, len(qs), in_limits, seed
        found.sort(key=_first)
        if self.geometry.near:  # two model answers may polish into one solution
            found = [
                item
                for k, item in enumerate(found)
                if all(float(np.abs(item[1] - other[1]).max()) > 1e-7 for other in found[:k])
            ]
        return found, len(qs), in_limits, seed

    def answer(self, raw: tuple[list[tuple[float, Array]], int, int, Array]) -> Answer:
        found, candidates, in_limits, seed = raw
        if found:
            return Answer(found[0][1], True, 0, "", tuple([item[1] for item in found]))
        if candidates < 0:
            why = "out of reach: the closed form has no real solution"
        elif not in_limits:
            why = f"{candidates} closed-form solution(s), none within the joint limits"
        else:
            why = f"{in_limits} closed-form solution(s) within the limits, none passed the FK check (tolerance {self.tolerance:g})"
        return Answer(self.chain.clamp(seed), False, 0, why)

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

    def _theta1(self, px: float, py: float, pz: float, sd0: float) -> tuple[float, ...]:
        """Roots of z1(θ1)·(P − o1(θ1)) = k: sin α1·(s1·px − c1·py) + cos α1·(pz − d1) = k."""
        sa1, ca1, _, d1, k = self._const[:5]
        h = (k - ca1 * (pz - d1)) / sa1
        rho = math.hypot(px, py)
        if rho < SINGULAR_TOL:  # P on axis 1: θ1 free if the offset allows it
            g, off = self._gk[0]
            return (g * (sd0 - off),) if abs(h) < LENGTH_TOL else ()
        v = h / rho
        if abs(v) >= 1.0 - DOUBLE_ROOT:  # P on the cylinder of radius |h| around axis 1 (or beyond it)
            return (math.atan2(py, px) + math.copysign(math.pi / 2, v),) if abs(v) < 1.0 + self._over else ()
        phi = math.atan2(py, px)
        a = math.asin(v)  # sin(θ1 − φ) = v
        return (phi + a, phi + math.pi - a)

    def _candidates_ur(self, tp: list[float], sd: list[float]) -> list[tuple[float, ...]]:
        """Every UR-type solution as q (each angle the 2π-representation nearest the seed's), limits not checked."""
        r00, r01, r02, px, r10, r11, r12, py, r20, r21, r22, pz = tp
        (sa1, ca1, a1, d1, _, a2, rr, gam, sq, inv2, _, _, a4, _d4, sa4, ca4, d5, sa5, ca5, hsum, hdiff, inv45) = (
            self._const
        )
        (g1, k1), (g2, k2), (g3, k3), (g4, k4), (g5, k5), (g6, k6) = self._gk
        s1_, s2_, s3_, s4_, s5_, s6_ = sd
        out: list[tuple[float, ...]] = []
        cos, sin, atan2, rem = math.cos, math.sin, math.atan2, math.remainder
        for th1 in self._theta1(px, py, pz, s1_):
            q1 = s1_ - rem(s1_ - g1 * th1 - k1, TAU)
            c1, s1 = cos(th1), sin(th1)
            ux, uy, uz = sa1 * s1, -sa1 * c1, ca1  # z1: the direction of axes 2, 3, 4
            yx, yy, yz = -ca1 * s1, ca1 * c1, sa1  # y1 (x1 = (c1, s1, 0))
            # R'ᵀ·z1, R'ᵀ·x1, R'ᵀ·y1: frame-1 axes seen from frame 6
            wx, wy, wz = r00 * ux + r10 * uy + r20 * uz, r01 * ux + r11 * uy + r21 * uz, r02 * ux + r12 * uy + r22 * uz
            ax, ay, az = r00 * c1 + r10 * s1, r01 * c1 + r11 * s1, r02 * c1 + r12 * s1
            bx, by, bz = r00 * yx + r10 * yy + r20 * yz, r01 * yx + r11 * yy + r21 * yz, r02 * yx + r12 * yy + r22 * yz
            hw = math.hypot(wx, wy)
            b5 = _theta5(hw, wz, hsum, hdiff, inv45, self._over)
            if b5 is None:
                continue
            singular = hw < SINGULAR_TOL  # axis 6 ∥ axes 2-4: θ6 free
            atw = atan2(wy, wx)
            c5 = cos(b5)
            # P − o1 in frame 1 (its z1 part is the constant offset)
            px1 = c1 * (px - a1 * c1) + s1 * (py - a1 * s1)
            py1 = yx * (px - a1 * c1) + yy * (py - a1 * s1) + yz * (pz - d1)
            for th5 in (b5,) if singular else (b5, -b5):
                s5 = sin(th5)
                if singular:
                    th6 = _ur_free_theta6(
                        g6 * (s6_ - k6), px1, py1, (ax, ay, az), (bx, by, bz), c5, s5, sa5, ca5, d5, a4, a2, rr
                    )
                else:
                    th6 = atan2(ca5 * c5 * sa4 + sa5 * ca4, s5 * sa4) - atw
                q5 = s5_ - rem(s5_ - g5 * th5 - k5, TAU)
                q6 = s6_ - rem(s6_ - g6 * th6 - k6, TAU)
                c6, s6 = cos(th6), sin(th6)
                e0, e1 = sa5 * s6, sa5 * c6  # z4 in frame 6: (e0, e1, ca5)
                f = -ca5 * s5
                h0, h1, h2 = c6 * c5 + s6 * f, c6 * f - s6 * c5, sa5 * s5  # x4 in frame 6
                xx, yx4 = ax * h0 + ay * h1 + az * h2, bx * h0 + by * h1 + bz * h2  # x4 in frame 1
                # o3 − o1 = (P − o1) − d5·z4 − a4·x4 − d4·z1: in frame 1 (X, Y, 0)
                X = px1 - d5 * (ax * e0 + ay * e1 + az * ca5) - a4 * xx
                Y = py1 - d5 * (bx * e0 + by * e1 + bz * ca5) - a4 * yx4
                th234 = atan2(yx4, xx)
                roots3 = _roots_acos((X * X + Y * Y - sq) * inv2, DOUBLE_ROOT, self._over)
                if roots3 is None:
                    continue
                atY = atan2(Y, X)
                cb = a2 + rr * cos(roots3[0])
                for b in roots3:
                    th3 = b - gam
                    th2 = atY - atan2(rr * sin(b), cb)
                    q2 = s2_ - rem(s2_ - g2 * th2 - k2, TAU)
                    q3 = s3_ - rem(s3_ - g3 * th3 - k3, TAU)
                    q4 = s4_ - rem(s4_ - g4 * (th234 - th2 - th3) - k4, TAU)
                    out.append((q1, q2, q3, q4, q5, q6))
        return out

    def _candidates_wrist(self, tp: list[float], sd: list[float]) -> list[tuple[float, ...]]:
        """Every spherical-wrist solution as q (each angle the 2π-representation nearest the seed's), limits not checked."""
        r00, r01, r02, px, r10, r11, r12, py, r20, r21, r22, pz = tp
        (sa1, ca1, a1, d1, _, a2, rr, gam, sq, inv2, sa3, ca3, _, _, sa4, ca4, _, sa5, ca5, hsum, hdiff, inv45) = (
            self._const
        )
        (g1, k1), (g2, k2), (g3, k3), (g4, k4), (g5, k5), (g6, k6) = self._gk
        s1_, s2_, s3_, s4_, s5_, s6_ = sd
        out: list[tuple[float, ...]] = []
        cos, sin, atan2, rem = math.cos, math.sin, math.atan2, math.remainder
        for th1 in self._theta1(px, py, pz, s1_):
            q1 = s1_ - rem(s1_ - g1 * th1 - k1, TAU)
            c1, s1 = cos(th1), sin(th1)
            ux, uy, uz = sa1 * s1, -sa1 * c1, ca1
            yx, yy, yz = -ca1 * s1, ca1 * c1, sa1
            qx, qy, qz = px - a1 * c1, py - a1 * s1, pz - d1
            X = c1 * qx + s1 * qy  # wrist centre in frame 1
            Y = yx * qx + yy * qy + yz * qz
            roots3 = _roots_acos((X * X + Y * Y - sq) * inv2, DOUBLE_ROOT, self._over)
            if roots3 is None:
                continue
            atY = atan2(Y, X)
            cb = a2 + rr * cos(roots3[0])
            for b in roots3:
                th3 = b - gam
                th2 = atY - atan2(rr * sin(b), cb)
                q2 = s2_ - rem(s2_ - g2 * th2 - k2, TAU)
                q3 = s3_ - rem(s3_ - g3 * th3 - k3, TAU)
                c23, s23 = cos(th2 + th3), sin(th2 + th3)
                # frame 3: x3 = c23·x1 + s23·y1, y3 = ca3·v + sa3·z1, z3 = −sa3·v + ca3·z1 with v = −s23·x1 + c23·y1
                x3x, x3y, x3z = c23 * c1 + s23 * yx, c23 * s1 + s23 * yy, s23 * yz
                vx, vy, vz = -s23 * c1 + c23 * yx, -s23 * s1 + c23 * yy, c23 * yz
                y3x, y3y, y3z = ca3 * vx + sa3 * ux, ca3 * vy + sa3 * uy, ca3 * vz + sa3 * uz
                z3x, z3y, z3z = -sa3 * vx + ca3 * ux, -sa3 * vy + ca3 * uy, -sa3 * vz + ca3 * uz
                # M = R03ᵀ·R' = Rz(θ4)·Rx(α4)·Rz(θ5)·Rx(α5)·Rz(θ6): its third column and third row
                m02 = x3x * r02 + x3y * r12 + x3z * r22
                m12 = y3x * r02 + y3y * r12 + y3z * r22
                m22 = z3x * r02 + z3y * r12 + z3z * r22
                m20 = z3x * r00 + z3y * r10 + z3z * r20
                m21 = z3x * r01 + z3y * r11 + z3z * r21
                hm = math.hypot(m02, m12)
                b5 = _theta5(hm, m22, hsum, hdiff, inv45, self._over)
                if b5 is None:
                    continue
                singular = hm < SINGULAR_TOL  # axis 6 ∥ axis 4: θ4 free, θ6 follows
                roots5 = (b5,) if singular else (b5, -b5)
                atm, atr = atan2(m12, m02), atan2(m21, m20)
                c5 = cos(roots5[0])
                for th5 in roots5:
                    s5 = sin(th5)
                    th4 = g4 * (s4_ - k4) if singular else atm - atan2(-ca4 * c5 * sa5 - sa4 * ca5, s5 * sa5)
                    if hm < NEAR_SINGULAR:  # θ4 and θ6 nearly share an axis: θ6 must absorb θ4's rounding
                        m00 = x3x * r00 + x3y * r10 + x3z * r20
                        m10 = y3x * r00 + y3y * r10 + y3z * r20
                        th6 = _wrist_theta6(th4, th5, m00, m10, m20, sa4, ca4, sa5, ca5)
                    else:
                        th6 = atan2(sa4 * c5 * ca5 + ca4 * sa5, sa4 * s5) - atr
                    q4 = s4_ - rem(s4_ - g4 * th4 - k4, TAU)
                    q5 = s5_ - rem(s5_ - g5 * th5 - k5, TAU)
                    q6 = s6_ - rem(s6_ - g6 * th6 - k6, TAU)
                    out.append((q1, q2, q3, q4, q5, q6))
        return out


def _wrist_theta6(
    th4: float, th5: float, m00: float, m10: float, m20: float, sa4: float, ca4: float, sa5: float, ca5: float
) -> float:
    """θ6 from the first column of Rz(θ6) = Rx(−α5)·Rz(−θ5)·Rx(−α4)·Rz(−θ4)·M, given θ4 and θ5 (near a wrist singularity)."""
    c, s = math.cos(th4), math.sin(th4)
    x, y, z = c * m00 + s * m10, -s * m00 + c * m10, m20
    y, z = ca4 * y + sa4 * z, -sa4 * y + ca4 * z
    c, s = math.cos(th5), math.sin(th5)
    x, y = c * x + s * y, -s * x + c * y
    y = ca5 * y + sa5 * z
    return math.atan2(y, x)


def _ur_free_theta6(
    seed6: float, px1: float, py1: float, ax_: tuple[float, float, float], bx_: tuple[float, float, float],
    c5: float, s5: float, sa5: float, ca5: float, d5: float, a4: float, a2: float, rr: float,
) -> float:  # fmt: skip
    """θ6 at a UR-type wrist singularity: the seed's if the elbow can then reach, else the nearest that can.

    With axis 6 parallel to axes 2-4, turning θ6 (and θ234 back) moves the point on axis 4 on a circle
    in frame 1: its squared distance is D(θ6) = A + R·cos(θ6 − β), and the elbow reaches it iff
    (a2 − rr)² ≤ D ≤ (a2 + rr)².
    """
    ax, ay, az = ax_
    bx, by, bz = bx_
    f, h2 = -ca5 * s5, sa5 * s5
    x0, xc, xs = (
        px1 - d5 * az * ca5 - a4 * az * h2,
        -d5 * ay * sa5 - a4 * (ax * c5 + ay * f),
        -d5 * ax * sa5 - a4 * (ax * f - ay * c5),
    )
    y0, yc, ys = (
        py1 - d5 * bz * ca5 - a4 * bz * h2,
        -d5 * by * sa5 - a4 * (bx * c5 + by * f),
        -d5 * bx * sa5 - a4 * (bx * f - by * c5),
    )
    A = x0 * x0 + y0 * y0 + (xc * xc + yc * yc + xs * xs + ys * ys) / 2.0
    P, Q = 2.0 * (x0 * xc + y0 * yc), 2.0 * (x0 * xs + y0 * ys)
    R, beta = math.hypot(P, Q), math.atan2(Q, P)
    d_lo, d_hi = (a2 - rr) ** 2, (a2 + rr) ** 2
    if R < LENGTH_TOL**2 or d_lo <= A + R * math.cos(seed6 - beta) <= d_hi:
        return seed6
    lo_c, hi_c = (d_lo - A) / R, (d_hi - A) / R
    if lo_c > 1.0 or hi_c < -1.0:
        return seed6  # unreachable for every θ6
    g1, g2 = math.acos(min(1.0, hi_c)), math.acos(max(-1.0, lo_c))
    return min((beta + g1, beta - g1, beta + g2, beta - g2), key=lambda t: abs(math.remainder(t - seed6, TAU)))


def _first(item: tuple[float, Array]) -> float:
    return item[0]
