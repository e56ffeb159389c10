"""`traj check`: a linter for joint trajectories. Each finding has a code, a severity, and names
the point index, its time and the joint; its line is the point's line in the file.

Between samples the trajectory is what a controller interpolating positions and velocities
executes: on each segment the cubic Hermite polynomial through (t, q, q̇) at both ends (ros_control's
joint_trajectory_controller does this for position+velocity points). Its velocity (quadratic),
acceleration (linear) and jerk (constant) are checked exactly over the whole segment, not only at
the samples. A file without velocities is checked by finite differences of the positions. A file's
own velocity and acceleration fields are checked at the samples as well.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from armtool.docs_links import DOCS_URL
from armtool.lint.finding import Finding, Severity
from armtool.traj.limits import JointLimits
from armtool.traj.trajectory import Array, Trajectory

if TYPE_CHECKING:
    from armtool.output.sarif import SarifTool

VEL_TOL = 1e-6  # relative: |v| ≤ limit·(1 + VEL_TOL)
ACC_TOL = 1e-3
JERK_TOL = 1e-3


class Code(NamedTuple):
    code: str
    name: str
    severity: Severity
    summary: str


CODES: dict[str, Code] = {
    c.code: c
    for c in (
        Code(
            "T101", "time-not-increasing", Severity.ERROR, "time_from_start must increase strictly from point to point."
        ),
        Code("T201", "position-out-of-limits", Severity.ERROR, "A position lies outside the joint's limits."),
        Code(
            "T301",
            "velocity-over-limit",
            Severity.ERROR,
            "A joint moves faster than its velocity limit (file field, or between samples).",
        ),
        Code(
            "T302", "acceleration-over-limit", Severity.ERROR, "A joint accelerates harder than its acceleration limit."
        ),
        Code("T303", "jerk-over-limit", Severity.ERROR, "A joint's jerk exceeds its jerk limit."),
        Code(
            "T304",
            "velocity-not-checked",
            Severity.WARNING,
            'A joint has no positive velocity limit (URDF velocity="0" or none given): its speed was not checked.',
        ),
        Code(
            "T401",
            "velocity-inconsistent",
            Severity.ERROR,
            "The file's velocities do not match how its positions change over time.",
        ),
        Code(
            "T501",
            "joint-jump",
            Severity.ERROR,
            "One step in joint space is far larger than the others (an IK branch switch).",
        ),
        Code(
            "T601",
            "unknown-joint",
            Severity.ERROR,
            "The trajectory names a joint that the URDF lacks (or that cannot move).",
        ),
        Code("T602", "duplicate-joint", Severity.ERROR, "The trajectory names a joint twice."),
        Code(
            "T701",
            "start-not-at-rest",
            Severity.WARNING,
            "The first point has a non-zero velocity: the controller starts with a jolt.",
        ),
        Code(
            "T702",
            "end-not-at-rest",
            Severity.WARNING,
            "The last point has a non-zero velocity: the arm must stop abruptly.",
        ),
    )
}

HELP_URI = DOCS_URL + "traj.md#check-codes"


def sarif_tool() -> SarifTool:
    """`traj check`'s SARIF driver: the T codes, documented in the manual's traj page."""
    from armtool.output.sarif import SarifRule, SarifTool

    return SarifTool(
        "armtool traj check",
        [SarifRule(c.code, c.name, c.summary, c.summary, c.severity, HELP_URI) for c in CODES.values()],
    )


@dataclass(frozen=True)
class CheckOptions:
    jump_factor: float = 10.0  # relative rule: step > factor × mean step (untimed paths, ≥ 10 steps)
    max_step: float | None = None  # absolute rule: rad (or m) per step, any path
    rest_tol: float = 1e-3  # start/end at rest: |v| ≤ rest_tol × velocity limit


def _finding(traj: Trajectory, code: str, index: int, message: str, hint: str | None = None) -> Finding:
    c = CODES[code]
    return Finding(traj.source, traj.line(index), 1, c.code, c.name, c.severity, message, hint)


def _at(traj: Trajectory, i: int) -> str:
    t = f", t={traj.times[i]:.4f} s" if traj.times is not None else ""
    return f"point {i}{t}"


def _runs(mask: np.ndarray) -> Iterator[tuple[int, int]]:
    """(start, stop) of each run of True."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return
    breaks = np.flatnonzero(np.diff(idx) > 1)
    starts = np.concatenate([[idx[0]], idx[breaks + 1]])
    stops = np.concatenate([idx[breaks], [idx[-1]]]) + 1
    yield from zip(starts.tolist(), stops.tolist())


def _over(
    traj: Trajectory,
    code: str,
    values: Array,
    points: np.ndarray,
    limit: Array,
    tol: float,
    names: tuple[str, ...],
    what: str,
    unit: tuple[str, ...],
    source: str,
) -> Iterator[Finding]:
    """One finding per joint and run of consecutive offending samples: the worst of the run."""
    for j in range(values.shape[1]):
        if not math.isfinite(limit[j]):
            continue
        ratio = np.abs(values[:, j]) / limit[j]
        for a, b in _runs(ratio > 1 + tol):
            k = a + int(np.argmax(ratio[a:b]))
            i = int(points[k])
            span = f" ({b - a} samples from {_at(traj, int(points[a]))})" if b - a > 1 else ""
            yield _finding(
                traj,
                code,
                i,
                f"{_at(traj, i)}, joint '{names[j]}': {what} {abs(values[k, j]):.6g} {unit[j]} "
                f"> limit {limit[j]:.6g} {unit[j]} ({ratio[k]:.4f}×, {source}){span}",
                "re-time it: armtool traj time PATH --urdf URDF (or `armtool traj retime --scale S` with S < 1)",
            )


def hermite_extremes(t: Array, q: Array, v: Array) -> tuple[Array, Array, Array]:
    """Per segment and joint, the largest |velocity|, |acceleration| and |jerk| of the cubic
    Hermite through (t, q, v) at its ends: (N-1, n) each, exact over the segment. The jerk also
    counts the step of acceleration at the segment's start knot, spread over the two segments'
    mean duration (the Hermite's acceleration is continuous inside a segment, not across knots)."""
    T = np.diff(t)[:, None]
    dq = np.diff(q, axis=0)
    v0, v1 = v[:-1], v[1:]
    c2 = (3 * dq / T - 2 * v0 - v1) / T
    c3 = (-2 * dq / T + v0 + v1) / T**2
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = np.where(np.abs(c3) > 0, -c2 / (3 * c3), -1.0)
    inside = (tau > 0) & (tau < T)
    v_mid = np.where(inside, v0 + 2 * c2 * tau + 3 * c3 * tau**2, 0.0)
    vmax = np.maximum(np.maximum(np.abs(v0), np.abs(v1)), np.abs(v_mid))
    a_start, a_end = 2 * c2, 2 * c2 + 6 * c3 * T
    amax = np.maximum(np.abs(a_start), np.abs(a_end))
    jerk = np.abs(6 * c3)
    if len(T) > 1:
        knot = np.abs(a_start[1:] - a_end[:-1]) / ((T[1:] + T[:-1]) / 2)
        jerk[1:] = np.maximum(jerk[1:], knot)
    return vmax, amax, jerk


def check(traj: Trajectory, limits: JointLimits, options: CheckOptions = CheckOptions()) -> list[Finding]:
    """Every finding for `traj` against `limits` (joints matched by name)."""
    findings: list[Finding] = []
    seen: set[str] = set()
    known: list[str] = []
    for name in traj.joint_names:
        if name in seen:
            findings.append(_finding(traj, "T602", 0, f"joint '{name}' appears twice in joint_names"))
            continue
        seen.add(name)
        if name not in limits.names:
            from armtool.suggest import did_you_mean

            findings.append(
                _finding(
                    traj,
                    "T601",
                    0,
                    f"joint '{name}' is not a moving joint of the URDF{did_you_mean(name, list(limits.names))}",
                    "rename it to the URDF's joint name, or pass the URDF this trajectory is for",
                )
            )
        else:
            known.append(name)
    if not known:
        return findings
    sub = traj.reorder(known) if len(set(traj.joint_names)) == len(traj.joint_names) else _first_of_each(traj, known)
    lim = limits.subset(known)
    names = tuple(known)
    units = tuple(lim.unit(j) for j in range(len(names)))
    q = sub.positions
    # positions
    lower_ok = q >= lim.lower - 1e-9
    upper_ok = q <= lim.upper + 1e-9
    for j in range(len(names)):
        for a, b in _runs(~(lower_ok[:, j] & upper_ok[:, j])):
            k = a + int(np.argmax(np.maximum(lim.lower[j] - q[a:b, j], q[a:b, j] - lim.upper[j])))
            span = f" ({b - a} points from point {a})" if b - a > 1 else ""
            findings.append(
                _finding(
                    sub,
                    "T201",
                    k,
                    f"{_at(sub, k)}, joint '{names[j]}': position {q[k, j]:.6g} {units[j]} "
                    f"outside [{lim.lower[j]:.6g}, {lim.upper[j]:.6g}]{span}",
                )
            )
    findings += list(_jumps(sub, names, units, options))
    if sub.times is not None and sub.n_points > 1:
        findings += list(_unchecked_velocity(sub, lim, names))
        findings += list(_timed(sub, lim, names, units, options))
    return sorted(findings, key=lambda f: (f.line, f.code))


def _unchecked_velocity(traj: Trajectory, lim: JointLimits, names: tuple[str, ...]) -> Iterator[Finding]:
    """One finding for the timed trajectory's joints that have no velocity limit to check against:
    without it, a URDF with velocity="0" (which MoveIt cannot plan with) would let any speed pass
    as "All checks passed"."""
    missing = [j for j in range(len(names)) if not (math.isfinite(lim.velocity[j]) and lim.velocity[j] > 0)]
    if not missing:
        return
    which = ", ".join(f"'{names[j]}' ({lim.sources[j]})" for j in missing)
    yield _finding(
        traj,
        "T304",
        0,
        f"no positive velocity limit for joint{'s' if len(missing) > 1 else ''} {which} "
        "(<limit velocity> is 0 or missing): their velocity was not checked",
        f"set <limit velocity> in the URDF, max_velocity in joint_limits.yaml, or --vel-limit {names[missing[0]]}=VALUE",
    )


def _first_of_each(traj: Trajectory, known: list[str]) -> Trajectory:
    from dataclasses import replace

    idx = [traj.joint_names.index(n) for n in known]
    return replace(
        traj,
        joint_names=tuple(known),
        positions=traj.positions[:, idx],
        velocities=None if traj.velocities is None else traj.velocities[:, idx],
        accelerations=None if traj.accelerations is None else traj.accelerations[:, idx],
        prismatic=tuple(traj.is_prismatic(i) for i in idx),
    )


def jump_steps(q: Array, factor: float | None, max_step: float | None) -> tuple[list[int], list[int]]:
    """Steps k (from point k to k+1) that jump: by the relative rule (joint-space distance > factor ×
    mean distance, MoveIt's rule, applied with at least 10 steps) and by the absolute rule (any joint
    moves more than max_step)."""
    d = np.abs(np.diff(q, axis=0))
    relative: list[int] = []
    if factor is not None and factor > 0 and d.shape[0] >= 10:
        dist = d.sum(axis=1)
        relative = np.flatnonzero(dist > factor * dist.mean()).tolist()
    absolute = np.flatnonzero(d.max(axis=1) > max_step).tolist() if max_step is not None else []
    return relative, absolute


def _jumps(
    traj: Trajectory, names: tuple[str, ...], units: tuple[str, ...], options: CheckOptions
) -> Iterator[Finding]:
    # A timed trajectory's jump is a velocity over its limit; the relative rule is for paths.
    factor = options.jump_factor if traj.times is None else None
    relative, absolute = jump_steps(traj.positions, factor, options.max_step)
    d = np.abs(np.diff(traj.positions, axis=0))
    mean = float(d.sum(axis=1).mean()) if d.size else 0.0
    for k in sorted(set(relative) | set(absolute)):
        j = int(np.argmax(d[k]))
        rules = []
        if k in relative:
            rules.append(f"{d[k].sum() / mean:.1f}× the mean step (relative rule, factor {options.jump_factor:g})")
        if k in absolute:
            rules.append(f"over --max-step {options.max_step:g} (absolute rule)")
        yield _finding(
            traj,
            "T501",
            k + 1,
            f"{_at(traj, k + 1)}, joint '{names[j]}': jumps {d[k, j]:.4g} {units[j]} from point {k}: "
            + " and ".join(rules),
            "an IK branch switch: re-plan with a seed, or use an analytic solver's nearest solution",
        )


def _timed(
    traj: Trajectory, lim: JointLimits, names: tuple[str, ...], units: tuple[str, ...], options: CheckOptions
) -> Iterator[Finding]:
    assert traj.times is not None
    t = traj.times
    dt = np.diff(t)
    bad = np.flatnonzero(~(dt > 0))
    for k in bad:
        yield _finding(
            traj,
            "T101",
            int(k) + 1,
            f"point {k + 1}: time {t[k + 1]:.6g} s is not after point {k}'s {t[k]:.6g} s",
            "times must increase strictly; re-time it with armtool traj time",
        )
    if bad.size:
        return  # rates between points are meaningless without increasing time
    vu = tuple(f"{u}/s" for u in units)
    au = tuple(f"{u}/s²" for u in units)
    ju = tuple(f"{u}/s³" for u in units)
    seg_points = np.arange(traj.n_points - 1) + 1  # a segment's finding points at its end point
    q, v, a = traj.positions, traj.velocities, traj.accelerations
    if v is not None:
        yield from _over(
            traj,
            "T301",
            v,
            np.arange(traj.n_points),
            lim.velocity,
            VEL_TOL,
            names,
            "velocity",
            vu,
            "file's velocity field",
        )
        vmax, amax, jmax = hermite_extremes(t, q, v)
        yield from _over(
            traj, "T301", vmax, seg_points, lim.velocity, VEL_TOL, names, "velocity", vu, "between samples"
        )
        yield from _over(
            traj, "T302", amax, seg_points, lim.acceleration, ACC_TOL, names, "acceleration", au, "between samples"
        )
        yield from _over(traj, "T303", jmax, seg_points, lim.jerk, JERK_TOL, names, "jerk", ju, "between samples")
        yield from _consistency(traj, lim, names, units)
        yield from _rest(traj, v, lim, names, vu, options)
    else:
        fd_v = np.diff(q, axis=0) / dt[:, None]
        yield from _over(
            traj, "T301", fd_v, seg_points, lim.velocity, VEL_TOL, names, "velocity", vu, "finite difference"
        )
        if traj.n_points > 2:
            mid = (t[2:] - t[:-2]) / 2
            fd_a = np.diff(fd_v, axis=0) / mid[:, None]
            yield from _over(
                traj,
                "T302",
                fd_a,
                np.arange(1, traj.n_points - 1),
                lim.acceleration,
                ACC_TOL,
                names,
                "acceleration",
                au,
                "finite difference",
            )
            if traj.n_points > 3:
                fd_j = np.diff(fd_a, axis=0) / dt[1:-1, None]
                yield from _over(
                    traj,
                    "T303",
                    fd_j,
                    np.arange(2, traj.n_points - 1),
                    lim.jerk,
                    JERK_TOL,
                    names,
                    "jerk",
                    ju,
                    "finite difference",
                )
    if a is not None:
        yield from _over(
            traj,
            "T302",
            a,
            np.arange(traj.n_points),
            lim.acceleration,
            ACC_TOL,
            names,
            "acceleration",
            au,
            "file's acceleration field",
        )


def _consistency(
    traj: Trajectory, lim: JointLimits, names: tuple[str, ...], units: tuple[str, ...]
) -> Iterator[Finding]:
    """Mean velocity Δq/Δt against the ends' (v0 + v1)/2: for any motion whose acceleration stays
    within ±A they differ by at most A·Δt/4 (a switch from +A to −A halfway reaches it)."""
    assert traj.times is not None and traj.velocities is not None
    dt = np.diff(traj.times)[:, None]
    v = traj.velocities
    gap = np.abs(np.diff(traj.positions, axis=0) / dt - (v[:-1] + v[1:]) / 2)
    acc_bound = np.where(np.isfinite(lim.acceleration), lim.acceleration, np.nan)
    if traj.accelerations is not None:
        file_acc = np.abs(traj.accelerations)
        acc_bound = np.fmax(acc_bound, np.maximum(file_acc[:-1], file_acc[1:]).max(axis=0))
    vel_scale = np.where(np.isfinite(lim.velocity), lim.velocity, np.abs(v).max(axis=0) + 1e-9)
    tol = np.where(np.isfinite(acc_bound), 1.05 * acc_bound * dt / 4, 0.1 * vel_scale) + 1e-3 * vel_scale + 1e-9
    for j in range(len(names)):
        for a, b in _runs(gap[:, j] > tol[:, j]):
            k = a + int(np.argmax(gap[a:b, j] - tol[a:b, j]))
            span = f" ({b - a} segments)" if b - a > 1 else ""
            yield _finding(
                traj,
                "T401",
                k + 1,
                f"{_at(traj, k + 1)}, joint '{names[j]}': moves at {float(np.diff(traj.positions[k : k + 2, j])[0] / dt[k, 0]):.6g} "
                f"{units[j]}/s on average from point {k}, but its velocities say {v[k, j]:.6g} and {v[k + 1, j]:.6g}{span}",
                "the velocities do not belong to these positions and times; re-time it with armtool traj time",
            )


def _rest(
    traj: Trajectory, v: Array, lim: JointLimits, names: tuple[str, ...], vu: tuple[str, ...], options: CheckOptions
) -> Iterator[Finding]:
    scale = np.where(np.isfinite(lim.velocity), lim.velocity, 1.0)
    for code, i, what in (("T701", 0, "starts"), ("T702", traj.n_points - 1, "ends")):
        moving = np.flatnonzero(np.abs(v[i]) > options.rest_tol * scale)
        if moving.size:
            j = int(moving[np.argmax(np.abs(v[i, moving]))])
            yield _finding(
                traj,
                code,
                i,
                f"{_at(traj, i)}, joint '{names[j]}': the trajectory {what} at {v[i, j]:.6g} {vu[j]}, not at rest",
                "time it rest to rest: armtool traj time",
            )
