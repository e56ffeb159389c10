"""`lm`'s inner loop, compiled with Numba: forward kinematics, the Jacobian and Levenberg–Marquardt
tries on a target, with no Python between iterations.

Why compiled: in Python each iteration was a dozen calls into Pinocchio, SciPy's LAPACK and numpy
(~10 µs of call overhead for a 6×7 problem whose arithmetic takes well under 1 µs), and `lm` ran
slower than roboticstoolbox's C++ `ik_LM` once both were timed the same way. Numba
compiles these functions on first use (~15 s) and caches the machine code beside this file (or in
the user's cache directory when that is read-only), so later processes load it in a fraction of a second.

The chain is one float array, `geometry` (n + 1, 19): per moving joint the origin's rotation (9,
row-major) and translation (3) from the previous joint's frame, the unit axis (3), 1.0 for a
prismatic joint, the lower and upper limits used while stepping (±inf for a continuous joint),
and 1.0 for a continuous joint (wrapped into [-π, π) where a try writes its answer into `out`);
the last row holds the tip offset's rotation and translation. The pose error is verify()'s,
e = [p_target − p; log(R_target Rᵀ)] in the base frame, so a try stops exactly where the independent
check will accept its answer (with a 0.99 margin on the tolerance).

`settings` (8,): first try's patience, later tries' patience, progress, iterations per try, error
damping k, damping bias, tolerance, and the seed's feature distance beyond which the table is asked
(see LevenbergMarquardt). The table (`scores`, `cell_scores`, `cell_bounds`, `table_q`) is described
in LevenbergMarquardt.table(); `table_q` is in cell order, so a cell row is a table row.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

SOLVED = 1.0  # out[0] of a try run
NEED_TABLE = -2  # first_tries: the seed is far and no table was given
NOT_FINITE = -3  # first_tries: the target or the seed holds a NaN or an infinity (nothing tried)
OUT_HEAD = 3  # out = [status, iterations, best ‖e‖², q (n), best q (n)]

_LOWER, _UPPER, _PRISMATIC, _CONTINUOUS = 16, 17, 15, 18  # geometry columns
TWO_PI = 2.0 * math.pi


@njit(cache=True, error_model="numpy")
def _write_answer(geometry, q, out):  # type: ignore[no-untyped-def]
    """q into both of out's configuration slots, continuous joints wrapped into [-π, π)."""
    n = q.shape[0]
    for i in range(n):
        v = q[i]
        if geometry[i, _CONTINUOUS] != 0.0:
            v = (v + math.pi) % TWO_PI - math.pi
        out[OUT_HEAD + i] = out[OUT_HEAD + n + i] = v


@njit(cache=True, error_model="numpy")
def _forward(geometry, q, R, p, points, axes, scratch):  # type: ignore[no-untyped-def]
    """Tip rotation R (3,3) and position p (3,) for q, in place; each joint's origin in `points`
    and its axis in the base frame in `axes` (n, 3), which the Jacobian reads."""
    n = q.shape[0]
    for a in range(3):
        p[a] = 0.0
        for b in range(3):
            R[a, b] = 1.0 if a == b else 0.0
    T = scratch
    for i in range(n + 1):
        g = geometry[i]
        # p += R · origin translation; R = R · origin rotation
        for a in range(3):
            p[a] += R[a, 0] * g[9] + R[a, 1] * g[10] + R[a, 2] * g[11]
        for a in range(3):
            r0, r1, r2 = R[a, 0], R[a, 1], R[a, 2]
            T[a, 0] = r0 * g[0] + r1 * g[3] + r2 * g[6]
            T[a, 1] = r0 * g[1] + r1 * g[4] + r2 * g[7]
            T[a, 2] = r0 * g[2] + r1 * g[5] + r2 * g[8]
        for a in range(3):
            for b in range(3):
                R[a, b] = T[a, b]
        if i == n:
            break
        x, y, z = g[12], g[13], g[14]
        for a in range(3):
            points[i, a] = p[a]
            axes[i, a] = R[a, 0] * x + R[a, 1] * y + R[a, 2] * z
        if g[_PRISMATIC] != 0.0:  # along the axis
            for a in range(3):
                p[a] += axes[i, a] * q[i]
        else:  # R = R · Rot(axis, q) (Rodrigues)
            c, s = math.cos(q[i]), math.sin(q[i])
            C = 1.0 - c
            m00, m01, m02 = c + x * x * C, x * y * C - z * s, x * z * C + y * s
            m10, m11, m12 = y * x * C + z * s, c + y * y * C, y * z * C - x * s
            m20, m21, m22 = z * x * C - y * s, z * y * C + x * s, c + z * z * C
            for a in range(3):
                r0, r1, r2 = R[a, 0], R[a, 1], R[a, 2]
                R[a, 0] = r0 * m00 + r1 * m10 + r2 * m20
                R[a, 1] = r0 * m01 + r1 * m11 + r2 * m21
                R[a, 2] = r0 * m02 + r1 * m12 + r2 * m22


@njit(cache=True, error_model="numpy")
def _jacobian(geometry, p, points, axes, J):  # type: ignore[no-untyped-def]
    """The 6×n Jacobian [v; ω] of the tip (base frame, at the tip's origin) from _forward's output."""
    n = points.shape[0]
    for i in range(n):
        w0, w1, w2 = axes[i, 0], axes[i, 1], axes[i, 2]
        if geometry[i, _PRISMATIC] != 0.0:
            J[0, i], J[1, i], J[2, i] = w0, w1, w2
            J[3, i] = J[4, i] = J[5, i] = 0.0
        else:
            r0, r1, r2 = p[0] - points[i, 0], p[1] - points[i, 1], p[2] - points[i, 2]
            J[0, i] = w1 * r2 - w2 * r1
            J[1, i] = w2 * r0 - w0 * r2
            J[2, i] = w0 * r1 - w1 * r0
            J[3, i], J[4, i], J[5, i] = w0, w1, w2


@njit(cache=True, error_model="numpy")
def _pose_error(R, p, target, e, M):  # type: ignore[no-untyped-def]
    """e = [p_target − p; log(R_target Rᵀ)] in place (armtool.ik.solver.rotation_error's formula)."""
    for a in range(3):
        e[a] = target[a, 3] - p[a]
    for a in range(3):
        for b in range(3):
            M[a, b] = target[a, 0] * R[b, 0] + target[a, 1] * R[b, 1] + target[a, 2] * R[b, 2]
    cos = min(1.0, max(-1.0, (M[0, 0] + M[1, 1] + M[2, 2] - 1.0) / 2.0))
    v0, v1, v2 = M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]
    angle = math.acos(cos)
    if angle < 1e-6:
        e[3], e[4], e[5] = 0.5 * v0, 0.5 * v1, 0.5 * v2
    elif math.pi - angle > 1e-6:
        f = angle / (2.0 * math.sin(angle))
        e[3], e[4], e[5] = v0 * f, v1 * f, v2 * f
    else:  # a half turn: the axis from the diagonal of (M + I)/2 = a aᵀ
        k, best = 0, -1.0
        for a in range(3):
            d = max((M[a, a] + 1.0) / 2.0, 0.0)
            if d > best:
                best, k = d, a
        root = math.sqrt(best)
        x0 = (M[0, k] + (1.0 if k == 0 else 0.0)) / 2.0 / root
        x1 = (M[1, k] + (1.0 if k == 1 else 0.0)) / 2.0 / root
        x2 = (M[2, k] + (1.0 if k == 2 else 0.0)) / 2.0 / root
        norm = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
        x0, x1, x2 = x0 / norm, x1 / norm, x2 / norm
        if x0 * v0 + x1 * v1 + x2 * v2 < 0.0:
            x0, x1, x2 = -x0, -x1, -x2
        e[3], e[4], e[5] = x0 * angle, x1 * angle, x2 * angle


@njit(cache=True, error_model="numpy")
def _damped_step(J, e, damping, free, dq, A, g):  # type: ignore[no-untyped-def]
    """dq = (JᵀJ + λI)⁻¹ Jᵀe over the joints whose `free` is 1.0 (the others get 0), by Cholesky;
    False when A is not positive definite (non-finite numbers)."""
    n = J.shape[1]
    for i in range(n):
        if free[i] == 0.0:
            g[i] = 0.0
            for j in range(i + 1):
                A[i, j] = 0.0
            A[i, i] = damping
            continue
        s = 0.0
        for r in range(6):
            s += J[r, i] * e[r]
        g[i] = s
        for j in range(i + 1):
            if free[j] != 0.0:
                s = 0.0
                for r in range(6):
                    s += J[r, i] * J[r, j]
                A[i, j] = s
            else:
                A[i, j] = 0.0
        A[i, i] += damping
    # A = L Lᵀ in the lower triangle, then the two triangular solves.
    for i in range(n):
        for j in range(i + 1):
            s = A[i, j]
            for k in range(j):
                s -= A[i, k] * A[j, k]
            if i == j:
                if not s > 0.0:
                    return False
                A[i, i] = math.sqrt(s)
            else:
                A[i, j] = s / A[j, j]
    for i in range(n):
        s = g[i]
        for k in range(i):
            s -= A[i, k] * dq[k]
        dq[i] = s / A[i, i]
    for i in range(n - 1, -1, -1):
        s = dq[i]
        for k in range(i + 1, n):
            s -= A[k, i] * dq[k]
        dq[i] = s / A[i, i]
    return True


@njit(cache=True, error_model="numpy")
def run_tries(geometry, settings, target, starts, first_patience, out):  # type: ignore[no-untyped-def]
    """Levenberg–Marquardt tries from each row of `starts` in turn, until one converges.

    A try ends when its best ‖e‖² has not fallen by `progress` in `patience` iterations
    (`first_patience` for the first row), or after `per_try` iterations. Every step is taken, also
    one that raises the error (λ = k·‖e‖² + bias grows with it): a monotone search stalls in the
    curved valleys near singular poses, this one crosses them. Joints held at a limit that the
    step pushes further out leave the step. Success: ‖Δp‖ and ‖Δω‖ each within 0.99·tolerance.

    `out` (3 + 2n,): [SOLVED or 0, iterations, best ‖e‖², q, best q]; on success q is the answer,
    otherwise q and best q are both the best configuration of these tries; continuous joints are
    wrapped into [-π, π) in both.
    """
    n = starts.shape[1]
    patience, progress, per_try = int(settings[1]), settings[2], int(settings[3])
    k, bias, tolerance = settings[4], settings[5], settings[6]
    # Plain loops and np.empty only: every other numpy operation costs Numba a compilation of its own.
    R, M = np.empty((3, 3)), np.empty((3, 3))
    p, e = np.empty(3), np.empty(6)
    points, axes = np.empty((n, 3)), np.empty((n, 3))
    J, A = np.empty((6, n)), np.empty((n, n))
    g, dq, q, q_next, best_q, free = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    tol2 = (0.99 * tolerance) ** 2
    near = 2.0 * tol2
    best_err = math.inf
    for i in range(n):
        best_q[i] = starts[0, i]
    iterations = 0
    for t in range(starts.shape[0]):
        for i in range(n):
            q[i] = min(max(starts[t, i], geometry[i, _LOWER]), geometry[i, _UPPER])
        try_err, since = math.inf, 0
        wait = first_patience if t == 0 else patience
        for step in range(per_try + 1):
            _forward(geometry, q, R, p, points, axes, M)
            _pose_error(R, p, target, e, M)
            pos2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
            err = pos2 + e[3] * e[3] + e[4] * e[4] + e[5] * e[5]
            if err < near and pos2 <= tol2 and err - pos2 <= tol2:
                out[0], out[1], out[2] = SOLVED, iterations, err
                _write_answer(geometry, q, out)
                return
            if err < try_err * progress:
                since = 0
            else:
                since += 1
            if err < try_err:
                try_err = err
                if err < best_err:
                    best_err = err
                    for i in range(n):
                        best_q[i] = q[i]
            if since >= wait or step >= per_try:
                break
            iterations += 1
            _jacobian(geometry, p, points, axes, J)
            damping = k * err + bias
            for i in range(n):
                free[i] = 1.0
            if not _damped_step(J, e, damping, free, dq, A, g):
                break
            crossed = False
            for i in range(n):
                q_next[i] = q[i] + dq[i]
                crossed = crossed or q_next[i] < geometry[i, _LOWER] or q_next[i] > geometry[i, _UPPER]
            if crossed:
                # Joints already at a limit that the step pushes further out leave the step, and
                # the others re-plan without them; the rest of the step is clamped.
                blocked = False
                for i in range(n):
                    if min(max(q_next[i], geometry[i, _LOWER]), geometry[i, _UPPER]) == q[i] != q_next[i]:
                        free[i] = 0.0
                        blocked = True
                if blocked and _damped_step(J, e, damping, free, dq, A, g):
                    for i in range(n):
                        q_next[i] = q[i] + dq[i]
                for i in range(n):
                    q_next[i] = min(max(q_next[i], geometry[i, _LOWER]), geometry[i, _UPPER])
            for i in range(n):
                q[i] = q_next[i]
    out[0], out[1], out[2] = 0.0, iterations, best_err
    _write_answer(geometry, best_q, out)


@njit(cache=True, error_model="numpy")
def _feature_distance2(geometry, starts, target):  # type: ignore[no-untyped-def]
    """The table's distance from the tip pose of starts[0] to the target: |Δp|² + 0.2²·‖R − R_target‖²_F."""
    n = starts.shape[1]
    R, M, p = np.empty((3, 3)), np.empty((3, 3)), np.empty(3)
    q = np.empty(n)
    for i in range(n):
        q[i] = starts[0, i]
    _forward(geometry, q, R, p, np.empty((n, 3)), np.empty((n, 3)), M)
    d = 0.0
    for a in range(3):
        x = target[a, 3] - p[a]
        d += x * x
        for b in range(3):
            x = target[a, b] - R[a, b]
            d += 0.04 * x * x
    return d


@njit(cache=True, error_model="numpy")
def _score(scores, row, target):  # type: ignore[no-untyped-def]
    """A table row's score against the target's 16 entries in row order."""
    s = 0.0
    for a in range(4):
        for b in range(4):
            s += scores[row, 4 * a + b] * target[a, b]
    return s


@njit(cache=True, error_model="numpy")
def _nearest_row(scores, cell_scores, cell_bounds, t):  # type: ignore[no-untyped-def]
    """(table row, feature distance²) of the pose nearest the target t within the cell whose centre
    is nearest it. A score f·F_i − |F_i|²/2 is largest for the nearest pose."""
    best, centre = -math.inf, 0
    for c in range(scores.shape[0]):
        s = _score(scores, c, t)
        if s > best:
            best, centre = s, c
    best, row = -math.inf, cell_bounds[centre]
    for i in range(cell_bounds[centre], cell_bounds[centre + 1]):
        s = _score(cell_scores, i, t)
        if s > best:
            best, row = s, i
    return row, t[0, 3] * t[0, 3] + t[1, 3] * t[1, 3] + t[2, 3] * t[2, 3] + 0.12 - 2.0 * best


@njit(cache=True, error_model="numpy")
def first_tries(geometry, settings, scores, cell_scores, cell_bounds, table_q, target, seed, out):  # type: ignore[no-untyped-def]
    """A solve's first try: from the seed or, when the seed's pose is farther than settings[7] and
    the nearest table pose is nearer the target, from that table pose and then from the seed.
    Returns the table row tried (−1: none), which the restarts skip, or NEED_TABLE without trying
    when the seed is far and the table is empty (not built yet: `cell_bounds` of length < 2), or
    NOT_FINITE without trying when the target or the seed holds a NaN or an infinity (the loop
    would clamp a NaN to a limit without a word). Shapes are the caller's to check."""
    n = seed.shape[0]
    for a in range(4):
        for b in range(4):
            if not math.isfinite(target[a, b]):
                return NOT_FINITE
    for i in range(n):
        if not math.isfinite(seed[i]):
            return NOT_FINITE
    from_seed, both = np.empty((1, n)), np.empty((2, n))  # [seed] or [table pose, seed]
    for i in range(n):
        from_seed[0, i] = both[1, i] = min(max(seed[i], geometry[i, _LOWER]), geometry[i, _UPPER])
    d_seed = _feature_distance2(geometry, from_seed, target)
    if d_seed > settings[7]:
        if cell_bounds.shape[0] < 2:
            return NEED_TABLE
        row, d_table = _nearest_row(scores, cell_scores, cell_bounds, target)
        if d_table < d_seed:
            for i in range(n):
                both[0, i] = table_q[row, i]
            run_tries(geometry, settings, target, both, int(settings[0]), out)
            return row
    run_tries(geometry, settings, target, from_seed, int(settings[0]), out)
    return -1


@njit(cache=True, error_model="numpy")
def _insert_best(values, keys, value, key):  # type: ignore[no-untyped-def]
    """Keep `values` (largest first) and their `keys` the best len(values) seen: insert one."""
    k = values.shape[0]
    if not value > values[k - 1]:
        return
    i = k - 1
    while i > 0 and value > values[i - 1]:
        values[i], keys[i] = values[i - 1], keys[i - 1]
        i -= 1
    values[i], keys[i] = value, key


@njit(cache=True, error_model="numpy")
def restart_rows(scores, cell_scores, cell_bounds, target, cells, count, skip):  # type: ignore[no-untyped-def]
    """Table rows of the `count` poses nearest the target, nearest first, among the cells of the
    `cells` centres nearest it; row `skip` (the first try's) left out."""
    t = target
    k = min(cells, scores.shape[0])
    best_cells, chosen = np.empty(k), np.empty(k, dtype=np.int64)
    for i in range(k):
        best_cells[i], chosen[i] = -math.inf, -1
    for c in range(scores.shape[0]):
        _insert_best(best_cells, chosen, _score(scores, c, t), c)
    best_rows, rows = np.empty(count), np.empty(count, dtype=np.int64)
    for i in range(count):
        best_rows[i], rows[i] = -math.inf, -1
    for c in chosen:
        if c < 0:
            continue
        for i in range(cell_bounds[c], cell_bounds[c + 1]):
            if i != skip:
                _insert_best(best_rows, rows, _score(cell_scores, i, t), i)
    taken = 0
    while taken < count and rows[taken] >= 0:
        taken += 1
    return rows[:taken]
