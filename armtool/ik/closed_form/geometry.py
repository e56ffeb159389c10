"""A 6R chain's joint axes as lines, and its Denavit–Hartenberg model: what closed-form detection reads.

The six axes at q = 0 are lines in the base frame (`axis_lines`). Turned into DH frames by their
common normals (frame i−1 on axis i; along parallel axes the normal through the previous origin,
so d = 0 there), with the axis signs, joint-zero offsets (θ_i = sign_i·q_i + offset_i), the base
frame B and the tool transform E measured from the chain, never assumed:
FK(q) = B·A1(θ1)…A5(θ5)·Rz(θ6)·E, A_i = Rz(θ)·Tz(d)·Tx(a)·Rx(α). Offsets and twists smaller than
the tolerances given are snapped to zero: the model then has exactly the structure (parallel or
intersecting axes) the chain has within them, and `model_error` says how far it is from the chain.
`dh_lines` gives the model's own axis lines, which the closed forms solve on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from armtool.ik.solver import Array
from armtool.model.chain import Chain

ANGLE_TOL = 1e-6  # rad: axes parallel
LENGTH_TOL = 1e-6  # m: lines intersect, offsets vanish

Line = tuple[Array, Array]  # (a point, the unit direction)


@dataclass(frozen=True)
class DHJoint:
    """One Denavit–Hartenberg link: A = Rz(θ)·Tz(d)·Tx(a)·Rx(α), with θ = sign·q + offset."""

    sign: float
    offset: float
    d: float
    a: float
    alpha: float


def axis_lines(chain: Chain) -> tuple[list[Line], Array]:
    """Each joint axis at q = 0 as (point, unit direction) in the base frame, and the tip pose at q = 0."""
    T = np.eye(4)
    lines = []
    for joint in chain.joints:
        T = T @ joint.origin
        lines.append((T[:3, 3].copy(), T[:3, :3] @ joint.axis))
    return lines, T @ chain.tip_offset


def parallel(w1: Array, w2: Array, angle_tol: float = ANGLE_TOL) -> bool:
    return float(np.linalg.norm(np.cross(w1, w2))) < angle_tol


def angle_deg(w1: Array, w2: Array) -> float:
    return math.degrees(math.atan2(float(np.linalg.norm(np.cross(w1, w2))), abs(float(w1 @ w2))))


def closest(p1: Array, w1: Array, p2: Array, w2: Array, angle_tol: float = ANGLE_TOL) -> tuple[Array, Array]:
    """Closest points of two lines (for parallel lines: p1 and its foot on line 2)."""
    r = p1 - p2
    b, e, f = float(w1 @ w2), float(w1 @ r), float(w2 @ r)
    den = 1.0 - b * b
    t = 0.0 if den < angle_tol**2 else (b * f - e) / den
    return p1 + t * w1, p2 + (f + t * b) * w2


def distance(l1: Line, l2: Line, angle_tol: float = ANGLE_TOL) -> float:
    c1, c2 = closest(l1[0], l1[1], l2[0], l2[1], angle_tol)
    return float(np.linalg.norm(c2 - c1))


def denavit_hartenberg(
    lines: list[Line], tip0: Array, angle_tol: float = ANGLE_TOL, length_tol: float = LENGTH_TOL
) -> tuple[tuple[DHJoint, ...], Array, Array]:
    """DH frames from the axis lines by common normals: joints, base frame B and tool transform E."""
    p1, w1 = lines[0]
    z_prev = w1 / np.linalg.norm(w1)
    o_prev = closest(p1, z_prev, lines[1][0], lines[1][1], angle_tol)[0]  # so d1 = 0
    origins: list[Array] = [o_prev]
    xs: list[Array] = []
    zs: list[Array] = [z_prev]
    params: list[tuple[float, float, float, float]] = []  # sign, d, a, alpha of joints 1..5
    sign = 1.0
    for p, w in lines[1:]:
        if parallel(z_prev, w, angle_tol):
            sign_next = 1.0 if float(z_prev @ w) > 0 else -1.0
            z = sign_next * w
            o = p + float((o_prev - p) @ z) * z
            d = 0.0
            v = o - o_prev
        else:
            sign_next = 1.0
            z = w
            c, o = closest(o_prev, z_prev, p, w, angle_tol)
            d = float((c - o_prev) @ z_prev)
            v = o - c
        a = float(np.linalg.norm(v))
        if a > length_tol:
            x = v / a
        elif not parallel(z_prev, z, angle_tol):
            x = np.cross(z_prev, z)
            x /= np.linalg.norm(x)
            a = 0.0
        else:
            x = xs[-1] if xs else any_normal(z_prev)
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
    zero = dh_fk(tuple(joints), base, np.eye(4), [0.0] * 6)
    tool = np.asarray(np.linalg.solve(zero, tip0), dtype=np.float64)
    return tuple(joints), base, tool


def any_normal(z: Array) -> Array:
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x: Array = np.cross(z, helper)
    unit: Array = x / np.linalg.norm(x)  # numpy's stubs: Any for an array divided by a numpy scalar
    return unit


def _dh_matrix(j: DHJoint, q: float) -> Array:
    th = j.sign * q + j.offset
    ct, st, ca, sa = math.cos(th), math.sin(th), math.cos(j.alpha), math.sin(j.alpha)
    return np.array(
        [
            [ct, -st * ca, st * sa, j.a * ct],
            [st, ct * ca, -ct * sa, j.a * st],
            [0.0, sa, ca, j.d],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


def dh_fk(joints: tuple[DHJoint, ...], base: Array, tool: Array, q: list[float]) -> Array:
    T: Array = base.copy()
    for j, qi in zip(joints, q):
        T = T @ _dh_matrix(j, qi)
    return T @ tool


def model_error(chain: Chain, joints: tuple[DHJoint, ...], base: Array, tool: Array) -> float:
    rng = np.random.default_rng(0)
    Q = np.vstack([np.zeros(6), rng.uniform(-math.pi, math.pi, size=(24, 6))])
    T_chain = chain.fk_batch(Q)
    return max(float(np.abs(dh_fk(joints, base, tool, list(q)) - T).max()) for q, T in zip(Q, T_chain))


def dh_lines(joints: tuple[DHJoint, ...], base: Array, tool: Array) -> tuple[list[Line], Array]:
    """The DH model's axis lines at q = 0 (joint i turns by +q about sign_i·z of frame i−1) and its tip pose."""
    T: Array = base.copy()
    lines: list[Line] = []
    for j in joints:
        lines.append((T[:3, 3].copy(), j.sign * T[:3, 2].copy()))
        T = T @ _dh_matrix(j, 0.0)
    return lines, T @ tool
