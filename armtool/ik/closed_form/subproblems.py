"""The Paden–Kahan subproblems, compiled with Numba: the pieces every closed-form IK here is built from.

Numbering and meaning as IK-Geo's (Elias & Wen 2022, "IK-Geo: Unified robot inverse kinematics
using subproblem decomposition"), which EAIK uses too. R(k, θ) is the rotation by θ about the unit
axis k (Rodrigues); vectors are 3-tuples of floats, so that nothing is allocated:

* `sp1(p1, p2, k, free)`: θ with R(k, θ)·p1 = p2 (one solution; least squares when the lengths or
  the components along k differ).
* `sp2(p1, p2, k1, k2, free1, free2)`: (θ1, θ2) with R(k1, θ1)·p1 = R(k2, θ2)·p2 (0, 1 or 2).
* `sp3(p1, p2, k, d, ...)`: θ with ‖R(k, θ)·p1 − p2‖ = d (0, 1 or 2).
* `sp4(h, p, k, d, ...)`: θ with hᵀ·R(k, θ)·p = d (0, 1 or 2).
* `sp5(p0, p1, p2, p3, k1, k2, k3, ...)`: (θ1, θ2, θ3) with p0 + R(k1, θ1)·p1 = R(k2, θ2)·(p2 + R(k3, θ3)·p3)
  (0 to 4): two scalar equations in θ1 and θ3 alone (the components along k2, and the lengths),
  one unknown eliminated, a quartic in tan(θ/2) (`real_roots4`).

An angle comes back as `(θ, cos θ, sin θ)`: the next subproblem turns vectors by it without
another sine or cosine (a libm atan2 or sincos costs ~40 ns, most of a closed-form solve). Roots
are written without acos near ±1: a root pair θ = φ ± a comes from cos a and sin a = √((1 − c)(1 + c)).

Degenerate cases are the caller's to settle and are passed in, never guessed: `free` is the angle
to return where the subproblem leaves its angle free (p1 or p2 along k: any θ solves it), e.g. the
seed's. `over` is how far beyond ±1 a cosine may lie and still count as rounding (the double root
is taken); `flat` merges a root pair within √(2·flat) rad of its midpoint into one (a tangent solution).

This layer knows nothing of robots: the families in `kernel.py` call it, and so can a 1-D search
over one joint (a later IK for arms with no closed form), which is why it is a module of its own.
"""

from __future__ import annotations

import math

from numba import njit

TINY = 1e-13  # a projection shorter than this (relative to the vectors' size) is zero: the angle is free
NO_ANGLE = (0.0, 1.0, 0.0)  # the placeholder in the slots of solutions that do not exist


@njit(cache=True)
def dot(a, b):  # type: ignore[no-untyped-def]
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True)
def cross(a, b):  # type: ignore[no-untyped-def]
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@njit(cache=True)
def add(a, b):  # type: ignore[no-untyped-def]
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@njit(cache=True)
def sub(a, b):  # type: ignore[no-untyped-def]
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@njit(cache=True)
def scale(a, f):  # type: ignore[no-untyped-def]
    return (a[0] * f, a[1] * f, a[2] * f)


@njit(cache=True)
def neg(a):  # type: ignore[no-untyped-def]
    return (-a[0], -a[1], -a[2])


@njit(cache=True)
def norm(a):  # type: ignore[no-untyped-def]
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@njit(cache=True)
def rot(k, c, s, v):  # type: ignore[no-untyped-def]
    """R(k, θ)·v for a unit k, given cos θ and sin θ (Rodrigues)."""
    kv = (k[0] * v[0] + k[1] * v[1] + k[2] * v[2]) * (1.0 - c)
    return (
        c * v[0] + s * (k[1] * v[2] - k[2] * v[1]) + kv * k[0],
        c * v[1] + s * (k[2] * v[0] - k[0] * v[2]) + kv * k[1],
        c * v[2] + s * (k[0] * v[1] - k[1] * v[0]) + kv * k[2],
    )


@njit(cache=True)
def rot_angle(k, angle, v):  # type: ignore[no-untyped-def]
    """R(k, θ)·v for an angle (θ, cos θ, sin θ)."""
    return rot(k, angle[1], angle[2], v)


@njit(cache=True)
def rot_back(k, angle, v):  # type: ignore[no-untyped-def]
    """R(k, θ)ᵀ·v = R(k, −θ)·v."""
    return rot(k, angle[1], -angle[2], v)


@njit(cache=True)
def angle_of(theta):  # type: ignore[no-untyped-def]
    return (theta, math.cos(theta), math.sin(theta))


@njit(cache=True)
def angle_cs(c, s):  # type: ignore[no-untyped-def]
    """The angle whose cosine and sine are proportional to c and s (normalised here)."""
    r = math.sqrt(c * c + s * s)
    return (math.atan2(s, c), c / r, s / r)


@njit(cache=True)
def sp1(p1, p2, k, free):  # type: ignore[no-untyped-def]
    """θ with R(k, θ)·p1 = p2 (least squares); θ = `free` where p1 or p2 lies along k."""
    x = dot(p1, p2) - dot(k, p1) * dot(k, p2)
    y = dot(k, cross(p1, p2))
    r = math.sqrt(x * x + y * y)
    if r <= TINY * (dot(p1, p1) + dot(p2, p2)):
        return angle_of(free)
    return (math.atan2(y, x), x / r, y / r)


@njit(cache=True)
def sp4(h, p, k, d, free, over, flat):  # type: ignore[no-untyped-def]
    """Every θ with hᵀ·R(k, θ)·p = d: (count, angle, angle). Count −1: every θ solves it (θ = `free`).

    hᵀR(k,θ)p = A cos θ + B sin θ + C with A = hᵀp⊥, B = hᵀ(k×p), C = (hᵀk)(kᵀp): θ = φ ± a,
    φ = atan2(B, A), cos a = (d − C)/√(A² + B²)."""
    hk, kp = dot(h, k), dot(k, p)
    A = dot(h, p) - hk * kp
    B = dot(h, cross(k, p))
    C = hk * kp
    r = math.sqrt(A * A + B * B)
    if r <= TINY * (1.0 + math.fabs(d)) * (1.0 + norm(p)):
        if math.fabs(d - C) <= 1e-9 * (1.0 + norm(p)):
            a = angle_of(free)
            return -1, a, a
        return 0, NO_ANGLE, NO_ANGLE
    c0 = (d - C) / r
    cf, sf = A / r, B / r
    if c0 >= 1.0 - flat:
        if c0 > 1.0 + over:
            return 0, NO_ANGLE, NO_ANGLE
        a = (math.atan2(sf, cf), cf, sf)
        return 1, a, a
    if c0 <= -1.0 + flat:
        if c0 < -1.0 - over:
            return 0, NO_ANGLE, NO_ANGLE
        a = (math.atan2(-sf, -cf), -cf, -sf)
        return 1, a, a
    sa = math.sqrt((1.0 - c0) * (1.0 + c0))
    phi, half = math.atan2(sf, cf), math.atan2(sa, c0)
    plus = (phi + half, cf * c0 - sf * sa, sf * c0 + cf * sa)
    minus = (phi - half, cf * c0 + sf * sa, sf * c0 - cf * sa)
    return 2, plus, minus


@njit(cache=True)
def sp3(p1, p2, k, d, free, over, flat):  # type: ignore[no-untyped-def]
    """Every θ with ‖R(k, θ)·p1 − p2‖ = d: as sp4, since ‖R p1 − p2‖² = |p1|² + |p2|² − 2·p2ᵀ R p1."""
    return sp4(p2, p1, k, 0.5 * (dot(p1, p1) + dot(p2, p2) - d * d), free, over, flat)


@njit(cache=True)
def sp2(p1, p2, k1, k2, free1, free2, over, flat):  # type: ignore[no-untyped-def]
    """Every (θ1, θ2) with R(k1, θ1)·p1 = R(k2, θ2)·p2 (k1 not parallel to k2): (count, (θ1, θ2), (θ1, θ2)).

    The common vector x has k1ᵀx = k1ᵀp1, k2ᵀx = k2ᵀp2 and |x| = |p1| (|p2|: their mean is taken):
    x = α k1 + β k2 ± γ (k1 × k2). Where p1 lies along k1, θ1 is free (`free1`) and θ2 follows
    by sp1 (and the other way round). The two solutions merge into one where they are closer than
    ~√(2·flat) rad (a tangent solution)."""
    n1 = cross(k1, p1)
    n2 = cross(k2, p2)
    size = dot(p1, p1) + dot(p2, p2)
    if dot(n1, n1) <= TINY * size:
        t1 = angle_of(free1)
        t2 = sp1(p2, p1, k2, free2)
        return 1, (t1, t2), (t1, t2)
    if dot(n2, n2) <= TINY * size:
        t2 = angle_of(free2)
        t1 = sp1(p1, p2, k1, free1)
        return 1, (t1, t2), (t1, t2)
    c12 = dot(k1, k2)
    den = 1.0 - c12 * c12
    a1, a2 = dot(k1, p1), dot(k2, p2)
    alpha = (a1 - c12 * a2) / den
    beta = (a2 - c12 * a1) / den
    axb = cross(k1, k2)
    base = add(scale(k1, alpha), scale(k2, beta))
    g2 = (0.5 * size - dot(base, base)) / den  # |k1 × k2|² = 1 − (k1ᵀk2)²
    if g2 < -over * size:
        return 0, (NO_ANGLE, NO_ANGLE), (NO_ANGLE, NO_ANGLE)
    if g2 * den <= flat * size:
        t1 = sp1(p1, base, k1, free1)
        t2 = sp1(p2, base, k2, free2)
        return 1, (t1, t2), (t1, t2)
    g = math.sqrt(g2)
    xa = add(base, scale(axb, g))
    xb = sub(base, scale(axb, g))
    return 2, (sp1(p1, xa, k1, free1), sp1(p2, xa, k2, free2)), (sp1(p1, xb, k1, free1), sp1(p2, xb, k2, free2))


# ---- polynomials ---------------------------------------------------------------------------------------


@njit(cache=True)
def _poly(c, n, t):  # type: ignore[no-untyped-def]
    """Value and derivative of c[0] + c[1] t + ... + c[n] tⁿ (Horner)."""
    v, dv = c[n], 0.0
    for i in range(n - 1, -1, -1):
        dv = dv * t + v
        v = v * t + c[i]
    return v, dv


@njit(cache=True)
def _bracketed(c, n, lo, hi, flo):  # type: ignore[no-untyped-def]
    """The root of the degree-n polynomial c in [lo, hi], where it changes sign (flo: its value at lo):
    Newton steps, bisection when a step leaves the bracket."""
    t = 0.5 * (lo + hi)
    for _ in range(100):
        v, dv = _poly(c, n, t)
        if v == 0.0:
            return t
        if (v < 0.0) == (flo < 0.0):
            lo, flo = t, v
        else:
            hi = t
        step = v / dv if dv != 0.0 else 0.0
        nt = t - step
        if not (lo < nt < hi) or dv == 0.0:
            nt = 0.5 * (lo + hi)
        if math.fabs(nt - t) <= 1e-16 * (1.0 + math.fabs(t)) or hi - lo <= 1e-16 * (1.0 + math.fabs(t)):
            return nt
        t = nt
    return t


@njit(cache=True)
def real_roots4(c0, c1, c2, c3, c4, work):  # type: ignore[no-untyped-def]
    """The real roots of c0 + c1 t + c2 t² + c3 t³ + c4 t⁴ (c4 ≠ 0) into work[:count], ascending; count.

    Roots are isolated by the critical points (the derivative's roots, found the same way between
    the second derivative's): between two neighbours the polynomial is monotone, so each sign
    change holds one root, found by safeguarded Newton steps. A critical point where the value
    vanishes to rounding is a double root (a tangent solution). `work`: scratch of length ≥ 12.
    Written here rather than np.roots (LAPACK's eigenvalues of the companion matrix: allocations
    and ~10 µs a call, more than a whole closed-form solve)."""
    q = (c0, c1, c2, c3, c4)
    d3 = (c1, 2.0 * c2, 3.0 * c3, 4.0 * c4)  # p'
    bound = 1.0 + max(math.fabs(c0), math.fabs(c1), math.fabs(c2), math.fabs(c3)) / math.fabs(c4)
    # work[4:8]: -bound, the inflection points (roots of p'', a quadratic) inside, +bound
    e0, e1, e2 = 2.0 * c2, 6.0 * c3, 12.0 * c4
    work[4] = -bound
    n_edges = 1
    disc = e1 * e1 - 4.0 * e2 * e0
    if disc > 0.0:
        qq = -0.5 * (e1 + math.copysign(math.sqrt(disc), e1))
        ra = qq / e2
        rb = e0 / qq if qq != 0.0 else ra
        for r in (min(ra, rb), max(ra, rb)):
            if -bound < r < bound:
                work[4 + n_edges] = r
                n_edges += 1
    work[4 + n_edges] = bound
    n_edges += 1
    # work[8:13]: -bound, the critical points (roots of p'), +bound
    work[8] = -bound
    n_crit = 1
    for i in range(n_edges - 1):
        lo, hi = work[4 + i], work[5 + i]
        flo = _poly(d3, 3, lo)[0]
        fhi = _poly(d3, 3, hi)[0]
        if flo == 0.0 and i > 0:
            work[8 + n_crit] = lo
            n_crit += 1
        elif (flo < 0.0) != (fhi < 0.0) and fhi != 0.0:
            work[8 + n_crit] = _bracketed(d3, 3, lo, hi, flo)
            n_crit += 1
    work[8 + n_crit] = bound
    n_crit += 1
    size = max(math.fabs(c0), math.fabs(c1), math.fabs(c2), math.fabs(c3), math.fabs(c4))
    count = 0
    for i in range(n_crit - 1):
        lo, hi = work[8 + i], work[9 + i]
        if hi <= lo:
            continue
        flo = _poly(q, 4, lo)[0]
        fhi = _poly(q, 4, hi)[0]
        w = 1.0 + lo * lo
        if i > 0 and math.fabs(flo) <= 1e-12 * size * w * w:
            work[count] = lo  # a double root at a critical point
            count += 1
        elif (flo < 0.0) != (fhi < 0.0) and fhi != 0.0:
            work[count] = _bracketed(q, 4, lo, hi, flo)
            count += 1
        if count == 4:
            break
    return count


@njit(cache=True)
def sp5(p0, p1, p2, p3, k1, k2, k3, free, over, roots, flat=0.0):  # type: ignore[no-untyped-def]
    """Every (θ1, θ2, θ3) with p0 + R(k1, θ1)·p1 = R(k2, θ2)·(p2 + R(k3, θ3)·p3): (count, solutions).

    With a(θ1) = p0 + R(k1,θ1)p1 and b(θ3) = p2 + R(k3,θ3)p3, θ2 exists iff k2ᵀa = k2ᵀb and
    |a| = |b|: two equations linear in u = (cos θ1, sin θ1) and v = (cos θ3, sin θ3). The one whose
    2×2 block is better conditioned is eliminated (v = A u + b, or the other way round), |v| = 1 is
    a quartic in tan(θ/2) (the parameter turned by π/2 when θ = π is nearly a root, where tan is
    infinite), then θ2 = sp1. `roots`: scratch for real_roots4. Two neighbouring roots within
    √(2·flat) rad of their midpoint (a near-tangent solution) are one there, as sp3 and sp4 merge. Up to four
    solutions, as a tuple of four (θ1, θ2, θ3) angle triples (the first `count` valid)."""
    # k2ᵀa = a0 + a1 c1 + a2 s1,  |a|² = g0 + g1 c1 + g2 s1 (and the same in θ3 for b)
    kp1, kp3 = dot(k1, p1), dot(k3, p3)
    p1_perp = sub(p1, scale(k1, kp1))
    p3_perp = sub(p3, scale(k3, kp3))
    k1p1, k3p3 = cross(k1, p1), cross(k3, p3)
    a0 = dot(k2, p0) + kp1 * dot(k2, k1)
    a1, a2 = dot(k2, p1_perp), dot(k2, k1p1)
    g0 = dot(p0, p0) + dot(p1, p1) + 2.0 * kp1 * dot(p0, k1)
    g1, g2 = 2.0 * dot(p0, p1_perp), 2.0 * dot(p0, k1p1)
    b0 = dot(k2, p2) + kp3 * dot(k2, k3)
    b1, b2 = dot(k2, p3_perp), dot(k2, k3p3)
    e0 = dot(p2, p2) + dot(p3, p3) + 2.0 * kp3 * dot(p2, k3)
    e1, e2 = 2.0 * dot(p2, p3_perp), 2.0 * dot(p2, k3p3)
    # [a1 a2; g1 g2] u + [a0; g0] = [b1 b2; e1 e2] v + [b0; e0]
    det_u = a1 * g2 - a2 * g1
    det_v = b1 * e2 - b2 * e1
    nu = (a1 * a1 + a2 * a2 + g1 * g1 + g2 * g2) + 1e-300
    nv = (b1 * b1 + b2 * b2 + e1 * e1 + e2 * e2) + 1e-300
    swap = math.fabs(det_u) / nu > math.fabs(det_v) / nv  # eliminate u instead: solve for θ3 first
    if swap:
        m11, m12, m21, m22, det = a1, a2, g1, g2, det_u
        n11, n12, n21, n22 = b1, b2, e1, e2
        r1, r2 = b0 - a0, e0 - g0
    else:
        m11, m12, m21, m22, det = b1, b2, e1, e2, det_v
        n11, n12, n21, n22 = a1, a2, g1, g2
        r1, r2 = a0 - b0, g0 - e0
    none = (NO_ANGLE, NO_ANGLE, NO_ANGLE)
    empty = (none, none, none, none)
    if math.fabs(det) <= 1e-12 * max(nu, nv):
        return 0, empty
    # the eliminated unit vector w = M⁻¹ (N x + r) = A x + b, x the remaining one
    i11, i12, i21, i22 = m22 / det, -m12 / det, -m21 / det, m11 / det
    A11, A12 = i11 * n11 + i12 * n21, i11 * n12 + i12 * n22
    A21, A22 = i21 * n11 + i22 * n21, i21 * n12 + i22 * n22
    bb1, bb2 = i11 * r1 + i12 * r2, i21 * r1 + i22 * r2
    # |A x + b|² = 1: xᵀ G x + 2 fᵀ x + h = 0 with x = (cos θ, sin θ)
    G11, G12, G22 = A11 * A11 + A21 * A21, A11 * A12 + A21 * A22, A12 * A12 + A22 * A22
    f1, f2 = A11 * bb1 + A21 * bb2, A12 * bb1 + A22 * bb2
    h = bb1 * bb1 + bb2 * bb2 - 1.0
    lead = G11 - 2.0 * f1 + h  # the quartic's leading coefficient: the value at θ = π
    big = max(math.fabs(G11), math.fabs(G12), math.fabs(G22), math.fabs(f1), math.fabs(f2), math.fabs(h))
    shift = math.fabs(lead) < 1e-6 * big
    if shift:  # θ = θ' + π/2: cos θ = −sin θ', sin θ = cos θ'
        G11, G12, G22, f1, f2 = G22, -G12, G11, f2, -f1
        lead = G11 - 2.0 * f1 + h
    count = real_roots4(
        G11 + 2.0 * f1 + h,
        4.0 * G12 + 4.0 * f2,
        -2.0 * G11 + 4.0 * G22 + 2.0 * h,
        -4.0 * G12 + 4.0 * f2,
        lead,
        roots,
    )
    window = math.sqrt(2.0 * flat)
    kept, i = 0, 0
    while i < count:
        t = roots[i]
        if i + 1 < count and math.atan(roots[i + 1]) - math.atan(t) <= window:  # θ = 2 atan t: half the gap
            t = 0.5 * (t + roots[i + 1])
            i += 1
        roots[kept] = t
        kept += 1
        i += 1
    count = kept
    sols = empty
    n = 0
    for i in range(count):
        t = roots[i]
        den = 1.0 + t * t
        cx, sx = (1.0 - t * t) / den, 2.0 * t / den
        if shift:
            cx, sx = -sx, cx
        cw, sw = A11 * cx + A12 * sx + bb1, A21 * cx + A22 * sx + bb2
        if swap:
            c1, s1, c3, s3 = cw, sw, cx, sx
        else:
            c1, s1, c3, s3 = cx, sx, cw, sw
        t1 = angle_cs(c1, s1)
        t3 = angle_cs(c3, s3)
        a = add(p0, rot_angle(k1, t1, p1))
        b = add(p2, rot_angle(k3, t3, p3))
        t2 = sp1(b, a, k2, free)
        sol = (t1, t2, t3)
        if n == 0:
            sols = (sol, none, none, none)
        elif n == 1:
            sols = (sols[0], sol, none, none)
        elif n == 2:
            sols = (sols[0], sols[1], sol, none)
        else:
            sols = (sols[0], sols[1], sols[2], sol)
        n += 1
    return n, sols
