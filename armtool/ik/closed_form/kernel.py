"""`analytic`'s compiled solve: every closed-form solution of one target (or of many), checked and sorted.

The model is one float array (`families.pack` writes it; the layout is the constants below):
the family, whether the chain is solved reversed, the axes H and the offsets P of IK-Geo's
form in the base frame at q = 0 (P[0] from the base to a point on axis 1, P[i] from axis i's
point to axis i+1's, P[6] to the tip; R6T the tip's rotation), the joint limits, and the
Denavit–Hartenberg model the answers are checked with. A chain whose spherical wrist or UR-type
triple sits at the base end is solved reversed: the target inverted, the axes in reverse order
(`families.reversed_lines`), the answers turned back.

One target (`solve_one`) or many (`solve_many`, one call for the whole batch):
1. the family's position and orientation subproblems (`subproblems`) give every candidate, each
   joint as (θ, cos θ, sin θ);
2. each angle is moved by whole turns to the value nearest the seed's, then by whole turns into
   its limits if outside; a candidate with a joint that cannot be placed is dropped;
3. (exact models) the candidate's forward kinematics, by the DH model from the cosines and
   sines already at hand, must reach the target: each position component within the tolerance,
   two columns of the rotation within a bound that caps the rotation angle at the tolerance;
4. it is inserted in the output sorted by squared distance to the seed, unless a kept solution
   is within DUPLICATE rad of it on every joint.

`out` (per target): OUT_HEAD values [count, candidates, within limits, status, the seed (6), scratch], then
MAX_SOLUTIONS rows of ROW values [q (6), squared distance to the seed]. Status BAD_INPUT: a
non-finite target or seed, or wrong shapes (nothing solved).

Numba compiles this on first use and caches the machine code beside it (see `lm_kernel`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

from armtool.ik.closed_form.subproblems import (
    add,
    cross,
    dot,
    neg,
    norm,
    rot,
    rot_angle,
    rot_back,
    scale,
    sp1,
    sp2,
    sp3,
    sp4,
    sp5,
    sub,
)

# ---- families -------------------------------------------------------------------------------------------
UR = 0  # axes 2∥3∥4, axes 5 and 6 intersect (EAIK: THREE_INNER_PARALLEL)
WRIST_12_PARALLEL = 1  # spherical wrist, axes 1∥2 (SPHERICAL_FIRST_TWO_PARALLEL)
WRIST_23_PARALLEL = 2  # spherical wrist, axes 2∥3 (SPHERICAL_SECOND_TWO_PARALLEL)
WRIST_12_INTERSECTING = 3  # spherical wrist, axes 1 and 2 intersect (SPHERICAL_FIRST_TWO_INTERSECTING)
WRIST_23_INTERSECTING = 4  # spherical wrist, axes 2 and 3 intersect (SPHERICAL_SECOND_TWO_INTERSECTING)
WRIST_GENERAL = 5  # spherical wrist, first three axes in general position: SP5 (SPHERICAL_NO_PARALLEL_NO_INTERSECTING)

# ---- the model array --------------------------------------------------------------------------------------
FAMILY, REVERSED, CHECK, OVER, FLAT, TOL, ROT_TOL2 = 0, 1, 2, 3, 4, 5, 6
H = 8  # 6 axes × 3
P = 26  # 7 offsets × 3
R6T = 47  # 9, row-major
N6 = 56  # a unit vector normal to axis 6 (θ6 by sp1 on it, well conditioned at every θ5)
N2 = 59  # a unit vector normal to axis 2 (UR: θ2+θ3+θ4 where it is free)
LO, HI = 62, 68  # joint limits in the chain's order (±inf: continuous)
DH_BASE = 74  # 12: rotation (row-major) and translation of frame 0 in the chain's base frame
DH_JOINTS = 86  # 7 per joint: sign, cos(offset), sin(offset), d, a, cos α, sin α
DH_TOOL = 128  # 12: the tip in frame 6
CONST = 140  # per family: UR [h2·(p12+p23+p34+p45), h3·h2, h4·h2]; spherical [the SP4 constant of θ1 or θ3]
MODEL_SIZE = 144

OUT_HEAD = 22  # count, candidates, within limits, status, the seed (6, for the answer), scratch (real_roots4's 12)
SEED, WORK = 4, 10
ROW = 7
MAX_SOLUTIONS = 16  # a 6R arm has at most 16; the 1-D search (search.py) gave 14 on a rendered arm
OUT_SIZE = OUT_HEAD + MAX_SOLUTIONS * ROW
SOLVED, BAD_INPUT = 0.0, -1.0
DUPLICATE = 1e-9  # rad: two candidates this close on every joint are one solution (a double root's two halves)
TAU = 2.0 * math.pi


@njit(cache=True)
def _v(m, i):  # type: ignore[no-untyped-def]
    return (m[i], m[i + 1], m[i + 2])


@njit(cache=True)
def _mat_vec(R, v):  # type: ignore[no-untyped-def]
    return (
        R[0] * v[0] + R[1] * v[1] + R[2] * v[2],
        R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
        R[6] * v[0] + R[7] * v[1] + R[8] * v[2],
    )


# ---- emission: representation, limits, check, sorted insertion -------------------------------------------


@njit(cache=True)
def _place(theta, s, lo, hi):  # type: ignore[no-untyped-def]
    """θ moved by whole turns to the value nearest s, then into [lo, hi] if outside; NaN if it cannot be."""
    q = theta + TAU * math.floor((s - theta) / TAU + 0.5)
    if q < lo - 1e-9:
        q += TAU * math.ceil((lo - q) / TAU)
    elif q > hi + 1e-9:
        q -= TAU * math.ceil((q - hi) / TAU)
    if not (lo - 1e-9 <= q <= hi + 1e-9):
        return math.nan
    return min(max(q, lo), hi)


@njit(cache=True)
def _reaches(m, cs, target):  # type: ignore[no-untyped-def]
    """Whether the DH model at joint cosines and sines cs (chain order) reaches the target within the tolerance."""
    x0, x1, x2 = m[DH_BASE], m[DH_BASE + 3], m[DH_BASE + 6]  # columns of the running rotation
    y0, y1, y2 = m[DH_BASE + 1], m[DH_BASE + 4], m[DH_BASE + 7]
    z0, z1, z2 = m[DH_BASE + 2], m[DH_BASE + 5], m[DH_BASE + 8]
    p0, p1, p2 = m[DH_BASE + 9], m[DH_BASE + 10], m[DH_BASE + 11]
    for i in range(6):
        j = DH_JOINTS + 7 * i
        sign, co, so, d, a, ca, sa = m[j], m[j + 1], m[j + 2], m[j + 3], m[j + 4], m[j + 5], m[j + 6]
        cq, sq = cs[2 * i], cs[2 * i + 1]
        c = co * cq - sign * so * sq
        s = so * cq + sign * co * sq
        # Rz(θ): x ← c x + s y, y ← −s x + c y; then Tz(d) Tx(a); then Rx(α): y ← ca y + sa z, z ← −sa y + ca z
        nx0, nx1, nx2 = c * x0 + s * y0, c * x1 + s * y1, c * x2 + s * y2
        ny0, ny1, ny2 = c * y0 - s * x0, c * y1 - s * x1, c * y2 - s * x2
        p0, p1, p2 = p0 + d * z0 + a * nx0, p1 + d * z1 + a * nx1, p2 + d * z2 + a * nx2
        x0, x1, x2 = nx0, nx1, nx2
        y0, y1, y2, z0, z1, z2 = (
            ca * ny0 + sa * z0,
            ca * ny1 + sa * z1,
            ca * ny2 + sa * z2,
            ca * z0 - sa * ny0,
            ca * z1 - sa * ny1,
            ca * z2 - sa * ny2,
        )
    E = DH_TOOL
    tx = p0 + x0 * m[E + 9] + y0 * m[E + 10] + z0 * m[E + 11]
    ty = p1 + x1 * m[E + 9] + y1 * m[E + 10] + z1 * m[E + 11]
    tz = p2 + x2 * m[E + 9] + y2 * m[E + 10] + z2 * m[E + 11]
    tol = m[TOL]
    if not (
        math.fabs(target[0, 3] - tx) <= tol
        and math.fabs(target[1, 3] - ty) <= tol
        and math.fabs(target[2, 3] - tz) <= tol
    ):
        return False
    # two columns of R·E_R: ‖ΔR e0‖² + ‖ΔR e1‖² ≥ 4 sin²(angle/2) bounds the rotation error
    e00, e10, e20, e01, e11, e21 = m[E], m[E + 3], m[E + 6], m[E + 1], m[E + 4], m[E + 7]
    u0 = target[0, 0] - (x0 * e00 + y0 * e10 + z0 * e20)
    u1 = target[1, 0] - (x1 * e00 + y1 * e10 + z1 * e20)
    u2 = target[2, 0] - (x2 * e00 + y2 * e10 + z2 * e20)
    v0 = target[0, 1] - (x0 * e01 + y0 * e11 + z0 * e21)
    v1 = target[1, 1] - (x1 * e01 + y1 * e11 + z1 * e21)
    v2 = target[2, 1] - (x2 * e01 + y2 * e11 + z2 * e21)
    return u0 * u0 + u1 * u1 + u2 * u2 + v0 * v0 + v1 * v1 + v2 * v2 <= m[ROT_TOL2]


@njit(cache=True)
def _emit(m, target, seed, out, t1, t2, t3, t4, t5, t6):  # type: ignore[no-untyped-def]
    """One candidate (solver order): placed, checked and inserted into out (see the module docstring)."""
    if m[REVERSED] != 0.0:
        t1, t2, t3, t4, t5, t6 = t6, t5, t4, t3, t2, t1
    out[1] += 1.0
    q0 = _place(t1[0], seed[0], m[LO], m[HI])
    q1 = _place(t2[0], seed[1], m[LO + 1], m[HI + 1])
    q2 = _place(t3[0], seed[2], m[LO + 2], m[HI + 2])
    q3 = _place(t4[0], seed[3], m[LO + 3], m[HI + 3])
    q4 = _place(t5[0], seed[4], m[LO + 4], m[HI + 4])
    q5 = _place(t6[0], seed[5], m[LO + 5], m[HI + 5])
    q = (q0, q1, q2, q3, q4, q5)
    dist = 0.0
    for i in range(6):
        e = q[i] - seed[i]
        dist += e * e
    if dist != dist:  # a joint that cannot be placed within its limits (NaN)
        return
    out[2] += 1.0
    count = int(out[0])
    for k in range(count):  # a kept solution reached twice (a double root's two halves) is one solution
        row = OUT_HEAD + ROW * k
        same = True
        for i in range(6):
            if math.fabs(out[row + i] - q[i]) > DUPLICATE:
                same = False
                break
        if same:
            return
    if m[CHECK] != 0.0:
        cs = (t1[1], t1[2], t2[1], t2[2], t3[1], t3[2], t4[1], t4[2], t5[1], t5[2], t6[1], t6[2])
        if not _reaches(m, cs, target):
            return
    if count >= MAX_SOLUTIONS:
        return
    k = count  # insertion, nearest the seed first
    while k > 0 and out[OUT_HEAD + ROW * (k - 1) + 6] > dist:
        src, dst = OUT_HEAD + ROW * (k - 1), OUT_HEAD + ROW * k
        for i in range(ROW):
            out[dst + i] = out[src + i]
        k -= 1
    row = OUT_HEAD + ROW * k
    for i in range(6):
        out[row + i] = q[i]
    out[row + 6] = dist
    out[0] = count + 1.0


# ---- spherical wrist: θ4, θ5, θ6 from a position solution --------------------------------------------------


@njit(cache=True)
def sp4_unit(h, p, k, w, free, over, flat):  # type: ignore[no-untyped-def]
    """sp4 for unit h, p, k with d = hᵀw (w unit): the angle between h and R(k, θ)p equals that between h and w.

    Near the double root (a wrist singularity) 1 ∓ cos(θ − φ) come as products of sines of half
    angles (ψ between h and w; α between h and k, β between k and p), so θ keeps ~1e-15 rad there;
    from the cosine hᵀw alone it would keep ~1e-8 rad (half the digits). A root pair within
    √(2·flat) rad of its midpoint is one root there (a tangent solution, as sp4 merges)."""
    n, a, b = sp4(h, p, k, dot(h, w), free, over, flat)
    hk, kp = dot(h, k), dot(k, p)
    A = dot(h, p) - hk * kp
    B = dot(h, cross(k, p))
    r = math.sqrt(A * A + B * B)
    if n == -1 or r <= 1e-12:
        return n, a, b
    c0 = (dot(h, w) - hk * kp) / r
    if math.fabs(c0) < 1.0 - 1e-4:
        return n, a, b
    psi = math.atan2(norm(cross(h, w)), dot(h, w))
    al = math.atan2(norm(cross(h, k)), hk)
    be = math.atan2(norm(cross(k, p)), kp)
    one_minus = 2.0 * math.sin(0.5 * (psi + al - be)) * math.sin(0.5 * (psi - al + be)) / r
    one_plus = 2.0 * math.sin(0.5 * (al + be + psi)) * math.sin(0.5 * (al + be - psi)) / r
    if one_minus < -over or one_plus < -over:
        return 0, a, b
    half = 2.0 * math.atan2(math.sqrt(max(one_minus, 0.0)), math.sqrt(max(one_plus, 0.0)))
    phi = math.atan2(B, A)
    plus = (phi + half, math.cos(phi + half), math.sin(phi + half))
    if half * half <= 2.0 * flat:  # the pair within √(2·flat) of φ: one root, at φ
        at = (phi, math.cos(phi), math.sin(phi))
        return 1, at, at
    if (math.pi - half) ** 2 <= 2.0 * flat:  # the pair within √(2·flat) of φ + π (modulo 2π): one root there
        at = (phi + math.pi, math.cos(phi + math.pi), math.sin(phi + math.pi))
        return 1, at, at
    return 2, plus, (phi - half, math.cos(phi - half), math.sin(phi - half))


@njit(cache=True)
def _wrist(m, target, seed, ss, out, w, mv, t1, t2, t3):  # type: ignore[no-untyped-def]
    """θ4, θ5, θ6 for a position solution (θ1, θ2, θ3): R36 = (R1 R2 R3)ᵀ R06 = R4 R5 R6.

    w = R06·h6 and mv = R06·n6 (n6 ⊥ h6). θ5: h4ᵀ R5 h6 = h4ᵀ R36 h6 (sp4_unit); θ4: R4 (R5 h6) = R36 h6
    (sp1; free at the wrist singularity: the seed's); θ6 from R6 n6 = R5ᵀ R4ᵀ R36 n6 (sp1 on n6,
    well conditioned everywhere, so θ6 absorbs what θ4 leaves near the singularity)."""
    h1, h2, h3, h4, h5, h6 = _v(m, H), _v(m, H + 3), _v(m, H + 6), _v(m, H + 9), _v(m, H + 12), _v(m, H + 15)
    w3 = rot_back(h3, t3, rot_back(h2, t2, rot_back(h1, t1, w)))
    m3 = rot_back(h3, t3, rot_back(h2, t2, rot_back(h1, t1, mv)))
    n5, a5, b5 = sp4_unit(h4, h6, h5, w3, ss[4], m[OVER], m[FLAT])
    if n5 == -1:  # axis 5 ∥ axis 6 (not a wrist): nothing to solve
        return
    for j in range(n5):
        t5 = a5 if j == 0 else b5
        t4 = sp1(rot_angle(h5, t5, h6), w3, h4, ss[3])
        t6 = sp1(_v(m, N6), rot_back(h5, t5, rot_back(h4, t4, m3)), h6, ss[5])
        _emit(m, target, seed, out, t1, t2, t3, t4, t5, t6)


@njit(cache=True)
def _spherical(m, target, seed, ss, out, R06, p16):  # type: ignore[no-untyped-def]
    """Every position solution (θ1, θ2, θ3) of the wrist centre, by the family's subproblems; each
    with its wrist solutions. p16 = R1 (p12 + R2 (p23 + R3 p34)) (IK-Geo's form, o4 = o5 = o6)."""
    family = int(m[FAMILY])
    over, flat = m[OVER], m[FLAT]
    h1, h2, h3 = _v(m, H), _v(m, H + 3), _v(m, H + 6)
    p12, p23, p34 = _v(m, P + 3), _v(m, P + 6), _v(m, P + 9)
    w = _mat_vec(R06, _v(m, H + 15))
    mv = _mat_vec(R06, _v(m, N6))
    if family == WRIST_23_PARALLEL:
        # h2ᵀ R1ᵀ p16 = h2ᵀ (p12 + p23 + p34): θ1; ‖p23 + R3 p34‖ = ‖R1ᵀ p16 − p12‖: θ3; then θ2
        n1, a1, b1 = sp4(h2, p16, neg(h1), m[CONST], ss[0], over, flat)
        for i in range(max(n1, 0) if n1 != -1 else 1):
            t1 = a1 if i == 0 else b1
            v = sub(rot_back(h1, t1, p16), p12)
            n3, a3, b3 = sp3(p34, neg(p23), h3, norm(v), ss[2], over, flat)
            for j in range(max(n3, 0) if n3 != -1 else 1):
                t3 = a3 if j == 0 else b3
                t2 = sp1(add(p23, rot_angle(h3, t3, p34)), v, h2, ss[1])
                _wrist(m, target, seed, ss, out, w, mv, t1, t2, t3)
    elif family == WRIST_12_PARALLEL:
        # h1ᵀ R3 p34 = h1ᵀ (p16 − p12 − p23): θ3; ‖R1 p12 − p16‖ = ‖p23 + R3 p34‖: θ1; then θ2
        n3, a3, b3 = sp4(h1, p34, h3, dot(h1, p16) - m[CONST], ss[2], over, flat)
        for j in range(max(n3, 0) if n3 != -1 else 1):
            t3 = a3 if j == 0 else b3
            x = add(p23, rot_angle(h3, t3, p34))
            n1, a1, b1 = sp3(p12, p16, h1, norm(x), ss[0], over, flat)
            for i in range(max(n1, 0) if n1 != -1 else 1):
                t1 = a1 if i == 0 else b1
                t2 = sp1(x, sub(rot_back(h1, t1, p16), p12), h2, ss[1])
                _wrist(m, target, seed, ss, out, w, mv, t1, t2, t3)
    elif family == WRIST_12_INTERSECTING:
        # p12 = 0: ‖p23 + R3 p34‖ = ‖p16‖: θ3; R1ᵀ p16 = R2 (p23 + R3 p34): θ1, θ2 (sp2)
        n3, a3, b3 = sp3(p34, neg(p23), h3, norm(p16), ss[2], over, flat)
        for j in range(max(n3, 0) if n3 != -1 else 1):
            t3 = a3 if j == 0 else b3
            x = add(p23, rot_angle(h3, t3, p34))
            n12, s12a, s12b = sp2(p16, x, neg(h1), h2, ss[0], ss[1], over, flat)
            for i in range(n12):
                s12 = s12a if i == 0 else s12b
                _wrist(m, target, seed, ss, out, w, mv, s12[0], s12[1], t3)
    elif family == WRIST_23_INTERSECTING:
        # p23 = 0: ‖R1 p12 − p16‖ = ‖p34‖: θ1; R2ᵀ (R1ᵀ p16 − p12) = R3 p34: θ2, θ3 (sp2)
        n1, a1, b1 = sp3(p12, p16, h1, norm(p34), ss[0], over, flat)
        for i in range(max(n1, 0) if n1 != -1 else 1):
            t1 = a1 if i == 0 else b1
            v = sub(rot_back(h1, t1, p16), p12)
            n23, s23a, s23b = sp2(v, p34, neg(h2), h3, ss[1], ss[2], over, flat)
            for j in range(n23):
                s23 = s23a if j == 0 else s23b
                _wrist(m, target, seed, ss, out, w, mv, t1, s23[0], s23[1])
    else:  # WRIST_GENERAL: −p12 + R1ᵀ p16 = R2 (p23 + R3 p34), SP5
        n, sols = sp5(neg(p12), p16, p23, p34, neg(h1), h2, h3, ss[0], over, out[WORK:OUT_HEAD], flat)
        for i in range(n):
            s = sols[i]
            _wrist(m, target, seed, ss, out, w, mv, s[0], s[1], s[2])


# ---- UR-type: axes 2∥3∥4, axes 5 and 6 intersect ----------------------------------------------------------


@njit(cache=True)
def _ur_free(m, R06, v0, t1, t5, ss):  # type: ignore[no-untyped-def]
    """θ14 = θ2 + θ3 + θ4 (about h2) at the wrist singularity (R5 h6 ∥ h2), where only θ14 ± θ6 is fixed.

    θ6 is the seed's if the elbow then reaches, else the nearest θ6 it reaches: turning θ14 moves
    the point on axis 4 on a circle, ‖v(θ14)‖² = D0 + Dr cos(θ14 − β), and the elbow reaches it
    iff ‖p23 + R3 p34‖² can equal it. Returns θ14."""
    h1, h2, h3, h5, h6 = _v(m, H), _v(m, H + 3), _v(m, H + 6), _v(m, H + 12), _v(m, H + 15)
    n2 = _v(m, N2)
    p23, p34, p45 = _v(m, P + 6), _v(m, P + 9), _v(m, P + 12)
    c6, s6 = math.cos(ss[5]), math.sin(ss[5])
    # R14 = R1ᵀ R06 R6ᵀ R5ᵀ: θ14 from its image of n2 (⊥ h2)
    x = _mat_vec(R06, rot(h6, c6, -s6, rot_back(h5, t5, n2)))
    t14 = sp1(n2, rot_back(h1, t1, x), h2, 0.0)
    # ‖v‖² = |v0|² + |p45|² − 2 v0ᵀ R14 p45 with v0 = R1ᵀ p16 − p12
    q45 = sub(p45, scale(h2, dot(h2, p45)))
    A = -2.0 * (dot(v0, q45))
    B = -2.0 * dot(v0, cross(h2, q45))
    D0 = dot(v0, v0) + dot(p45, p45) - 2.0 * dot(h2, p45) * dot(h2, v0)
    Dr, beta = math.sqrt(A * A + B * B), math.atan2(B, A)
    q34 = sub(p34, scale(h3, dot(h3, p34)))
    reach0 = dot(p23, p23) + dot(p34, p34) + 2.0 * dot(h3, p34) * dot(h3, p23)
    reach_r = 2.0 * norm(sub(p23, scale(h3, dot(h3, p23)))) * norm(q34)
    lo, hi = reach0 - reach_r, reach0 + reach_r
    if Dr < 1e-12 or lo <= D0 + Dr * math.cos(t14[0] - beta) <= hi:
        return t14
    lo_c, hi_c = (lo - D0) / Dr, (hi - D0) / Dr
    if lo_c > 1.0 or hi_c < -1.0:
        return t14  # unreachable for every θ14
    g1, g2 = math.acos(min(1.0, hi_c)), math.acos(max(-1.0, lo_c))
    best, gap = t14[0], math.inf
    for cand in (beta + g1, beta - g1, beta + g2, beta - g2):
        e = cand - t14[0]
        e = math.fabs(e - TAU * math.floor(e / TAU + 0.5))
        if e < gap:
            best, gap = cand, e
    return (best, math.cos(best), math.sin(best))


@njit(cache=True)
def _ur(m, target, seed, ss, out, R06, p16):  # type: ignore[no-untyped-def]
    """Every UR-type solution (IK-Geo's three-parallel-two-intersecting decomposition).

    h2ᵀ R1ᵀ p16 = h2ᵀ (p12 + p23 + p34 + p45): θ1 (sp4); h2ᵀ R5 h6 = h2ᵀ R1ᵀ R06 h6: θ5 (sp4_unit);
    R14 R5 h6 = R1ᵀ R06 h6: θ14 = θ2 + θ3 + θ4 (sp1); R6 n6 = R5ᵀ R14ᵀ R1ᵀ R06 n6: θ6 (sp1); then the
    planar elbow: ‖p23 + R3 p34‖ = ‖v‖ with v = R1ᵀ p16 − p12 − R14 p45: θ3 (sp3), R2 (p23 + R3 p34) = v: θ2."""
    over, flat = m[OVER], m[FLAT]
    h1, h2, h3, h5, h6 = _v(m, H), _v(m, H + 3), _v(m, H + 6), _v(m, H + 12), _v(m, H + 15)
    p12, p23, p34, p45 = _v(m, P + 3), _v(m, P + 6), _v(m, P + 9), _v(m, P + 12)
    s3, s4 = m[CONST + 1], m[CONST + 2]
    w = _mat_vec(R06, h6)
    mv = _mat_vec(R06, _v(m, N6))
    n1, a1, b1 = sp4(h2, p16, neg(h1), m[CONST], ss[0], over, flat)
    for i in range(max(n1, 0) if n1 != -1 else 1):
        t1 = a1 if i == 0 else b1
        w1 = rot_back(h1, t1, w)
        v0 = sub(rot_back(h1, t1, p16), p12)
        singular = norm(cross(h2, w1)) < 1e-11
        n5, a5, b5 = sp4_unit(h2, h6, h5, w1, ss[4], over, flat)
        if singular and n5 > 1:
            n5 = 1
        for j in range(max(n5, 0) if n5 != -1 else 1):
            t5 = a5 if j == 0 else b5
            if singular:
                t14 = _ur_free(m, R06, v0, t1, t5, ss)
            else:
                t14 = sp1(rot_angle(h5, t5, h6), w1, h2, 0.0)
            t6 = sp1(_v(m, N6), rot_back(h5, t5, rot_back(h2, t14, rot_back(h1, t1, mv))), h6, ss[5])
            v = sub(v0, rot_angle(h2, t14, p45))
            n3, a3, b3 = sp3(p34, neg(p23), h3, norm(v), ss[2], over, flat)
            for k in range(max(n3, 0) if n3 != -1 else 1):
                t3 = a3 if k == 0 else b3
                t2 = sp1(add(p23, rot_angle(h3, t3, p34)), v, h2, ss[1])
                # θ4 = s4 (θ14 − θ2 − s3 θ3): its cosine and sine by the angle-sum formulas
                c23 = t2[1] * t3[1] - s3 * t2[2] * t3[2]
                s23 = t2[2] * t3[1] + s3 * t2[1] * t3[2]
                c4 = t14[1] * c23 + t14[2] * s23
                s4_ = s4 * (t14[2] * c23 - t14[1] * s23)
                t4 = (s4 * (t14[0] - t2[0] - s3 * t3[0]), c4, s4_)
                _emit(m, target, seed, out, t1, t2, t3, t4, t5, t6)


# ---- entry points ------------------------------------------------------------------------------------------


@njit(cache=True)
def target_frame(target, seed, reverse, R6T_row):  # type: ignore[no-untyped-def]
    """The target's rotation (9-tuple, row-major) and position and the seed in the solver's order
    (reversed chain: T⁻¹ and the seed backwards), and R06 = R · R6ᵀ with R6T_row the tip's rotation
    at q = 0 (row-major): shared by this kernel and the 1-D search (search.py)."""
    Rt = (
        target[0, 0],
        target[0, 1],
        target[0, 2],
        target[1, 0],
        target[1, 1],
        target[1, 2],
        target[2, 0],
        target[2, 1],
        target[2, 2],
    )
    pt = (target[0, 3], target[1, 3], target[2, 3])
    if reverse:  # solve T⁻¹ on the reversed chain
        Rt = (Rt[0], Rt[3], Rt[6], Rt[1], Rt[4], Rt[7], Rt[2], Rt[5], Rt[8])
        pt = neg(_mat_vec(Rt, pt))
        ss = (seed[5], seed[4], seed[3], seed[2], seed[1], seed[0])
    else:
        ss = (seed[0], seed[1], seed[2], seed[3], seed[4], seed[5])
    T = R6T_row
    R06 = (
        Rt[0] * T[0] + Rt[1] * T[1] + Rt[2] * T[2],
        Rt[0] * T[3] + Rt[1] * T[4] + Rt[2] * T[5],
        Rt[0] * T[6] + Rt[1] * T[7] + Rt[2] * T[8],
        Rt[3] * T[0] + Rt[4] * T[1] + Rt[5] * T[2],
        Rt[3] * T[3] + Rt[4] * T[4] + Rt[5] * T[5],
        Rt[3] * T[6] + Rt[4] * T[7] + Rt[5] * T[8],
        Rt[6] * T[0] + Rt[7] * T[1] + Rt[8] * T[2],
        Rt[6] * T[3] + Rt[7] * T[4] + Rt[8] * T[5],
        Rt[6] * T[6] + Rt[7] * T[7] + Rt[8] * T[8],
    )
    return Rt, pt, ss, R06


@njit(cache=True)
def _solve(m, target, seed, out):  # type: ignore[no-untyped-def]
    for i in range(4):
        out[i] = 0.0
    for i in range(6):
        out[SEED + i] = seed[i]
        if not math.isfinite(seed[i]):
            out[3] = BAD_INPUT
            return
    for r in range(4):
        for c in range(4):
            if not math.isfinite(target[r, c]):
                out[3] = BAD_INPUT
                return
    _Rt, pt, ss, R06 = target_frame(target, seed, m[REVERSED] != 0.0, m[R6T : R6T + 9])
    p16 = sub(sub(pt, _v(m, P)), _mat_vec(R06, _v(m, P + 18)))
    if int(m[FAMILY]) == UR:
        _ur(m, target, seed, ss, out, R06, p16)
    else:
        _spherical(m, target, seed, ss, out, R06, p16)


@njit(cache=True)
def solve_one(m, target, seed, out):  # type: ignore[no-untyped-def]
    """Every solution of one target (4×4) from one seed (6,) into out (OUT_SIZE,); returns the status."""
    if target.shape[0] != 4 or target.shape[1] != 4 or seed.shape[0] != 6 or out.shape[0] < OUT_SIZE:
        return BAD_INPUT
    _solve(m, target, seed, out)
    return out[3]


@njit(cache=True)
def solve_many(m, targets, seeds, out):  # type: ignore[no-untyped-def]
    """solve_one for (N,4,4) targets and (N,6) seeds into out (N, OUT_SIZE): one call for the batch."""
    n = targets.shape[0]
    if targets.shape[1] != 4 or targets.shape[2] != 4 or seeds.shape[0] != n or seeds.shape[1] != 6:
        return BAD_INPUT
    if out.shape[0] != n or out.shape[1] < OUT_SIZE:
        return BAD_INPUT
    status = SOLVED
    for i in range(n):
        _solve(m, targets[i], seeds[i], out[i])
        if out[i, 3] == BAD_INPUT:
            status = BAD_INPUT
    return status


@njit(cache=True)
def gather_solutions(out, counts, Q):  # type: ignore[no-untyped-def]
    """Each row of solve_many's `out`: its count into counts (N,) and its solutions into Q
    (N, MAX_SOLUTIONS, 6), NaN past the count. Why compiled: the same with NumPy (a mask, then
    np.where over Q) took 0.22 µs per target, a third of a spherical-wrist batch's time; this,
    0.03 µs (1000 targets, measured here)."""
    for i in range(out.shape[0]):
        c = int(out[i, 0])
        counts[i] = c
        for k in range(MAX_SOLUTIONS):
            base = OUT_HEAD + k * ROW
            for j in range(6):
                Q[i, k, j] = out[i, base + j] if k < c else math.nan


def empty_out(count: int | None = None) -> NDArray[np.float64]:
    """An output buffer for solve_one (count None) or solve_many."""
    return np.empty(OUT_SIZE if count is None else (count, OUT_SIZE))
