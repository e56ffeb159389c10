"""The families' generic cases as straight-line code over lanes (one target each), which LLVM vectorizes.

`solve(family, m, targets, seeds, out)` writes what kernel.solve_many writes (same `out` layout, same
model array) for an exact model of a family in FAMILIES, the chain read from either end: the UR-type,
and the spherical wrist with axes 1∥2, 2∥3, 1 and 2 intersecting, or 2 and 3 intersecting. Each is a
fixed tree of eight candidate slots: UR-type θ1, θ5 and the elbow, two roots each; spherical: four
position solutions (two roots of each of the family's two subproblems for θ1..θ3), each with the
wrist's two θ5 roots. A target whose solve meets a special case anywhere — a subproblem with a free
angle, roots closer than the general kernel's merge window, a wrist or shoulder singularity — is
solved by kernel's general code instead: every such case is the general kernel's, and the lanes never
guess one. The spherical wrist with the first three axes in general position (SP5's quartic, whose
roots are found by iteration) has no lanes.

Why. The general kernel solves one target at a time (~2-3 µs on UR5 or Kinova here), ~35 libm atan2
calls and a branch on every root. Written without branches (a subproblem without a real root gives
NaN, which the later steps carry into the slot's status) and with a polynomial atan2, the same
decomposition runs eight targets per instruction (AVX-512): 0.4-0.7 µs per target here, 4-5× the
kernel's batch (benchmarks/ik_closed_form.py). A batch's answers equal single calls'
(kernel.solve_one) to ~1e-9 rad (another atan2, cosines from square roots), and have the same count.

What keeps it vectorized (each measured to stop LLVM's loop vectorizer, which then runs one target at
a time, ~4× slower): a call left in the loop (so every helper in it is inline="always" or small enough
for LLVM to inline), an array passed to a function called in the loop (Numba's reference counting), a
libm call (atan2: `atan2` here; sqrt, floor and division vectorize), a loop inside the loop (a tuple's
items stored by index), loads and stores LLVM cannot prove independent (rows of a 2-D scratch, several
scratch arrays, or the lanes inlined into the loop over the chunks beside the call's arrays). So the
inputs are copied into one flat scratch at constant offsets first, and the lanes are a function of
their own that sees only that scratch.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from llvmlite import ir  # type: ignore[import-untyped]
from numba import njit, types
from numba.extending import intrinsic

from armtool.ik.closed_form import kernel as K
from armtool.ik.closed_form.subproblems import add, cross, dot, neg, rot, scale, sub

CHUNK = 64  # targets per pass through the scratch (it stays in the L1/L2 cache)
SLOT = 8  # per candidate slot in the scratch: q (6), squared distance to the seed, status
# The scratch: one flat array of rows of CHUNK values (one per lane), at these rows. One array with
# constant offsets, so that LLVM proves its loads and stores independent (rows of a 2-D array, whose
# stride it does not know, or separate arrays needed run-time overlap checks: no vectorization).
TARGET = 0  # 12 rows: R row-major, then p
SEEDS = 12  # 6 rows
SLOTS = 18  # 8 × SLOT rows
RARE = SLOTS + 8 * SLOT  # the row that flags a target for the general kernel
ROWS = RARE + 1
# slot status
NONE, OUTSIDE, FAILED, GOOD = 0.0, 1.0, 2.0, 3.0
# A lane defers to the general kernel well before it would treat a case specially.
NEAR_ONE = 1e-8  # |cos| within this of 1: a double root (the general kernel merges within 5e-11)
DEGENERATE = 1e-9  # relative size below which a subproblem's angle may be free (the general kernel: 1e-13)
TAN_15 = 0.2679491924311227  # tan(π/12)
TAN_30 = 0.5773502691896257  # tan(π/6)
# atan t = t + t·z·Σ c_j z^j, z = t², c_j = (−1)^(j+1)/(2j+3): |t| ≤ tan 15°, so 14 terms leave < 1e-18
ATAN = tuple((-1.0) ** (j + 1) / (2 * j + 3) for j in range(14))
TAU = 2.0 * math.pi


def _sqrt_llvm(typingctx, x):  # type: ignore[no-untyped-def]
    """√x as LLVM's intrinsic, which vectorizes (math.sqrt is a libm call that LLVM did not always turn into it)."""
    if x != types.float64:
        return None

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        return builder.call(builder.module.declare_intrinsic("llvm.sqrt", [ir.DoubleType()]), args)

    return types.float64(types.float64), codegen


_sqrt: Any = intrinsic(_sqrt_llvm)  # typed Any: mypy sees numba's intrinsic wrapper, not the √x it compiles to


@njit(cache=True, error_model="numpy")
def atan2(y, x):  # type: ignore[no-untyped-def]
    """atan2 without a libm call (which would stop vectorization): the octant by selects, then
    atan of min/max, reduced by tan 30° above tan 15°, by its Taylor series. Within 4.5e-16 rad of
    libm's (tests/ik/closed_form/test_lanes.py); atan2(0, 0) = 0, atan2(−0, −x) = π, NaN in, NaN out."""
    ax, ay = math.fabs(x), math.fabs(y)
    swap = ay > ax
    big = ay if swap else ax
    small = ax if swap else ay
    t = small / big if big != 0.0 else 0.0  # NaN stays NaN: a slot without a root
    reduced = t > TAN_15
    t = (t - TAN_30) / (1.0 + TAN_30 * t) if reduced else t
    z = t * t
    s = ATAN[13]
    s = s * z + ATAN[12]
    s = s * z + ATAN[11]
    s = s * z + ATAN[10]
    s = s * z + ATAN[9]
    s = s * z + ATAN[8]
    s = s * z + ATAN[7]
    s = s * z + ATAN[6]
    s = s * z + ATAN[5]
    s = s * z + ATAN[4]
    s = s * z + ATAN[3]
    s = s * z + ATAN[2]
    s = s * z + ATAN[1]
    s = s * z + ATAN[0]
    a = t + t * z * s + (math.pi / 6.0 if reduced else 0.0)
    a = math.pi / 2.0 - a if swap else a
    a = math.pi - a if x < 0.0 else a
    return -a if y < 0.0 else a


# ---- subproblems without branches: NaN for no root, a flag where the general kernel must decide -------------


@njit(cache=True, error_model="numpy", inline="always")
def _sp4(h, p, k, d):  # type: ignore[no-untyped-def]
    """subproblems.sp4's two roots (θ, cos, sin), NaN where there is none, and whether the target is rare here."""
    hk, kp = dot(h, k), dot(k, p)
    A = dot(h, p) - hk * kp
    B = dot(h, cross(k, p))
    r = _sqrt(A * A + B * B)
    c0 = (d - hk * kp) / r
    near = math.fabs(math.fabs(c0) - 1.0) <= NEAR_ONE
    rare = (r <= DEGENERATE * (1.0 + math.fabs(d)) * (1.0 + _sqrt(dot(p, p)))) | near
    sa = _sqrt((1.0 - c0) * (1.0 + c0))  # NaN beyond ±1: no root
    cf, sf = A / r, B / r
    ca, sa_ = cf * c0 - sf * sa, sf * c0 + cf * sa
    cb, sb = cf * c0 + sf * sa, sf * c0 - cf * sa
    return (atan2(sa_, ca), ca, sa_), (atan2(sb, cb), cb, sb), rare


@njit(cache=True, error_model="numpy", inline="always")
def _sp3(p1, p2, k, d2):  # type: ignore[no-untyped-def]
    """subproblems.sp3 given the squared distance d² (no square root needed)."""
    return _sp4(p2, p1, k, 0.5 * (dot(p1, p1) + dot(p2, p2) - d2))


@njit(cache=True, error_model="numpy", inline="always")
def _sp1(p1, p2, k):  # type: ignore[no-untyped-def]
    x = dot(p1, p2) - dot(k, p1) * dot(k, p2)
    y = dot(k, cross(p1, p2))
    r = _sqrt(x * x + y * y)
    return (atan2(y, x), x / r, y / r), r <= DEGENERATE * (dot(p1, p1) + dot(p2, p2))


# ---- the families ------------------------------------------------------------------------------------------


@njit(cache=True, error_model="numpy", inline="always")
def _ur_elbow(c, v, t14, t3):  # type: ignore[no-untyped-def]
    """θ2 and θ4 for one elbow root θ3 (kernel._ur's innermost step)."""
    h2, h3 = c[0][1], c[0][2]
    p23, p34 = c[1][2], c[1][3]
    s3, s4 = c[6][1], c[6][2]
    t2, rare = _sp1(add(p23, rot(h3, t3[1], t3[2], p34)), v, h2)
    c23 = t2[1] * t3[1] - s3 * t2[2] * t3[2]
    s23 = t2[2] * t3[1] + s3 * t2[1] * t3[2]
    t4 = (s4 * (t14[0] - t2[0] - s3 * t3[0]), t14[1] * c23 + t14[2] * s23, s4 * (t14[2] * c23 - t14[1] * s23))
    return t2, t4, rare


@njit(cache=True, error_model="numpy", inline="always")
def _ur_wrist(c, w1, v0, m1, t1, t5):  # type: ignore[no-untyped-def]
    """θ2+θ3+θ4, θ6 and both elbows for one (θ1, θ5): two slots."""
    h2, h3, h5, h6 = c[0][1], c[0][2], c[0][4], c[0][5]
    p23, p34, p45 = c[1][2], c[1][3], c[1][4]
    t14, r0 = _sp1(rot(h5, t5[1], t5[2], h6), w1, h2)
    t6, r1 = _sp1(c[3], rot(h5, t5[1], -t5[2], rot(h2, t14[1], -t14[2], m1)), h6)
    v = sub(v0, rot(h2, t14[1], t14[2], p45))
    t3a, t3b, r2 = _sp3(p34, neg(p23), h3, dot(v, v))
    t2a, t4a, r3 = _ur_elbow(c, v, t14, t3a)
    t2b, t4b, r4 = _ur_elbow(c, v, t14, t3b)
    return (t1, t2a, t3a, t4a, t5, t6), (t1, t2b, t3b, t4b, t5, t6), r0 | r1 | r2 | r3 | r4


@njit(cache=True, error_model="numpy", inline="always")
def _ur_shoulder(c, w, mv, p16, t1):  # type: ignore[no-untyped-def]
    h1, h2, h5, h6 = c[0][0], c[0][1], c[0][4], c[0][5]
    w1 = rot(h1, t1[1], -t1[2], w)
    v0 = sub(rot(h1, t1[1], -t1[2], p16), c[1][1])
    m1 = rot(h1, t1[1], -t1[2], mv)
    t5a, t5b, r0 = _sp4(h2, h6, h5, dot(h2, w1))
    a, b, r1 = _ur_wrist(c, w1, v0, m1, t1, t5a)
    d, e, r2 = _ur_wrist(c, w1, v0, m1, t1, t5b)
    return a, b, d, e, r0 | r1 | r2


@njit(cache=True, error_model="numpy", inline="always")
def _ur(c, R06, p16):  # type: ignore[no-untyped-def]
    """kernel._ur's eight slots."""
    h1, h2, h6 = c[0][0], c[0][1], c[0][5]
    w = _mat_vec(R06, h6)
    mv = _mat_vec(R06, c[3])
    t1a, t1b, r0 = _sp4(h2, p16, neg(h1), c[6][0])
    a0, a1, a2, a3, ra = _ur_shoulder(c, w, mv, p16, t1a)
    b0, b1, b2, b3, rb = _ur_shoulder(c, w, mv, p16, t1b)
    return (a0, a1, a2, a3, b0, b1, b2, b3), r0 | ra | rb


@njit(cache=True, error_model="numpy", inline="always")
def _sp2(p1, p2, k1, k2):  # type: ignore[no-untyped-def]
    """subproblems.sp2's two solutions ((θ1, θ2), (θ1, θ2)), NaN where there is none, and whether the target is rare."""
    n1, n2 = cross(k1, p1), cross(k2, p2)
    size = dot(p1, p1) + dot(p2, p2)
    c12 = dot(k1, k2)
    den = 1.0 - c12 * c12
    a1, a2 = dot(k1, p1), dot(k2, p2)
    alpha, beta = (a1 - c12 * a2) / den, (a2 - c12 * a1) / den
    axb = cross(k1, k2)
    base = add(scale(k1, alpha), scale(k2, beta))
    g2 = (0.5 * size - dot(base, base)) / den
    free = (dot(n1, n1) <= DEGENERATE * size) | (dot(n2, n2) <= DEGENERATE * size)
    rare = free | (math.fabs(g2 * den) <= NEAR_ONE * size)  # p1 or p2 along its axis, or a tangent pair
    g = _sqrt(g2)  # NaN below 0: no solution
    xa, xb = add(base, scale(axb, g)), sub(base, scale(axb, g))
    t1a, r0 = _sp1(p1, xa, k1)
    t2a, r1 = _sp1(p2, xa, k2)
    t1b, r2 = _sp1(p1, xb, k1)
    t2b, r3 = _sp1(p2, xb, k2)
    return (t1a, t2a), (t1b, t2b), rare | r0 | r1 | r2 | r3


@njit(cache=True, error_model="numpy", inline="always")
def _back3(c, t, v):  # type: ignore[no-untyped-def]
    """(R1 R2 R3)ᵀ v for a position solution t = (θ1, θ2, θ3)."""
    h1, h2, h3 = c[0][0], c[0][1], c[0][2]
    v = rot(h1, t[0][1], -t[0][2], v)
    v = rot(h2, t[1][1], -t[1][2], v)
    return rot(h3, t[2][1], -t[2][2], v)


@njit(cache=True, error_model="numpy", inline="always")
def _wrist_46(c, w3, m3, t5):  # type: ignore[no-untyped-def]
    """θ4 and θ6 for one θ5 root (kernel._wrist's loop body)."""
    h4, h5, h6 = c[0][3], c[0][4], c[0][5]
    t4, r0 = _sp1(rot(h5, t5[1], t5[2], h6), w3, h4)
    t6, r1 = _sp1(c[3], rot(h5, t5[1], -t5[2], rot(h4, t4[1], -t4[2], m3)), h6)
    return t4, t6, r0 | r1


@njit(cache=True, error_model="numpy", inline="always")
def _wrist(c, w, mv, t):  # type: ignore[no-untyped-def]
    """kernel._wrist's two slots for one position solution t = (θ1, θ2, θ3)."""
    h4, h5, h6 = c[0][3], c[0][4], c[0][5]
    w3, m3 = _back3(c, t, w), _back3(c, t, mv)
    t5a, t5b, r0 = _sp4(h4, h6, h5, dot(h4, w3))
    t4a, t6a, r1 = _wrist_46(c, w3, m3, t5a)
    t4b, t6b, r2 = _wrist_46(c, w3, m3, t5b)
    return (t[0], t[1], t[2], t4a, t5a, t6a), (t[0], t[1], t[2], t4b, t5b, t6b), r0 | r1 | r2


@njit(cache=True, error_model="numpy", inline="always")
def _wrist_slots(c, R06, positions):  # type: ignore[no-untyped-def]
    """The eight slots of four position solutions, two wrists each."""
    w, mv = _mat_vec(R06, c[0][5]), _mat_vec(R06, c[3])
    a0, a1, ra = _wrist(c, w, mv, positions[0])
    b0, b1, rb = _wrist(c, w, mv, positions[1])
    d0, d1, rd = _wrist(c, w, mv, positions[2])
    e0, e1, re = _wrist(c, w, mv, positions[3])
    return (a0, a1, b0, b1, d0, d1, e0, e1), ra | rb | rd | re


@njit(cache=True, error_model="numpy", inline="always")
def _parallel_23_elbow(c, p16, t1):  # type: ignore[no-untyped-def]
    h1, h2, h3 = c[0][0], c[0][1], c[0][2]
    p12, p23, p34 = c[1][1], c[1][2], c[1][3]
    v = sub(rot(h1, t1[1], -t1[2], p16), p12)
    t3a, t3b, r0 = _sp3(p34, neg(p23), h3, dot(v, v))
    t2a, r1 = _sp1(add(p23, rot(h3, t3a[1], t3a[2], p34)), v, h2)
    t2b, r2 = _sp1(add(p23, rot(h3, t3b[1], t3b[2], p34)), v, h2)
    return (t1, t2a, t3a), (t1, t2b, t3b), r0 | r1 | r2


@njit(cache=True, error_model="numpy", inline="always")
def _parallel_23(c, p16):  # type: ignore[no-untyped-def]
    """kernel._spherical's WRIST_23_PARALLEL: θ1 by sp4, θ3 by sp3, θ2 by sp1."""
    t1a, t1b, r0 = _sp4(c[0][1], p16, neg(c[0][0]), c[6][0])
    a, b, r1 = _parallel_23_elbow(c, p16, t1a)
    d, e, r2 = _parallel_23_elbow(c, p16, t1b)
    return (a, b, d, e), r0 | r1 | r2


@njit(cache=True, error_model="numpy", inline="always")
def _parallel_12_shoulder(c, p16, t3):  # type: ignore[no-untyped-def]
    h1, h2, h3 = c[0][0], c[0][1], c[0][2]
    p12, p23, p34 = c[1][1], c[1][2], c[1][3]
    x = add(p23, rot(h3, t3[1], t3[2], p34))
    t1a, t1b, r0 = _sp3(p12, p16, h1, dot(x, x))
    t2a, r1 = _sp1(x, sub(rot(h1, t1a[1], -t1a[2], p16), p12), h2)
    t2b, r2 = _sp1(x, sub(rot(h1, t1b[1], -t1b[2], p16), p12), h2)
    return (t1a, t2a, t3), (t1b, t2b, t3), r0 | r1 | r2


@njit(cache=True, error_model="numpy", inline="always")
def _parallel_12(c, p16):  # type: ignore[no-untyped-def]
    """kernel._spherical's WRIST_12_PARALLEL: θ3 by sp4, θ1 by sp3, θ2 by sp1."""
    h1 = c[0][0]
    t3a, t3b, r0 = _sp4(h1, c[1][3], c[0][2], dot(h1, p16) - c[6][0])
    a, b, r1 = _parallel_12_shoulder(c, p16, t3a)
    d, e, r2 = _parallel_12_shoulder(c, p16, t3b)
    return (a, b, d, e), r0 | r1 | r2


@njit(cache=True, error_model="numpy", inline="always")
def _intersecting_12_shoulder(c, p16, t3):  # type: ignore[no-untyped-def]
    x = add(c[1][2], rot(c[0][2], t3[1], t3[2], c[1][3]))
    a, b, rare = _sp2(p16, x, neg(c[0][0]), c[0][1])
    return (a[0], a[1], t3), (b[0], b[1], t3), rare


@njit(cache=True, error_model="numpy", inline="always")
def _intersecting_12(c, p16):  # type: ignore[no-untyped-def]
    """kernel._spherical's WRIST_12_INTERSECTING: θ3 by sp3, θ1 and θ2 by sp2."""
    t3a, t3b, r0 = _sp3(c[1][3], neg(c[1][2]), c[0][2], dot(p16, p16))
    a, b, r1 = _intersecting_12_shoulder(c, p16, t3a)
    d, e, r2 = _intersecting_12_shoulder(c, p16, t3b)
    return (a, b, d, e), r0 | r1 | r2


@njit(cache=True, error_model="numpy", inline="always")
def _intersecting_23_elbow(c, p16, t1):  # type: ignore[no-untyped-def]
    v = sub(rot(c[0][0], t1[1], -t1[2], p16), c[1][1])
    a, b, rare = _sp2(v, c[1][3], neg(c[0][1]), c[0][2])
    return (t1, a[0], a[1]), (t1, b[0], b[1]), rare


@njit(cache=True, error_model="numpy", inline="always")
def _intersecting_23(c, p16):  # type: ignore[no-untyped-def]
    """kernel._spherical's WRIST_23_INTERSECTING: θ1 by sp3, θ2 and θ3 by sp2."""
    p34 = c[1][3]
    t1a, t1b, r0 = _sp3(c[1][1], p16, c[0][0], dot(p34, p34))
    a, b, r1 = _intersecting_23_elbow(c, p16, t1a)
    d, e, r2 = _intersecting_23_elbow(c, p16, t1b)
    return (a, b, d, e), r0 | r1 | r2


# ---- one lane: the target's frame, the slots, each slot placed and checked ---------------------------------


@njit(cache=True, error_model="numpy")
def _mat_vec(R, v):  # type: ignore[no-untyped-def]
    return (
        R[0] * v[0] + R[1] * v[1] + R[2] * v[2],
        R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
        R[6] * v[0] + R[7] * v[1] + R[8] * v[2],
    )


@njit(cache=True, error_model="numpy", inline="always")
def _place(theta, s, lo, hi):  # type: ignore[no-untyped-def]
    """kernel._place without branches."""
    q = theta + TAU * math.floor((s - theta) / TAU + 0.5)
    q = q + TAU * max(math.ceil((lo - 1e-9 - q) / TAU), 0.0)  # whole turns up into the limits
    q = q - TAU * max(math.ceil((q - hi - 1e-9) / TAU), 0.0)  # or down
    inside = 1.0 * int((lo - 1e-9 <= q) & (q <= hi + 1e-9))
    return min(max(q, lo), hi) + 0.0 / inside  # + 0 inside, + NaN (0/0) outside: no branch


@njit(cache=True, error_model="numpy", inline="always")
def _dh_step(frame, joint, t):  # type: ignore[no-untyped-def]
    """kernel._reaches' step: frame · Rz(θ) Tz(d) Tx(a) Rx(α) with θ = sign·q + offset, from q's cos and sin."""
    x0, x1, x2, y0, y1, y2, z0, z1, z2, p0, p1, p2 = frame
    sign, co, so, d, a, ca, sa = joint
    cq = co * t[1] - sign * so * t[2]
    sq = so * t[1] + sign * co * t[2]
    nx0, nx1, nx2 = cq * x0 + sq * y0, cq * x1 + sq * y1, cq * x2 + sq * y2
    ny0, ny1, ny2 = cq * y0 - sq * x0, cq * y1 - sq * x1, cq * y2 - sq * x2
    return (
        nx0,
        nx1,
        nx2,
        ca * ny0 + sa * z0,
        ca * ny1 + sa * z1,
        ca * ny2 + sa * z2,
        ca * z0 - sa * ny0,
        ca * z1 - sa * ny1,
        ca * z2 - sa * ny2,
        p0 + d * z0 + a * nx0,
        p1 + d * z1 + a * nx1,
        p2 + d * z2 + a * nx2,
    )


@njit(cache=True, error_model="numpy")
def _pick(second, a, b):  # type: ignore[no-untyped-def]
    """The angle b if second else a, as three float selects (LLVM does not vectorize a select of a whole
    tuple); a function of its own, as a branch in the caller's code would be one more block for Numba's
    analyses, which grow with blocks × variables."""
    return (b[0] if second else a[0], b[1] if second else a[1], b[2] if second else a[2])


@njit(cache=True, error_model="numpy", inline="always")
def _emit(c, seed, tgt, slot):  # type: ignore[no-untyped-def]
    """A slot (solver order) as kernel._emit judges it: (q (6), squared distance to the seed, status)."""
    rev = c[7]
    t1, t2, t3 = _pick(rev, slot[0], slot[5]), _pick(rev, slot[1], slot[4]), _pick(rev, slot[2], slot[3])
    t4, t5, t6 = _pick(rev, slot[3], slot[2]), _pick(rev, slot[4], slot[1]), _pick(rev, slot[5], slot[0])
    lo, hi = c[4], c[5]
    q0 = _place(t1[0], seed[0], lo[0], hi[0])
    q1 = _place(t2[0], seed[1], lo[1], hi[1])
    q2 = _place(t3[0], seed[2], lo[2], hi[2])
    q3 = _place(t4[0], seed[3], lo[3], hi[3])
    q4 = _place(t5[0], seed[4], lo[4], hi[4])
    q5 = _place(t6[0], seed[5], lo[5], hi[5])
    e0, e1, e2, e3, e4, e5 = q0 - seed[0], q1 - seed[1], q2 - seed[2], q3 - seed[3], q4 - seed[4], q5 - seed[5]
    dist = e0 * e0 + e1 * e1 + e2 * e2 + e3 * e3 + e4 * e4 + e5 * e5
    exists = math.isfinite(t1[0] + t2[0] + t3[0] + t4[0] + t5[0] + t6[0])
    placed = math.isfinite(dist)
    base, joints, E = c[8]
    f = _dh_step(base, joints[0], t1)
    f = _dh_step(f, joints[1], t2)
    f = _dh_step(f, joints[2], t3)
    f = _dh_step(f, joints[3], t4)
    f = _dh_step(f, joints[4], t5)
    f = _dh_step(f, joints[5], t6)
    x0, x1, x2, y0, y1, y2, z0, z1, z2, p0, p1, p2 = f
    tol, rot_tol2 = c[9], c[10]
    ex = tgt[9] - (p0 + x0 * E[9] + y0 * E[10] + z0 * E[11])
    ey = tgt[10] - (p1 + x1 * E[9] + y1 * E[10] + z1 * E[11])
    ez = tgt[11] - (p2 + x2 * E[9] + y2 * E[10] + z2 * E[11])
    u0 = tgt[0] - (x0 * E[0] + y0 * E[3] + z0 * E[6])
    u1 = tgt[3] - (x1 * E[0] + y1 * E[3] + z1 * E[6])
    u2 = tgt[6] - (x2 * E[0] + y2 * E[3] + z2 * E[6])
    v0 = tgt[1] - (x0 * E[1] + y0 * E[4] + z0 * E[7])
    v1 = tgt[4] - (x1 * E[1] + y1 * E[4] + z1 * E[7])
    v2 = tgt[7] - (x2 * E[1] + y2 * E[4] + z2 * E[7])
    good = (
        (math.fabs(ex) <= tol)
        & (math.fabs(ey) <= tol)
        & (math.fabs(ez) <= tol)
        & (u0 * u0 + u1 * u1 + u2 * u2 + v0 * v0 + v1 * v1 + v2 * v2 <= rot_tol2)
    )
    status = 1.0 * (int(exists) + int(placed) + int(placed & good))  # NONE, OUTSIDE, FAILED or GOOD
    return (q0, q1, q2, q3, q4, q5, dist, status)


@njit(cache=True, error_model="numpy")
def _frame(c, tgt):  # type: ignore[no-untyped-def]
    """R06 and p16 of a target (tgt: R row-major, then p, in the chain's base frame), as kernel._solve."""
    R, p = tgt[:9], tgt[9:]
    if c[7]:  # reversed: T⁻¹ = (Rᵀ, −Rᵀ p)
        R = (R[0], R[3], R[6], R[1], R[4], R[7], R[2], R[5], R[8])
        p = (
            -(R[0] * p[0] + R[1] * p[1] + R[2] * p[2]),
            -(R[3] * p[0] + R[4] * p[1] + R[5] * p[2]),
            -(R[6] * p[0] + R[7] * p[1] + R[8] * p[2]),
        )
    T = c[2]  # R06 = R · R6Tᵀ
    R06 = (
        R[0] * T[0] + R[1] * T[1] + R[2] * T[2],
        R[0] * T[3] + R[1] * T[4] + R[2] * T[5],
        R[0] * T[6] + R[1] * T[7] + R[2] * T[8],
        R[3] * T[0] + R[4] * T[1] + R[5] * T[2],
        R[3] * T[3] + R[4] * T[4] + R[5] * T[5],
        R[3] * T[6] + R[4] * T[7] + R[5] * T[8],
        R[6] * T[0] + R[7] * T[1] + R[8] * T[2],
        R[6] * T[3] + R[7] * T[4] + R[8] * T[5],
        R[6] * T[6] + R[7] * T[7] + R[8] * T[8],
    )
    return R06, sub(sub(p, c[1][0]), _mat_vec(R06, c[1][6]))


@njit(cache=True, error_model="numpy", inline="always")
def _judge(c, seed, tgt, slots):  # type: ignore[no-untyped-def]
    return (
        _emit(c, seed, tgt, slots[0]),
        _emit(c, seed, tgt, slots[1]),
        _emit(c, seed, tgt, slots[2]),
        _emit(c, seed, tgt, slots[3]),
        _emit(c, seed, tgt, slots[4]),
        _emit(c, seed, tgt, slots[5]),
        _emit(c, seed, tgt, slots[6]),
        _emit(c, seed, tgt, slots[7]),
    )


# ---- the model, the chunks, the output ---------------------------------------------------------------------


@njit(cache=True, error_model="numpy")
def _vec(m, i):  # type: ignore[no-untyped-def]
    return (m[i], m[i + 1], m[i + 2])


@njit(cache=True, error_model="numpy")
def _dh_joint(m, i):  # type: ignore[no-untyped-def]
    j = K.DH_JOINTS + 7 * i
    return (m[j], m[j + 1], m[j + 2], m[j + 3], m[j + 4], m[j + 5], m[j + 6])


@njit(cache=True, error_model="numpy")
def _constants(m):  # type: ignore[no-untyped-def]
    """The model array as tuples (read once per call, outside the vectorized loop): axes, offsets,
    R6T, n6, lower and upper limits, the family's constants, reversed, the DH model, tolerances."""
    H, P, T = K.H, K.P, K.R6T
    axes = (_vec(m, H), _vec(m, H + 3), _vec(m, H + 6), _vec(m, H + 9), _vec(m, H + 12), _vec(m, H + 15))
    offsets = (
        _vec(m, P),
        _vec(m, P + 3),
        _vec(m, P + 6),
        _vec(m, P + 9),
        _vec(m, P + 12),
        _vec(m, P + 15),
        _vec(m, P + 18),
    )
    r6t = (m[T], m[T + 1], m[T + 2], m[T + 3], m[T + 4], m[T + 5], m[T + 6], m[T + 7], m[T + 8])
    lo = (m[K.LO], m[K.LO + 1], m[K.LO + 2], m[K.LO + 3], m[K.LO + 4], m[K.LO + 5])
    hi = (m[K.HI], m[K.HI + 1], m[K.HI + 2], m[K.HI + 3], m[K.HI + 4], m[K.HI + 5])
    B, E = K.DH_BASE, K.DH_TOOL  # the base as columns x, y, z, then its origin; the tool row-major, then its origin
    base = (
        m[B],
        m[B + 3],
        m[B + 6],
        m[B + 1],
        m[B + 4],
        m[B + 7],
        m[B + 2],
        m[B + 5],
        m[B + 8],
        m[B + 9],
        m[B + 10],
        m[B + 11],
    )
    tool = (
        m[E],
        m[E + 1],
        m[E + 2],
        m[E + 3],
        m[E + 4],
        m[E + 5],
        m[E + 6],
        m[E + 7],
        m[E + 8],
        m[E + 9],
        m[E + 10],
        m[E + 11],
    )
    joints = (_dh_joint(m, 0), _dh_joint(m, 1), _dh_joint(m, 2), _dh_joint(m, 3), _dh_joint(m, 4), _dh_joint(m, 5))
    const = (m[K.CONST], m[K.CONST + 1], m[K.CONST + 2])
    return (
        axes,
        offsets,
        r6t,
        _vec(m, K.N6),
        lo,
        hi,
        const,
        m[K.REVERSED] != 0.0,
        (base, joints, tool),
        m[K.TOL],
        m[K.ROT_TOL2],
    )


@njit(cache=True, error_model="numpy", inline="always")
def _chunk_in(targets, seeds, start, w, finite):  # type: ignore[no-untyped-def]
    """The chunk of targets from start into the scratch (their rotation, position and seed), whether each is
    finite; how many."""
    n = min(CHUNK, targets.shape[0] - start)
    for j in range(n):
        ok = True
        for r in range(3):
            for col in range(3):
                w[(TARGET + 3 * r + col) * CHUNK + j] = targets[start + j, r, col]
            w[(TARGET + 9 + r) * CHUNK + j] = targets[start + j, r, 3]
        for r in range(4):
            for col in range(4):
                ok &= math.isfinite(targets[start + j, r, col])
        for k in range(6):
            w[(SEEDS + k) * CHUNK + j] = seeds[start + j, k]
            ok &= math.isfinite(seeds[start + j, k])
        finite[j] = ok
    return n


@njit(cache=True, error_model="numpy", inline="always")
def _at(w, row, j):  # type: ignore[no-untyped-def]
    return w[row * CHUNK + j]


@njit(cache=True, error_model="numpy", inline="always")
def _lane_in(w, j):  # type: ignore[no-untyped-def]
    tgt = (
        _at(w, TARGET, j),
        _at(w, TARGET + 1, j),
        _at(w, TARGET + 2, j),
        _at(w, TARGET + 3, j),
        _at(w, TARGET + 4, j),
        _at(w, TARGET + 5, j),
        _at(w, TARGET + 6, j),
        _at(w, TARGET + 7, j),
        _at(w, TARGET + 8, j),
        _at(w, TARGET + 9, j),
        _at(w, TARGET + 10, j),
        _at(w, TARGET + 11, j),
    )
    seed = (
        _at(w, SEEDS, j),
        _at(w, SEEDS + 1, j),
        _at(w, SEEDS + 2, j),
        _at(w, SEEDS + 3, j),
        _at(w, SEEDS + 4, j),
        _at(w, SEEDS + 5, j),
    )
    return tgt, seed


@njit(cache=True, error_model="numpy", inline="always")
def _chunk_out(m, targets, seeds, out, start, n, w, finite):  # type: ignore[no-untyped-def]
    """Each target's good slots into out, nearest the seed first; a rare one solved by the general kernel."""
    status = K.SOLVED
    for j in range(n):
        i = start + j
        row = out[i]
        if not finite[j]:
            row[0] = row[1] = row[2] = 0.0
            row[3] = K.BAD_INPUT
            status = K.BAD_INPUT
        elif _at(w, RARE, j) != 0.0:
            K.solve_one(m, targets[i], seeds[i], row)
        else:
            _collect(w, j, seeds[i], row)
    return status


@njit(cache=True, error_model="numpy")
def _shapes_ok(targets, seeds, out):  # type: ignore[no-untyped-def]
    n = targets.shape[0]
    return (
        targets.shape[1] == 4
        and targets.shape[2] == 4
        and seeds.shape[0] == n
        and seeds.shape[1] == 6
        and out.shape[0] == n
        and out.shape[1] >= K.OUT_SIZE
    )


@njit(cache=True, error_model="numpy", inline="always")
def _store(c, seed, tgt, slots, rare, w, j):  # type: ignore[no-untyped-def]
    """Lane j's eight slots judged into the scratch, and whether the general kernel must solve it."""
    a, b, d, e, f, g, h, i = _judge(c, seed, tgt, slots)
    _put(w, SLOTS, j, a)
    _put(w, SLOTS + SLOT, j, b)
    _put(w, SLOTS + 2 * SLOT, j, d)
    _put(w, SLOTS + 3 * SLOT, j, e)
    _put(w, SLOTS + 4 * SLOT, j, f)
    _put(w, SLOTS + 5 * SLOT, j, g)
    _put(w, SLOTS + 6 * SLOT, j, h)
    _put(w, SLOTS + 7 * SLOT, j, i)
    w[RARE * CHUNK + j] = 1.0 * int(rare)


@njit(cache=True, error_model="numpy", inline="always")
def _put(w, row, j, slot):  # type: ignore[no-untyped-def]
    """One judged slot into the scratch, element by element (a loop over a tuple's items would be a loop
    inside the lanes' loop, which LLVM then does not vectorize)."""
    w[(row) * CHUNK + j] = slot[0]
    w[(row + 1) * CHUNK + j] = slot[1]
    w[(row + 2) * CHUNK + j] = slot[2]
    w[(row + 3) * CHUNK + j] = slot[3]
    w[(row + 4) * CHUNK + j] = slot[4]
    w[(row + 5) * CHUNK + j] = slot[5]
    w[(row + 6) * CHUNK + j] = slot[6]
    w[(row + 7) * CHUNK + j] = slot[7]


# Per family: the lanes (the loop over one chunk's targets, which LLVM vectorizes) and the loop over the
# chunks, each compiled on its family's first batch. The lanes are a function of their own that sees the
# scratch only: inside the loop over the chunks, with the arrays of the call beside it, LLVM did not
# vectorize them (measured: no vector instruction in the loop).


@njit(cache=True, error_model="numpy")
def _ur_lanes(c, w, n):  # type: ignore[no-untyped-def]
    for j in range(n):
        tgt, seed = _lane_in(w, j)
        R06, p16 = _frame(c, tgt)
        slots, rare = _ur(c, R06, p16)
        _store(c, seed, tgt, slots, rare, w, j)


@njit(cache=True, error_model="numpy")
def _parallel_23_lanes(c, w, n):  # type: ignore[no-untyped-def]
    for j in range(n):
        tgt, seed = _lane_in(w, j)
        R06, p16 = _frame(c, tgt)
        positions, r0 = _parallel_23(c, p16)
        slots, r1 = _wrist_slots(c, R06, positions)
        _store(c, seed, tgt, slots, r0 | r1, w, j)


@njit(cache=True, error_model="numpy")
def _parallel_12_lanes(c, w, n):  # type: ignore[no-untyped-def]
    for j in range(n):
        tgt, seed = _lane_in(w, j)
        R06, p16 = _frame(c, tgt)
        positions, r0 = _parallel_12(c, p16)
        slots, r1 = _wrist_slots(c, R06, positions)
        _store(c, seed, tgt, slots, r0 | r1, w, j)


@njit(cache=True, error_model="numpy")
def _intersecting_12_lanes(c, w, n):  # type: ignore[no-untyped-def]
    for j in range(n):
        tgt, seed = _lane_in(w, j)
        R06, p16 = _frame(c, tgt)
        positions, r0 = _intersecting_12(c, p16)
        slots, r1 = _wrist_slots(c, R06, positions)
        _store(c, seed, tgt, slots, r0 | r1, w, j)


@njit(cache=True, error_model="numpy")
def _intersecting_23_lanes(c, w, n):  # type: ignore[no-untyped-def]
    for j in range(n):
        tgt, seed = _lane_in(w, j)
        R06, p16 = _frame(c, tgt)
        positions, r0 = _intersecting_23(c, p16)
        slots, r1 = _wrist_slots(c, R06, positions)
        _store(c, seed, tgt, slots, r0 | r1, w, j)


@njit(cache=True, error_model="numpy")
def _ur_loop(m, targets, seeds, out):  # type: ignore[no-untyped-def]
    c = _constants(m)  # here, not in Python: boxing these tuples costs more than a small batch
    w, finite = np.empty(ROWS * CHUNK), np.empty(CHUNK, dtype=np.bool_)
    status = K.SOLVED
    for start in range(0, targets.shape[0], CHUNK):
        n = _chunk_in(targets, seeds, start, w, finite)
        _ur_lanes(c, w, n)
        status = min(status, _chunk_out(m, targets, seeds, out, start, n, w, finite))
    return status


@njit(cache=True, error_model="numpy")
def _parallel_23_loop(m, targets, seeds, out):  # type: ignore[no-untyped-def]
    c = _constants(m)  # here, not in Python: boxing these tuples costs more than a small batch
    w, finite = np.empty(ROWS * CHUNK), np.empty(CHUNK, dtype=np.bool_)
    status = K.SOLVED
    for start in range(0, targets.shape[0], CHUNK):
        n = _chunk_in(targets, seeds, start, w, finite)
        _parallel_23_lanes(c, w, n)
        status = min(status, _chunk_out(m, targets, seeds, out, start, n, w, finite))
    return status


@njit(cache=True, error_model="numpy")
def _parallel_12_loop(m, targets, seeds, out):  # type: ignore[no-untyped-def]
    c = _constants(m)  # here, not in Python: boxing these tuples costs more than a small batch
    w, finite = np.empty(ROWS * CHUNK), np.empty(CHUNK, dtype=np.bool_)
    status = K.SOLVED
    for start in range(0, targets.shape[0], CHUNK):
        n = _chunk_in(targets, seeds, start, w, finite)
        _parallel_12_lanes(c, w, n)
        status = min(status, _chunk_out(m, targets, seeds, out, start, n, w, finite))
    return status


@njit(cache=True, error_model="numpy")
def _intersecting_12_loop(m, targets, seeds, out):  # type: ignore[no-untyped-def]
    c = _constants(m)  # here, not in Python: boxing these tuples costs more than a small batch
    w, finite = np.empty(ROWS * CHUNK), np.empty(CHUNK, dtype=np.bool_)
    status = K.SOLVED
    for start in range(0, targets.shape[0], CHUNK):
        n = _chunk_in(targets, seeds, start, w, finite)
        _intersecting_12_lanes(c, w, n)
        status = min(status, _chunk_out(m, targets, seeds, out, start, n, w, finite))
    return status


@njit(cache=True, error_model="numpy")
def _intersecting_23_loop(m, targets, seeds, out):  # type: ignore[no-untyped-def]
    c = _constants(m)  # here, not in Python: boxing these tuples costs more than a small batch
    w, finite = np.empty(ROWS * CHUNK), np.empty(CHUNK, dtype=np.bool_)
    status = K.SOLVED
    for start in range(0, targets.shape[0], CHUNK):
        n = _chunk_in(targets, seeds, start, w, finite)
        _intersecting_23_lanes(c, w, n)
        status = min(status, _chunk_out(m, targets, seeds, out, start, n, w, finite))
    return status


@njit(cache=True, error_model="numpy", inline="always")
def _collect(w, j, seed, row):  # type: ignore[no-untyped-def]
    """The good slots of lane j into the output row, nearest the seed first, with the header kernel._solve writes."""
    count = candidates = within = 0
    for s in range(8):
        st = _at(w, SLOTS + SLOT * s + 7, j)
        candidates += st >= OUTSIDE
        within += st >= FAILED
        if st != GOOD:
            continue
        dist = _at(w, SLOTS + SLOT * s + 6, j)
        k = count
        while k > 0 and row[K.OUT_HEAD + K.ROW * (k - 1) + 6] > dist:
            for x in range(K.ROW):
                row[K.OUT_HEAD + K.ROW * k + x] = row[K.OUT_HEAD + K.ROW * (k - 1) + x]
            k -= 1
        for x in range(K.ROW):
            row[K.OUT_HEAD + K.ROW * k + x] = _at(w, SLOTS + SLOT * s + x, j)
        count += 1
    row[0], row[1], row[2], row[3] = count, candidates, within, K.SOLVED
    for k in range(6):
        row[K.SEED + k] = seed[k]


def solve(family: int, m: Any, targets: Any, seeds: Any, out: Any) -> float:
    """Every solution of (N,4,4) targets from (N,6) seeds into out (N, kernel.OUT_SIZE), as kernel.solve_many
    (the same status), for a model of `family` (one of FAMILIES) with its CHECK on."""
    if family not in LOOPS:
        raise ValueError(f"no lanes for family {family}")
    if not _shapes_ok(targets, seeds, out):
        return K.BAD_INPUT
    return float(LOOPS[family](m, targets, seeds, out))


# family → its compiled loop (whose cache says whether the family's lanes were compiled before)
LOOPS = {
    K.UR: _ur_loop,
    K.WRIST_23_PARALLEL: _parallel_23_loop,
    K.WRIST_12_PARALLEL: _parallel_12_loop,
    K.WRIST_12_INTERSECTING: _intersecting_12_loop,
    K.WRIST_23_INTERSECTING: _intersecting_23_loop,
}
FAMILIES = tuple(LOOPS)
