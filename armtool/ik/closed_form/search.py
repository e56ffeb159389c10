"""Every IK solution of a 6R arm with no closed form, by a 1-D search over one joint (IK-Geo's way).

Which arms. 6R chains whose axes 4 and 5 intersect and whose axes 2 and 3 are parallel (or the
same read from the tip: axes 2∩3, 4∥5) but whose wrist is not spherical: axis 6 offset (xArm6),
or axes 4∩5 and 5∩6 meeting in two points (Kinova Gen3 lite). EAIK reports no decomposition for
them; IK-Geo's own 1-D search ("two intersecting" / "two parallel" classes, Elias & Wen 2022 §V,
1000 samples) reaches them only to ~1e-4 here.

How (solver order; the chain reversed when the pair is at the base end):
1. Given θ6, the frame after joint 5 is known, hence the point where axes 4 and 5 meet (it moves with
   neither joint): p16(θ6) = p_target − p01 − R06·p6T − R06·R6ᵀ·p56 = R1 p12 + R1R2 p23 + R1R2R3 p34,
   the spherical-wrist family "axes 2∥3"'s position problem: SP4 for θ1, SP3 for θ3, SP1 for θ2.
   Its four branches are the slots 2·(θ1 root) + (θ3 root); where a branch does not reach, the
   subproblems return their least-squares continuation (cosines clamped), so a slot is continuous.
2. The orientation left, R4·R5 = R3ᵀR2ᵀR1ᵀ·R06·R6ᵀ, has two joints for three degrees of freedom:
   the error e(θ6) = h4ᵀ·(R3ᵀR2ᵀR1ᵀ R06 R6ᵀ h5) − h4ᵀh5 vanishes exactly at the solutions (R4 keeps
   the component along h4).
3. e is sampled at SAMPLES points of the circle per slot, with each slot's reach margin (1 − |cos|
   of its SP4 and SP3: negative where it is clamped). Between two reaching samples, a sign change is
   refined by the Illinois method; a local minimum of |e| without one (two roots closer than a step,
   or a tangent root) is tested at its parabola's vertex. Between a reaching and a clamped sample the
   reach boundary is found first (Illinois on the margin), then the reaching part is searched: near
   it a branch's e behaves as a square root, and roots there sit where no sample sees them.
   Intervals clamped at both ends hold no solution and are skipped. Before that, a margin whose
   |margin| has a small sampled local minimum is descended until it changes sign (_dips): near a
   wrist or shoulder singularity a branch can exist between two clamped samples only, or vanish
   between two reaching ones (UR10, bench target 34), and the point found joins the grid. The
   samples form no angle (cosines and sines only, θ6's by rotation, the subproblems' coefficients
   that do not depend on θ6 computed once): they are most of the work.
4. Each root gives θ1..θ3 (its slot), θ4 = SP1(h5 → R45 h5 about h4), θ5 = SP1 about h5; then up to
   POLISH_STEPS Newton steps on the full 6-D pose residual of the real chain (its axis lines, not the
   model), so that every solution is exact to machine precision, and a chain whose structure holds
   only within SNAP_TOL (Gen3 lite: axes 2∥3 within 3.7e-6 rad) still gets its own solutions.
   The polished pose must be within the tolerance on every component of verify()'s error.
5. The kernel's emission (`kernel._emit`, its DH check off) places each angle, drops those outside
   the limits, merges duplicates and sorts by distance to the seed: `out` has kernel.solve_one's
   layout, so `analytic` reads both alike.

The model array: kernel's layout (the emission's fields: limits, tolerance) followed by this
module's (offsets below).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armtool.errors import ArmtoolError
from armtool.ik.closed_form import kernel as K
from armtool.ik.closed_form.families import reversed_lines
from armtool.ik.closed_form.geometry import Line, any_normal, axis_lines, closest, distance, parallel
from armtool.ik.closed_form.kernel import _mat_vec, _v
from armtool.ik.closed_form.subproblems import (
    TINY,
    add,
    angle_of,
    cross,
    dot,
    neg,
    norm,
    rot,
    rot_back,
    scale,
    sp1,
    sub,
)
from armtool.ik.solver import Array
from armtool.model.chain import Chain

SAMPLES = 64  # θ6 samples on the circle per target (measured: benchmarks/ik_search.py)
SNAP_TOL = 1e-4  # rad / m: axes this close to intersecting / parallel are solved on the exact model, then polished
POLISH_STEPS = 8  # Newton steps on the real chain per root (1-2 where the model is the chain)
POLISH_GOAL = 1e-14  # m / rad: a polished residual this small stops the steps
VERTEX_STEPS = 12  # steps towards a local minimum of |e| that may hide two roots
DIP_GAP = 0.05  # a reach margin whose sampled local minimum of |margin| is below this is descended: it may change sign
CLOSE_GAP = 0.05  # |e| at a sampled local minimum below this is searched for two close roots
VERTEX_GAP = 1e-3  # |e| at a parabola's vertex below this is tried as a (double) root: polishing decides
STEEP = 0.2  # an error change between samples beyond this (of one sign) is sampled SPLIT times finer
SPLIT = 8
PAIR_SAMPLES = 8  # samples of a branch pair's curve at a reach boundary
ROOT_STEP = 1e-7  # rad: a bracket's refinement stops at a step this small; Newton on the chain does the rest
WORK_COLUMNS = 25  # _polish's scratch: J (6), its augmented copy (7), axes (3), points (3), R (3), e, dq, q
LIMIT_SLACK = 1e-3  # rad: an unpolished joint this far outside its limits may still end inside
WIDE = 1e300  # `over` for the position subproblems: never refuse, clamp (least-squares continuation)

# ---- this module's part of the model array (after kernel's MODEL_SIZE) -------------------------------------
S = K.MODEL_SIZE
S_REVERSED, S_SAMPLES, S_SIGN3, S_CONST = S, S + 1, S + 2, S + 3  # S_SIGN3: h3 = ±h2; S_CONST: h2ᵀ(p12 + p23 + p34)
S_H = S + 4  # the model's axes, solver order (6 × 3)
S_P = S_H + 18  # the model's offsets (7 × 3): P[4] = 0 (axes 4, 5 meet)
S_R6T = S_P + 21  # the model's tip rotation at q = 0 (9)
S_N5 = S_R6T + 9  # a unit normal of h5
S_LP = S_N5 + 3  # the real chain's axis points, chain order (6 × 3)
S_LW = S_LP + 18  # the real chain's axis directions (6 × 3)
S_TIP = S_LW + 18  # the real chain's tip at q = 0: rotation (9, row-major), translation (3)
S_T1 = S_TIP + 12  # θ1's SP4 coefficients A, B, C = a·p16 (3 × 3: a for A, B, C)
S_T3 = S_T1 + 9  # θ3's SP4 (constant): C, A, B (both 0: degenerate, solved in general), its reach constant
S_T2 = S_T3 + 4  # θ2's SP1: p23 + R3 p34 = U + c3 V + s3 W and h2 × (p23 + R3 p34) alike (6 × 3)
S_E = S_T2 + 18  # the orientation error: h4 × h2 (3), h4ᵀh2, h4ᵀh5
SEARCH_MODEL_SIZE = S_E + 5


@njit(cache=True, inline="always")
def _roots_cs(A, B, d, C, p, free):  # type: ignore[no-untyped-def]
    """The roots of A cos θ + B sin θ + C = d (sp4's form, `over` unbounded) as cosines and sines, no
    angle formed (the samples need none): (margin, cos θ₊, sin θ₊, cos θ₋, sin θ₋).

    θ = φ ± a with cos a clamped to ±1 where it lies beyond (the least-squares continuation, both
    roots φ or φ + π); the margin 1 − |cos a| before clamping: > 0 two roots, < 0 none (the clamped
    side). Where A and B vanish (relative to d and the vector p turned), both roots are `free`
    (sp4's "every θ") or 0 (its "none")."""
    r = math.sqrt(A * A + B * B)
    margin = 1.0 if r <= 1e-300 else 1.0 - math.fabs((d - C) / r)
    if r <= 1e-6 * (1.0 + math.fabs(d)) and r <= TINY * (1.0 + math.fabs(d)) * (1.0 + norm(p)):
        if math.fabs(d - C) <= 1e-9 * (1.0 + norm(p)):
            c, s = math.cos(free), math.sin(free)
            return margin, c, s, c, s
        return margin, 1.0, 0.0, 1.0, 0.0
    c0 = min(max((d - C) / r, -1.0), 1.0)
    cf, sf = A / r, B / r
    sa = math.sqrt((1.0 - c0) * (1.0 + c0))
    return margin, cf * c0 - sf * sa, sf * c0 + cf * sa, cf * c0 + sf * sa, sf * c0 - cf * sa


@njit(cache=True)
def _sp4_cs(h, p, k, d, free):  # type: ignore[no-untyped-def]
    """sp4(h, p, k, d) as _roots_cs: hᵀR(k,θ)p = A cos θ + B sin θ + C, A = hᵀp⊥, B = hᵀ(k×p), C = (hᵀk)(kᵀp)."""
    hk, kp = dot(h, k), dot(k, p)
    return _roots_cs(dot(h, p) - hk * kp, dot(h, cross(k, p)), d, hk * kp, p, free)


@njit(cache=True)
def _terms(m, R06, pt):  # type: ignore[no-untyped-def]
    """What θ6 enters linearly, once per target: p16(θ6) = P0 + cos θ6·P1 + sin θ6·P2 (the 4∩5 point
    from axis 1) and x(θ6) = X0 + cos θ6·X1 + sin θ6·X2 (R06·R6ᵀ·h5), since R(h6, −θ6)·v =
    (h6ᵀv)h6 + cos θ6 (v − (h6ᵀv)h6) − sin θ6 (h6 × v); and θ1's SP4 coefficients A, B, C, each
    a·p16 with a fixed vector a (S_T1), as (value, cos θ6 part, sin θ6 part) × 3."""
    h5, h6 = _v(m, S_H + 12), _v(m, S_H + 15)
    p01, p56, p6t = _v(m, S_P), _v(m, S_P + 15), _v(m, S_P + 18)
    a56, a5 = scale(h6, dot(h6, p56)), scale(h6, dot(h6, h5))
    P0 = sub(sub(sub(pt, p01), _mat_vec(R06, p6t)), _mat_vec(R06, a56))
    P1 = neg(_mat_vec(R06, sub(p56, a56)))
    P2 = _mat_vec(R06, cross(h6, p56))
    X0 = _mat_vec(R06, a5)
    X1 = _mat_vec(R06, sub(h5, a5))
    X2 = neg(_mat_vec(R06, cross(h6, h5)))
    a, b, c = _v(m, S_T1), _v(m, S_T1 + 3), _v(m, S_T1 + 6)
    L = (dot(a, P0), dot(a, P1), dot(a, P2), dot(b, P0), dot(b, P1), dot(b, P2), dot(c, P0), dot(c, P1), dot(c, P2))
    return P0, P1, P2, X0, X1, X2, L


@njit(cache=True, inline="always")
def _lin(a, b, d, c, s):  # type: ignore[no-untyped-def]
    """a + c·b + s·d: a vector of _terms (or of the model's θ2 terms) at the cosine c and sine s of its angle."""
    return (a[0] + c * b[0] + s * d[0], a[1] + c * b[1] + s * d[1], a[2] + c * b[2] + s * d[2])


# ---- one value of θ6: the four position branches and their orientation errors ---------------------------


@njit(cache=True)
def _branches(m, T, c6, s6, ss, only):  # type: ignore[no-untyped-def]
    """At θ6 (its cosine and sine), for every slot (or slot `only`, if 0-3; or, if 4-7, slot only − 4's
    margin alone): its (θ1, θ2, θ3) as cosines
    and sines, orientation error and reach margin: ((c1, s1, c2, s2, c3, s3) of slot `only` (or of
    slot 3), (e × 4), (margin × 4), θ1's margin); slots not computed: NaN, and so are, when
    sampling (`only` < 0), the errors of slots that do not reach (never read). A slot's margin is the
    smaller of θ1's and its θ3's. No angle is formed (no atan2), and what does not depend on θ6 is
    computed once (pack: S_T3, S_T2, S_E; _terms): the samples are most of the work."""
    h1, h2, h3, h4 = _v(m, S_H), _v(m, S_H + 3), _v(m, S_H + 6), _v(m, S_H + 9)
    p12, p23, p34 = _v(m, S_P + 3), _v(m, S_P + 6), _v(m, S_P + 9)
    p16, x, L = _lin(T[0], T[1], T[2], c6, s6), _lin(T[3], T[4], T[5], c6, s6), T[6]
    # h2ᵀ R1ᵀ p16 = h2ᵀ (p12 + p23 + p34): θ1; ‖p23 + R3 p34‖ = ‖R1ᵀ p16 − p12‖: θ3; then θ2
    A1, B1, C1 = L[0] + c6 * L[1] + s6 * L[2], L[3] + c6 * L[4] + s6 * L[5], L[6] + c6 * L[7] + s6 * L[8]
    margin1, ca, sa, cb, sb = _roots_cs(A1, B1, m[S_CONST], C1, p16, ss[0])
    C3, A3, B3, REACH3 = m[S_T3], m[S_T3 + 1], m[S_T3 + 2], m[S_T3 + 3]
    W = (_v(m, S_T2), _v(m, S_T2 + 3), _v(m, S_T2 + 6), _v(m, S_T2 + 9), _v(m, S_T2 + 12), _v(m, S_T2 + 15))
    h42, c42, c45, sign3 = _v(m, S_E), m[S_E + 3], m[S_E + 4], m[S_SIGN3]
    nan = math.nan
    e0 = e1 = e2 = e3 = g0 = g1 = g2 = g3 = nan
    sol = (ca, sa, ca, sa, ca, sa)
    if only < 0 and margin1 < 0.0:  # a sample where no slot reaches: its errors are never read (NaN)
        return sol, (nan, nan, nan, nan), (margin1, margin1, margin1, margin1), margin1
    want = only % 4 if only >= 0 else -1  # only ≥ 4: slot only − 4, its margin alone (_reach)
    for i in range(2):
        if want >= 0 and want // 2 != i:
            continue
        c1, s1 = (ca, sa) if i == 0 else (cb, sb)
        v = sub(rot(h1, c1, -s1, p16), p12)
        w = rot(h1, c1, -s1, x)
        d3 = REACH3 - 0.5 * dot(v, v)
        if A3 != 0.0 or B3 != 0.0:  # θ3's SP4 with its constant coefficients (pack)
            margin3, c3a, s3a, c3b, s3b = _roots_cs(A3, B3, d3, C3, p34, ss[2])
        else:
            margin3, c3a, s3a, c3b, s3b = _sp4_cs(neg(p23), p34, h3, d3, ss[2])
        margin = min(margin1, margin3)
        if (only < 0 and margin < 0.0) or only >= 4:  # margins only: clamped samples, or _reach
            if i == 0:
                g0 = g1 = margin
            else:
                g2 = g3 = margin
            continue
        # e = h4ᵀ R(h2, −φ) w − h4ᵀh5 = γ − h4ᵀh5 + cos φ (α − γ) − sin φ β, φ = θ2 + σθ3
        alpha, beta, gamma, hv = dot(h4, w), dot(w, h42), dot(h2, w) * c42, dot(h2, v)
        for j in range(2):
            k = 2 * i + j
            if want >= 0 and want != k:
                continue
            c3, s3 = (c3a, s3a) if j == 0 else (c3b, s3b)
            # θ2 = sp1(p23 + R3 p34, v, h2), with p23 + R3 p34 = U + c3 V + s3 W and h2 × it alike (S_T2)
            q = _lin(W[0], W[1], W[2], c3, s3)
            hq = _lin(W[3], W[4], W[5], c3, s3)
            xx = dot(q, v) - dot(h2, q) * hv
            yy = dot(hq, v)
            r = math.sqrt(xx * xx + yy * yy)
            if r <= TINY * (dot(q, q) + dot(v, v)):
                c2, s2 = math.cos(ss[1]), math.sin(ss[1])
            else:
                c2, s2 = xx / r, yy / r
            # h3 = σ h2 (the model's axes 2∥3): R3ᵀ R2ᵀ = R(h2, −(θ2 + σ θ3))
            cphi = c2 * c3 - sign3 * s2 * s3
            sphi = s2 * c3 + sign3 * c2 * s3
            ek = gamma - c45 + cphi * (alpha - gamma) - sphi * beta
            if k == 0:
                e0, g0 = ek, margin
            elif k == 1:
                e1, g1 = ek, margin
            elif k == 2:
                e2, g2 = ek, margin
            else:
                e3, g3 = ek, margin
            sol = (c1, s1, c2, s2, c3, s3)
    return sol, (e0, e1, e2, e3), (g0, g1, g2, g3), margin1


@njit(cache=True)
def _error(m, R06, T, theta, ss, k):  # type: ignore[no-untyped-def]
    return _branches(m, T, math.cos(theta), math.sin(theta), ss, k)[1][k]


@njit(cache=True)
def _reach(m, R06, T, theta, ss, k):  # type: ignore[no-untyped-def]
    return _branches(m, T, math.cos(theta), math.sin(theta), ss, k + 4)[2][k]


@njit(cache=True)
def _pair(m, R06, T, ss, k, partner, tb, side, u):  # type: ignore[no-untyped-def]
    """The error along two slots that meet at a reach boundary tb, as one smooth curve: θ = tb + side·u²,
    slot k for u ≥ 0, its partner for u < 0 (each branch goes as a square root of the distance to tb)."""
    return _error(m, R06, T, tb + side * u * u, ss, k if u >= 0.0 else partner)


@njit(cache=True)
def _f(m, R06, T, ss, k, mode, partner, tb, side, x):  # type: ignore[no-untyped-def]
    if mode == 0:
        return _error(m, R06, T, x, ss, k)
    if mode == 1:
        return _reach(m, R06, T, x, ss, k)
    return _pair(m, R06, T, ss, k, partner, tb, side, x)


@njit(cache=True)
def _illinois(m, R06, T, ss, k, a, b, fa, fb, mode, partner, tb, side):  # type: ignore[no-untyped-def]
    """The root in [a, b], where it changes sign, of slot k's error (mode 0), its reach margin (1), or
    a slot pair's error at a reach boundary (2, see _pair): Illinois (regula falsi that halves the
    value kept at an end retained twice; superlinear)."""
    last = 0
    c = a
    for _ in range(80):
        prev = c
        c = (a * fb - b * fa) / (fb - fa)
        if not (a <= c <= b):
            c = 0.5 * (a + b)
        fc = _f(m, R06, T, ss, k, mode, partner, tb, side, c)
        if fc != fc:
            return math.nan
        if fc == 0.0 or math.fabs(c - prev) <= ROOT_STEP:
            return c
        if (fc < 0.0) == (fb < 0.0):
            b, fb = c, fc
            if last == -1:
                fa *= 0.5
            last = -1
        else:
            a, fa = c, fc
            if last == 1:
                fb *= 0.5
            last = 1
    return c


@njit(cache=True)
def _descend(m, R06, T, ss, k, x0, x1, x2, f0, f1, f2, mode, partner, tb, side):  # type: ignore[no-untyped-def]
    """Towards the minimum of |f| (mode: as _illinois) between x0 and x2, where |f1| is smallest of the
    three and all are of one sign: parabolic steps, golden-section ones where a parabola does not help,
    at most VERTEX_STEPS, until f changes sign. (v, f(v)) the first point of the other sign (NaN if
    none), and the last three points."""
    for _ in range(VERTEX_STEPS):
        den = (x1 - x0) * (f1 - f2) - (x1 - x2) * (f1 - f0)
        v = x1 - 0.5 * ((x1 - x0) ** 2 * (f1 - f2) - (x1 - x2) ** 2 * (f1 - f0)) / den if den != 0.0 else x1
        lo, hi = x0 + 0.1 * (x1 - x0), x2 - 0.1 * (x2 - x1)
        if not (lo < v < hi) or math.fabs(v - x1) < 1e-3 * (x2 - x0):
            v = x1 + 0.382 * (x2 - x1) if x2 - x1 > x1 - x0 else x1 - 0.382 * (x1 - x0)  # golden section
        fv = _f(m, R06, T, ss, k, mode, partner, tb, side, v)
        if fv != fv:
            break
        if (fv < 0.0) != (f1 < 0.0) and fv != 0.0:
            return v, fv, x0, x1, x2, f0, f1, f2
        if math.fabs(fv) < math.fabs(f1):  # v the new middle
            if v < x1:
                x1, x2, f1, f2 = v, x1, fv, f1
            else:
                x0, x1, f0, f1 = x1, v, f1, fv
        elif v < x1:
            x0, f0 = v, fv
        else:
            x2, f2 = v, fv
        if x2 - x0 < 1e-9:
            break
    return math.nan, math.nan, x0, x1, x2, f0, f1, f2


@njit(cache=True)
def _close_pair(m, R06, T, ss, k, x0, x1, x2, f0, f1, f2, mode, partner, tb, side):  # type: ignore[no-untyped-def]
    """Up to two roots near x1, where |f| (mode: as _illinois) has a local minimum of one sign between
    x0 and x2: |f| minimised (_descend) until f changes sign (two brackets) or its minimum is below
    VERTEX_GAP (a tangent root, for polishing to decide); none where |f| is CLOSE_GAP or more."""
    if math.fabs(f1) >= CLOSE_GAP:
        return (math.nan, math.nan)  # a minimum far from zero: no root nearby
    v, fv, x0, x1, x2, f0, f1, f2 = _descend(m, R06, T, ss, k, x0, x1, x2, f0, f1, f2, mode, partner, tb, side)
    if v == v:
        return (
            _illinois(m, R06, T, ss, k, x0, v, f0, fv, mode, partner, tb, side),
            _illinois(m, R06, T, ss, k, v, x2, fv, f2, mode, partner, tb, side),
        )
    if math.fabs(f1) < VERTEX_GAP:
        # a tangent root, or two roots the model (within SNAP_TOL of the chain) merged into none: Newton
        # on the chain starts from either side, where the parabola through the last three points is 2|f1|
        c2 = 2.0 * math.fabs(((f2 - f1) / (x2 - x1) - (f1 - f0) / (x1 - x0)) / (x2 - x0))
        h = math.sqrt(2.0 * math.fabs(f1) / c2) if c2 > 0.0 else 0.0
        if not h > 1e-9:
            return (x1, math.nan)
        return (x1 - h, x1 + h)
    return (math.nan, math.nan)


@njit(cache=True)
def _boundary(m, target, seed, out, work, R06, T, ss, k, partner, a, b, ga, gb):  # type: ignore[no-untyped-def]
    """Every root of slots k and partner in [a, b], where their branch pair reaches on one side of a
    boundary only: the boundary tb first (Illinois on the margin), then the pair's curve (_pair) in
    u ∈ [−√L, √L] (L the reaching length), sampled at PAIR_SAMPLES points, sign changes refined.
    Where the sample beyond the reaching end is clamped too, the pair's curve there is the clamped
    continuation: its roots do not reach, and the polish drops them."""
    tb = _illinois(m, R06, T, ss, k, a, b, ga, gb, 1, 0, 0.0, 0.0)
    if tb != tb:
        return
    side = -1.0 if ga >= 0.0 else 1.0  # the reaching side: θ = tb + side·u²
    # the reaching length: to the reaching end and one step beyond (the square-root part of a branch
    # reaches further than a sample; roots found twice are merged by the emission)
    far = math.sqrt(max(tb - a if ga >= 0.0 else b - tb, 0.0) + (b - a))
    ends = _pair(m, R06, T, ss, k, partner, tb, side, far)
    us = np.empty(PAIR_SAMPLES + 1)
    fs = np.empty(PAIR_SAMPLES + 1)
    for i in range(PAIR_SAMPLES + 1):
        us[i] = -far + 2.0 * far * i / PAIR_SAMPLES
        fs[i] = ends if i == PAIR_SAMPLES else _pair(m, R06, T, ss, k, partner, tb, side, us[i])
    _scan(m, target, seed, out, work, R06, T, ss, k, us, fs, 2, partner, tb, side)


@njit(cache=True)
def _steep(m, target, seed, out, work, R06, T, ss, k, a, b, fa, fb):  # type: ignore[no-untyped-def]
    """An interval where slot k's error changes by more than STEEP without changing sign (θ1 spins fast
    where the wrist point passes near axis 1): sampled at SPLIT sub-intervals and scanned."""
    xs = np.empty(SPLIT + 1)
    fs = np.empty(SPLIT + 1)
    for i in range(SPLIT + 1):
        xs[i] = a + (b - a) * i / SPLIT
        fs[i] = fa if i == 0 else (fb if i == SPLIT else _error(m, R06, T, xs[i], ss, k))
    _scan(m, target, seed, out, work, R06, T, ss, k, xs, fs, 0, 0, 0.0, 0.0)


@njit(cache=True)
def _scan(m, target, seed, out, work, R06, T, ss, k, xs, fs, mode, partner, tb, side):  # type: ignore[no-untyped-def]
    """Every root of f (mode: as _illinois) on a grid xs with values fs: sign changes refined, sampled
    minima of |f| of one sign searched for a close pair (_close_pair); each root finished."""
    n = len(xs) - 1
    for i in range(n):
        roots = (math.nan, math.nan)
        if fs[i] == 0.0:
            roots = (xs[i], math.nan)
        elif (fs[i] < 0.0) != (fs[i + 1] < 0.0) and fs[i + 1] != 0.0:
            roots = (
                _illinois(m, R06, T, ss, k, xs[i], xs[i + 1], fs[i], fs[i + 1], mode, partner, tb, side),
                math.nan,
            )
        elif i + 2 <= n:
            f0, f1, f2 = fs[i], fs[i + 1], fs[i + 2]
            if (f2 < 0.0) == (f1 < 0.0) and math.fabs(f1) <= math.fabs(f0) and math.fabs(f1) < math.fabs(f2):
                roots = _close_pair(m, R06, T, ss, k, xs[i], xs[i + 1], xs[i + 2], f0, f1, f2, mode, partner, tb, side)
        for root in roots:
            if root == root:
                if mode == 2:
                    t6 = angle_of(tb + side * root * root)
                    slot = k if root >= 0.0 else partner
                else:
                    t6, slot = angle_of(root), k
                _finish(m, target, seed, out, work, R06, t6, _branches(m, T, t6[1], t6[2], ss, slot)[0], ss)


@njit(cache=True)
def _fk_jacobian(m, q, J, ws, os_):  # type: ignore[no-untyped-def]
    """The real chain's tip pose (rotation row-major (9), position) at q (chain order), and its
    world-aligned Jacobian at the tip into J (6 × 6: rows linear then angular)."""
    R = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    p = (0.0, 0.0, 0.0)
    for i in range(6):
        o, w = _v(m, S_LP + 3 * i), _v(m, S_LW + 3 * i)
        wi = _mat_vec(R, w)
        oi = add(_mat_vec(R, o), p)
        for r in range(3):
            ws[i, r] = wi[r]
            os_[i, r] = oi[r]
        c, s = math.cos(q[i]), math.sin(q[i])
        # T ← T · [Rot(w, q), o − Rot(w, q) o]: the columns of R turned about wi (in the world)
        c0 = rot(wi, c, s, (R[0], R[3], R[6]))
        c1 = rot(wi, c, s, (R[1], R[4], R[7]))
        c2 = rot(wi, c, s, (R[2], R[5], R[8]))
        p = add(oi, rot(wi, c, s, sub(p, oi)))
        R = (c0[0], c1[0], c2[0], c0[1], c1[1], c2[1], c0[2], c1[2], c2[2])
    E = S_TIP
    tip = (m[E + 9], m[E + 10], m[E + 11])
    pt = add(_mat_vec(R, tip), p)
    Rt = (
        R[0] * m[E] + R[1] * m[E + 3] + R[2] * m[E + 6],
        R[0] * m[E + 1] + R[1] * m[E + 4] + R[2] * m[E + 7],
        R[0] * m[E + 2] + R[1] * m[E + 5] + R[2] * m[E + 8],
        R[3] * m[E] + R[4] * m[E + 3] + R[5] * m[E + 6],
        R[3] * m[E + 1] + R[4] * m[E + 4] + R[5] * m[E + 7],
        R[3] * m[E + 2] + R[4] * m[E + 5] + R[5] * m[E + 8],
        R[6] * m[E] + R[7] * m[E + 3] + R[8] * m[E + 6],
        R[6] * m[E + 1] + R[7] * m[E + 4] + R[8] * m[E + 7],
        R[6] * m[E + 2] + R[7] * m[E + 5] + R[8] * m[E + 8],
    )
    for i in range(6):
        wi = (ws[i, 0], ws[i, 1], ws[i, 2])
        lin = cross(wi, sub(pt, (os_[i, 0], os_[i, 1], os_[i, 2])))
        for r in range(3):
            J[r, i] = lin[r]
            J[3 + r, i] = wi[r]
    return Rt, pt


@njit(cache=True)
def _residual(target, Rt, pt, M):  # type: ignore[no-untyped-def]
    """[p_target − p; ω] with ω the rotation vector of R_target·Rᵀ (exact log: Newton keeps quadratic)."""
    # M = R_target Rᵀ
    for r in range(3):
        for c in range(3):
            M[r, c] = target[r, 0] * Rt[3 * c] + target[r, 1] * Rt[3 * c + 1] + target[r, 2] * Rt[3 * c + 2]
    vx, vy, vz = M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]
    sin2 = math.sqrt(vx * vx + vy * vy + vz * vz)  # 2 sin(angle)
    cos2 = M[0, 0] + M[1, 1] + M[2, 2] - 1.0  # 2 cos(angle)
    angle = math.atan2(sin2, cos2)
    f = 0.5 if sin2 < 1e-12 else angle / sin2
    return (target[0, 3] - pt[0], target[1, 3] - pt[1], target[2, 3] - pt[2], f * vx, f * vy, f * vz)


@njit(cache=True)
def _solve6(J, e, A, x):  # type: ignore[no-untyped-def]
    """x with J x = e into x (Gaussian elimination with partial pivoting on A, 6 × 7); False if singular."""
    for r in range(6):
        for c in range(6):
            A[r, c] = J[r, c]
        A[r, 6] = e[r]
    for c in range(6):
        piv = c
        for r in range(c + 1, 6):
            if math.fabs(A[r, c]) > math.fabs(A[piv, c]):
                piv = r
        if math.fabs(A[piv, c]) < 1e-14:
            return False
        if piv != c:
            for k in range(7):
                A[c, k], A[piv, k] = A[piv, k], A[c, k]
        for r in range(c + 1, 6):
            f = A[r, c] / A[c, c]
            for k in range(c, 7):
                A[r, k] -= f * A[c, k]
    for r in range(5, -1, -1):
        v = A[r, 6]
        for k in range(r + 1, 6):
            v -= A[r, k] * x[k]
        x[r] = v / A[r, r]
    return True


@njit(cache=True)
def _polish(m, target, q, work):  # type: ignore[no-untyped-def]
    """Newton steps on the real chain's pose residual from q (chain order, changed in place); the
    largest residual component at the q it leaves (verify()'s error: [Δp; log(R_target Rᵀ)]).
    `work`: scratch (6 × WORK_COLUMNS), allocated once per target."""
    J, A, ws, os_ = work[:, :6], work[:, 6:13], work[:, 13:16], work[:, 16:19]
    M, e, dq = work[:3, 19:22], work[:, 22], work[:, 23]
    big = math.inf
    for step in range(POLISH_STEPS + 1):
        Rt, pt = _fk_jacobian(m, q, J, ws, os_)
        r = _residual(target, Rt, pt, M)
        big = 0.0
        for i in range(6):
            e[i] = r[i]
            big = max(big, math.fabs(r[i]))
        if big <= POLISH_GOAL or not big < 0.5 or step == POLISH_STEPS:
            return big
        if not _solve6(J, e, A, dq):
            return big
        for i in range(6):
            q[i] += dq[i]
    return big


@njit(cache=True)
def _finish(m, target, seed, out, work, R06, t6, sol, ss):  # type: ignore[no-untyped-def]
    """θ4, θ5 at a root (solver order), the whole solution polished on the real chain and emitted."""
    h1, h2, h3, h4, h5, h6 = (
        _v(m, S_H),
        _v(m, S_H + 3),
        _v(m, S_H + 6),
        _v(m, S_H + 9),
        _v(m, S_H + 12),
        _v(m, S_H + 15),
    )
    c1, s1, c2, s2, c3, s3 = sol
    t1, t2, t3 = (math.atan2(s1, c1), c1, s1), (math.atan2(s2, c2), c2, s2), (math.atan2(s3, c3), c3, s3)
    y = rot_back(h3, t3, rot_back(h2, t2, rot_back(h1, t1, _mat_vec(R06, rot_back(h6, t6, h5)))))
    n5 = _v(m, S_N5)
    z = rot_back(h3, t3, rot_back(h2, t2, rot_back(h1, t1, _mat_vec(R06, rot_back(h6, t6, n5)))))
    t4 = sp1(h5, y, h4, ss[3])
    t5 = sp1(n5, rot_back(h4, t4, z), h5, ss[4])
    q = work[:, 24]
    q[0], q[1], q[2], q[3], q[4], q[5] = t1[0], t2[0], t3[0], t4[0], t5[0], t6[0]
    if m[S_REVERSED] != 0.0:
        q[0], q[1], q[2], q[3], q[4], q[5] = t6[0], t5[0], t4[0], t3[0], t2[0], t1[0]
    for i in range(6):  # a joint no whole turn brings within its limits: dropped before polishing
        placed = K._place(q[i], seed[i], m[K.LO + i] - LIMIT_SLACK, m[K.HI + i] + LIMIT_SLACK)
        if placed != placed:
            out[1] += 1.0
            return
    if not _polish(m, target, q, work) <= m[K.TOL]:  # checked on the real chain (the emission's DH check is off)
        return
    K._emit(
        m,
        target,
        seed,
        out,
        angle_of(q[0]),
        angle_of(q[1]),
        angle_of(q[2]),
        angle_of(q[3]),
        angle_of(q[4]),
        angle_of(q[5]),
    )


# ---- the search ---------------------------------------------------------------------------------------------


@njit(cache=True)
def _sample(m, T, ss, xs, c, s, E, G, G1, i):  # type: ignore[no-untyped-def]
    _, e, g, g1 = _branches(m, T, c, s, ss, -1)
    G1[i] = g1
    for k in range(4):
        E[i, k], G[i, k] = e[k], g[k]


@njit(cache=True)
def _dips(m, R06, T, ss, xs, G, n):  # type: ignore[no-untyped-def]
    """Points where a slot's reach margin changes sign between two samples of one sign: a dip below
    zero between two reaching samples, or an island above it between two clamped ones (the wrist
    point passing near axis 1, where θ1's margin turns sharply). A sampled local minimum of |margin|
    below DIP_GAP is descended (_descend) until the margin changes sign. There a branch pair exists
    on part of a step only (θ1's or θ3's double root, near a singularity), and a root where it
    exists is bracketed by neither sample."""
    found = np.empty(4 * n)
    count = 0
    for k in range(4):
        for i in range(n):
            g0, g1, g2 = G[(i - 1) % n, k], G[i, k], G[(i + 1) % n, k]
            same = (g0 < 0.0) == (g1 < 0.0) == (g2 < 0.0)
            if not (
                same and math.fabs(g1) < DIP_GAP and math.fabs(g1) <= math.fabs(g0) and math.fabs(g1) < math.fabs(g2)
            ):
                continue
            x1 = xs[i]
            v = _descend(m, R06, T, ss, k, x1 - (xs[1] - xs[0]), x1, x1 + (xs[1] - xs[0]), g0, g1, g2, 1, 0, 0.0, 0.0)[
                0
            ]
            if v == v:
                found[count] = v - 2.0 * math.pi * math.floor((v + math.pi) / (2.0 * math.pi))
                count += 1
    return found[:count]


@njit(cache=True)
def _search(m, target, seed, out):  # type: ignore[no-untyped-def]
    _Rt, pt, ss, R06 = K.target_frame(target, seed, m[S_REVERSED] != 0.0, m[S_R6T : S_R6T + 9])
    T = _terms(m, R06, pt)
    work = np.empty((6, WORK_COLUMNS))  # the polish's scratch (see _polish), once per target
    n = int(m[S_SAMPLES])
    step = 2.0 * math.pi / n
    # the grid: n samples from −π (cosines and sines by rotation, no libm call), then the first two again
    xs = np.empty(n + 2)
    E, G, G1 = np.empty((n + 2, 4)), np.empty((n + 2, 4)), np.empty(n + 2)
    cd, sd = math.cos(step), math.sin(step)
    c, s = -1.0, 0.0
    for i in range(n):
        xs[i] = -math.pi + step * i
        _sample(m, T, ss, xs, c, s, E, G, G1, i)
        c, s = c * cd - s * sd, s * cd + c * sd
    extra = _dips(m, R06, T, ss, xs, G, n)
    if len(extra):  # merged into the grid, sorted, each sampled
        base, (Eb, Gb, G1b) = xs[:n].copy(), (E[:n].copy(), G[:n].copy(), G1[:n].copy())
        extra.sort()
        n += len(extra)
        xs = np.empty(n + 2)
        E, G, G1 = np.empty((n + 2, 4)), np.empty((n + 2, 4)), np.empty(n + 2)
        a = b = 0
        for i in range(n):
            if b < len(extra) and (a == len(base) or extra[b] < base[a]):
                xs[i] = extra[b]
                _sample(m, T, ss, xs, math.cos(extra[b]), math.sin(extra[b]), E, G, G1, i)
                b += 1
            else:
                xs[i], E[i], G[i], G1[i] = base[a], Eb[a], Gb[a], G1b[a]
                a += 1
    for i in range(2):
        xs[n + i], E[n + i], G[n + i], G1[n + i] = xs[i] + 2.0 * math.pi, E[i], G[i], G1[i]
    for k in range(4):
        for i in range(n):
            a, b = xs[i], xs[i + 1]
            fa, fb, ga, gb = E[i, k], E[i + 1, k], G[i, k], G[i + 1, k]
            if ga < 0.0 and gb < 0.0:  # clamped at both ends: no branch here
                continue
            if (ga < 0.0) != (gb < 0.0):  # a reach boundary inside: k and the slot it meets there
                partner = k ^ 2 if min(G1[i], G1[i + 1]) < 0.0 else k ^ 1
                if k < partner:
                    _boundary(m, target, seed, out, work, R06, T, ss, k, partner, a, b, ga, gb)
                continue
            roots = (math.nan, math.nan)
            if fa == 0.0:
                roots = (a, math.nan)
            elif (fa < 0.0) != (fb < 0.0) and fb != 0.0:
                roots = (_illinois(m, R06, T, ss, k, a, b, fa, fb, 0, 0, 0.0, 0.0), math.nan)
            else:
                if math.fabs(fa - fb) > STEEP:
                    _steep(m, target, seed, out, work, R06, T, ss, k, a, b, fa, fb)
                # |e| smallest at sample i + 1 of three of one sign, all reaching: two roots closer than a
                # sample step, or a tangent one, near the minimum (successive parabolic interpolation)
                fc, gc = E[i + 2, k], G[i + 2, k]
                if (
                    gc < 0.0
                    or (fc < 0.0) != (fb < 0.0)
                    or not (math.fabs(fb) <= math.fabs(fa) and math.fabs(fb) < math.fabs(fc))
                ):
                    continue
                roots = _close_pair(m, R06, T, ss, k, a, b, xs[i + 2], fa, fb, fc, 0, 0, 0.0, 0.0)
            for r in roots:
                if r == r:
                    t6 = angle_of(r)
                    _finish(m, target, seed, out, work, R06, t6, _branches(m, T, t6[1], t6[2], ss, k)[0], ss)


@njit(cache=True)
def _solve(m, target, seed, out):  # type: ignore[no-untyped-def]
    for i in range(4):
        out[i] = 0.0
    for i in range(6):
        out[K.SEED + i] = seed[i]
        if not math.isfinite(seed[i]):
            out[3] = K.BAD_INPUT
            return
    for r in range(4):
        for c in range(4):
            if not math.isfinite(target[r, c]):
                out[3] = K.BAD_INPUT
                return
    _search(m, target, seed, out)


@njit(cache=True)
def solve_one(m, target, seed, out):  # type: ignore[no-untyped-def]
    """Every solution of one target (4×4) from one seed (6,) into out (kernel.OUT_SIZE,); the status."""
    if target.shape[0] != 4 or target.shape[1] != 4 or seed.shape[0] != 6 or out.shape[0] < K.OUT_SIZE:
        return K.BAD_INPUT
    _solve(m, target, seed, out)
    return out[3]


@njit(cache=True)
def solve_many(m, targets, seeds, out):  # type: ignore[no-untyped-def]
    """solve_one for (N,4,4) targets and (N,6) seeds into out (N, kernel.OUT_SIZE)."""
    n = targets.shape[0]
    if targets.shape[1] != 4 or targets.shape[2] != 4 or seeds.shape[0] != n or seeds.shape[1] != 6:
        return K.BAD_INPUT
    if out.shape[0] != n or out.shape[1] < K.OUT_SIZE:
        return K.BAD_INPUT
    status = K.SOLVED
    for i in range(n):
        _solve(m, targets[i], seeds[i], out[i])
        if out[i, 3] == K.BAD_INPUT:
            status = K.BAD_INPUT
    return status


# ---- detection and the model ------------------------------------------------------------------------------


def _meet(l1: Line, l2: Line) -> Array:
    c1, c2 = closest(l1[0], l1[1], l2[0], l2[1], SNAP_TOL)
    return (c1 + c2) / 2.0


def _intersect(l1: Line, l2: Line) -> bool:
    return not parallel(l1[1], l2[1], SNAP_TOL) and distance(l1, l2, SNAP_TOL) < SNAP_TOL


def plan(chain: Chain) -> bool:
    """Whether the search runs on the chain reversed (axes 2∩3, 4∥5), or ArmtoolError saying why it cannot run."""
    where = f"{chain.base} → {chain.tip}"
    if chain.n != 6 or any(j.kind == "prismatic" for j in chain.joints):
        raise ArmtoolError("the 1-D search needs a 6R chain (six revolute joints)", where=where)
    lines, _ = axis_lines(chain)
    for reverse in (False, True):
        order = lines[::-1] if reverse else lines
        if (
            _intersect(order[3], order[4])
            and parallel(order[1][1], order[2][1], SNAP_TOL)
            and distance(order[1], order[2], SNAP_TOL) > SNAP_TOL
        ):
            return reverse
    raise ArmtoolError(
        "the 1-D search needs axes 4, 5 intersecting and axes 2∥3 (or axes 2, 3 intersecting and 4∥5); this chain has neither",
        where=where,
        hint="use a numerical solver such as lm (`--solvers lm`)",
    )


def title(reverse: bool) -> str:
    """The method in words (ik-bench's row)."""
    if reverse:
        return "1-D search over θ1 (axes 2, 3 intersecting, 4∥5; no closed form), every solution, Newton-polished"
    return "1-D search over θ6 (axes 4, 5 intersecting, 2∥3; no closed form), every solution, Newton-polished"


def _pack_terms(m: Array, h: list[Array], P: list[Array]) -> None:
    """What the samples share (see _branches): θ1's, θ3's and θ2's subproblem coefficients, the error's."""
    k1 = -h[0]
    m[S_T1 : S_T1 + 9] = np.concatenate([h[1] - (h[1] @ k1) * k1, np.cross(h[1], k1), (h[1] @ k1) * k1])
    hh, pp, k3 = -P[2], P[3], h[2]  # θ3: sp4(−p23, p34, h3, ·)
    A, B = float(hh @ pp - (hh @ k3) * (k3 @ pp)), float(hh @ np.cross(k3, pp))
    r = math.hypot(A, B)
    degenerate = r <= 1e-9 * (1.0 + float(np.linalg.norm(pp)))  # p34 or p23 along axis 3: solved in general
    m[S_T3 : S_T3 + 4] = [
        float((hh @ k3) * (k3 @ pp)),
        0.0 if degenerate else A,
        0.0 if degenerate else B,
        float(0.5 * (pp @ pp + P[2] @ P[2])),
    ]
    along = (k3 @ pp) * k3
    U, V, W = P[2] + along, pp - along, np.cross(k3, pp)
    m[S_T2 : S_T2 + 18] = np.concatenate([U, V, W, np.cross(h[1], U), np.cross(h[1], V), np.cross(h[1], W)])
    m[S_E : S_E + 5] = np.concatenate([np.cross(h[3], h[1]), [h[3] @ h[1], h[3] @ h[4]]])


def pack(chain: Chain, tolerance: float, samples: int = SAMPLES) -> Array:
    """The model array solve_one reads."""
    reverse = plan(chain)
    lines, tip0 = axis_lines(chain)
    m = np.zeros(SEARCH_MODEL_SIZE)
    solver_lines, tip = reversed_lines(lines, tip0) if reverse else (list(lines), tip0)
    h = [w / np.linalg.norm(w) for _, w in solver_lines]
    pts = [p.copy() for p, _ in solver_lines]
    # the structure made exact: axes 4, 5 through their meeting point, axis 3 along axis 2
    pts[3] = pts[4] = _meet(solver_lines[3], solver_lines[4])
    m[S_SIGN3] = 1.0 if float(h[1] @ h[2]) > 0 else -1.0
    h[2] = h[1] * m[S_SIGN3]
    P = [pts[0]] + [pts[i] - pts[i - 1] for i in range(1, 6)] + [tip[:3, 3] - pts[5]]
    m[S_REVERSED], m[S_SAMPLES] = float(reverse), samples
    m[S_H : S_H + 18] = np.concatenate(h)
    m[S_P : S_P + 21] = np.concatenate(P)
    m[S_R6T : S_R6T + 9] = tip[:3, :3].reshape(9)
    m[S_N5 : S_N5 + 3] = any_normal(h[4])
    m[S_CONST] = float(h[1] @ (P[1] + P[2] + P[3]))
    _pack_terms(m, h, P)
    m[S_LP : S_LP + 18] = np.concatenate([p for p, _ in lines])
    m[S_LW : S_LW + 18] = np.concatenate([w / np.linalg.norm(w) for _, w in lines])
    m[S_TIP : S_TIP + 9] = tip0[:3, :3].reshape(9)
    m[S_TIP + 9 : S_TIP + 12] = tip0[:3, 3]
    # the emission's fields (kernel's layout): never reversed there (solutions come in chain order)
    m[K.REVERSED] = 0.0
    m[K.TOL], m[K.ROT_TOL2] = tolerance, 4.0 * math.sin(tolerance / 2.0) ** 2
    m[K.LO : K.LO + 6] = np.where(chain.continuous, -math.inf, chain.lower)
    m[K.HI : K.HI + 6] = np.where(chain.continuous, math.inf, chain.upper)
    m[K.CHECK] = 0.0  # the polish checks every answer on the real chain's axis lines instead
    return m
