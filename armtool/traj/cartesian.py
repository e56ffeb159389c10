"""`traj cartesian`: a straight line, a circle or arc, or a list of poses for the tool, turned into a
joint path by IK, each point seeded from the previous one (MoveIt's computeCartesianPath, without ROS).

* Sampling: each segment gets ceil(max(distance / eef_step_m, rotation / eef_step_rad)) steps.
* Precision (MoveIt's CartesianPrecision): the tool pose at the joint midpoint of two consecutive
  points must lie within `precision_m` / `precision_rad` of the ideal pose halfway between them;
  if not, the halfway pose is solved and inserted, recursively (at most `max_depth` halvings).
* Jumps: a step whose joint-space distance is over `jump_factor` × the mean step (MoveIt's
  relative rule, with at least 10 steps) or where any joint moves more than `max_step_rad` /
  `max_step_m` (absolute rule). Both rules are evaluated and reported; the path is cut before the
  first jump, as MoveIt cuts it.
* Closed forms (`analytic`: every solution of a pose): each point takes the solution nearest the
  previous one, and the steps over which the path changes branch are listed, each with the joint
  that flipped (`armtool.traj.branches`); a switch that breaks a jump rule is the jump the path is
  cut at, and its message says so.
* The result says the fraction of the path achieved and, if short of 1, why and where it stopped:
  unreachable (IK failed), joint limit, singularity (with the smallest singular value of the
  Jacobian), or jump.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal, Protocol

import numpy as np

from armtool.errors import ArmtoolError
from armtool.ik.solver import IKResult, rotation_error
from armtool.model.chain import Chain, axis_angle_batch
from armtool.traj.branches import BranchSwitch, branch_switches, nearest
from armtool.traj.check import jump_steps
from armtool.traj.trajectory import Array

PoseFn = Callable[[float], Array]  # λ in [0, 1] -> 4x4 pose
StopReason = Literal["", "unreachable", "joint limit", "singularity", "jump"]
SINGULAR_SIGMA = 1e-3


class PoseSolver(Protocol):
    """What the path needs of IK: an `armtool.ik` solver."""

    def solve(self, target: Array, seed: Array) -> IKResult: ...


@dataclass(frozen=True)
class Segment:
    pose_at: PoseFn
    length_m: float
    rotation_rad: float


@dataclass(frozen=True)
class CartesianOptions:
    eef_step_m: float = 0.01
    eef_step_rad: float = 0.05
    precision_m: float = 1e-3
    precision_rad: float = 0.01
    max_depth: int = 8
    jump_factor: float | None = 10.0
    max_step_rad: float | None = 0.5
    max_step_m: float | None = 0.1


@dataclass(frozen=True)
class CartesianResult:
    q: Array  # (M, n) the achieved joint path
    poses: Array  # (M, 4, 4) the ideal pose of each point
    params: Array  # (M,) path parameter of each point, 0..1 over the whole path
    fraction: float
    reason: StopReason
    detail: str
    inserted: int  # points added by the precision check
    max_deviation_m: float  # worst tool-position deviation at the joint midpoints of the achieved steps
    max_deviation_rad: float
    relative_jumps: list[int] = field(default_factory=list)  # step k: from point k to k+1
    absolute_jumps: list[int] = field(default_factory=list)
    midpoint_deviation_m: Array = field(
        default_factory=lambda: np.zeros(0)
    )  # per step: tool at the joint midpoint vs the path
    midpoint_deviation_rad: Array = field(default_factory=lambda: np.zeros(0))
    closed_form: bool = False  # the solver returned every solution: each point is the nearest one
    branch_switches: list[BranchSwitch] = field(default_factory=list)  # closed form only


def _slerp_R(R0: Array, R1: Array, lam: float) -> Array:
    w = rotation_error(R0, R1)  # R1 = exp(w) R0
    angle = float(np.linalg.norm(w))
    if angle < 1e-15:
        same: Array = R0.copy()
        return same
    out: Array = axis_angle_batch(w / angle, np.array([lam * angle]))[0] @ R0
    return out


def line_segment(start: Array, end: Array) -> Segment:
    R0, R1 = start[:3, :3], end[:3, :3]
    p0, p1 = start[:3, 3], end[:3, 3]

    def pose(lam: float) -> Array:
        T = np.eye(4)
        T[:3, :3] = _slerp_R(R0, R1, lam)
        T[:3, 3] = p0 + lam * (p1 - p0)
        return T

    return Segment(pose, float(np.linalg.norm(p1 - p0)), float(np.linalg.norm(rotation_error(R0, R1))))


def circle_segment(start: Array, center: Array, normal: Array, angle_rad: float) -> Segment:
    """The tool point turns about the axis through `center` along `normal` by `angle_rad`
    (right-handed), keeping the start orientation."""
    n = np.asarray(normal, dtype=np.float64)
    if not np.all(np.isfinite(n)) or np.linalg.norm(n) < 1e-12:
        raise ArmtoolError(
            "the circle's plane normal is zero", hint="e.g. --normal 1,0,0 for a circle in the y-z plane"
        )
    n = n / np.linalg.norm(n)
    r_vec = start[:3, 3] - center
    radius = float(np.linalg.norm(r_vec))
    if radius < 1e-6:
        raise ArmtoolError(
            f"the circle's radius is {radius:.3g} m: its centre is the tool's start position",
            hint="--center-offset must move the centre away from the start, e.g. --center-offset 0,-0.1,0",
        )
    if abs(float(r_vec @ n)) > 1e-6 * max(1.0, radius):
        raise ArmtoolError(
            "the start position is not in the circle's plane: (start − centre) is not perpendicular to the normal",
            hint="choose a centre offset perpendicular to --normal",
        )
    if not (math.isfinite(angle_rad) and angle_rad != 0):
        raise ArmtoolError(f"the arc angle must be non-zero, got {angle_rad}")
    K = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    eye, KK = np.eye(3), K @ K  # once, not per pose: a path samples thousands of poses

    def pose(lam: float) -> Array:
        th = lam * angle_rad
        Rn = eye + math.sin(th) * K + (1 - math.cos(th)) * KK
        T: Array = start.copy()
        T[:3, 3] = center + Rn @ r_vec
        return T

    return Segment(pose, abs(angle_rad) * radius, 0.0)


def circle_about(start: Array, center: Array, radius: float, normal: Array, angle_rad: float) -> list[Segment]:
    """The lecture's circle: a straight line from the start to centre + radius·e1, then the circle
    of `radius` about `center` in the plane normal to `normal` (e1, e2 = normal × e1: for normal x,
    e1 = y and e2 = z, so the points are (y + r cos θ, z + r sin θ) as in the lecture's loop)."""
    if not (math.isfinite(radius) and radius > 0):
        raise ArmtoolError(f"the circle's radius must be > 0 m, got {radius}", hint="e.g. --radius 0.1")
    n = np.asarray(normal, dtype=np.float64)
    if not np.all(np.isfinite(n)) or np.linalg.norm(n) < 1e-12:
        raise ArmtoolError(
            "the circle's plane normal is zero", hint="e.g. --normal 1,0,0 for a circle in the y-z plane"
        )
    n = n / np.linalg.norm(n)
    helper = next(e for e in np.eye(3) if abs(float(e @ n)) < 0.9)
    e1 = helper - (helper @ n) * n
    e1 /= np.linalg.norm(e1)
    first = start.copy()
    first[:3, 3] = center + radius * e1
    segments = []
    if np.linalg.norm(first[:3, 3] - start[:3, 3]) > 1e-9:
        segments.append(line_segment(start, first))
    return segments + [circle_segment(first, center, n, angle_rad)]


def arc_through(start: Array, via: Array, end: Array) -> Segment:
    """The circular arc from the start through `via` to `end` (Pilz CIRC with an interim point)."""
    a, b, c = start[:3, 3], np.asarray(via, float), np.asarray(end, float)
    ab, ac = b - a, c - a
    n = np.cross(ab, ac)
    if np.linalg.norm(n) < 1e-9:
        raise ArmtoolError(
            "the three arc points lie on one line: no circle passes through them",
            hint="move --arc-via off the line from the start to --arc-to",
        )
    # circumcentre
    center = a + (np.cross(n, ab) * (ac @ ac) + np.cross(ac, n) * (ab @ ab)) / (2 * (n @ n))
    n = n / np.linalg.norm(n)

    def ang(p: Array) -> float:
        u, v = a - center, p - center
        return math.atan2(float(np.cross(u, v) @ n), float(u @ v)) % (2 * math.pi)

    return circle_segment(start, center, n, ang(c))


class _Stepper:
    def __init__(self, chain: Chain, solver: PoseSolver, options: CartesianOptions) -> None:
        self.chain, self.solver, self.o = chain, solver, options
        self.inserted = 0
        self.steps_m: list[float] = []  # per kept step: the tool at its joint midpoint vs the path
        self.steps_rad: list[float] = []
        self.closed_form = False  # the solver returned every solution of a pose (analytic)

    def deviation(self, q: Array, target: Array) -> tuple[float, float]:
        T = self.chain.fk(q)
        return float(np.linalg.norm(T[:3, 3] - target[:3, 3])), float(
            np.linalg.norm(rotation_error(T[:3, :3], target[:3, :3]))
        )

    def solve(self, target: Array, seed: Array) -> tuple[Array | None, str]:
        r = self.solver.solve(target, seed)
        if r.success and r.solutions:
            self.closed_form = True
            return nearest(self.chain, r.solutions, seed), ""
        if r.success:
            return r.q, ""
        return None, r.reason

    def refine(
        self, seg: Segment, la: float, qa: Array, lb: float, qb: Array, depth: int
    ) -> list[tuple[float, Array]] | None:
        """Points strictly after la up to lb (inclusive), with midpoints inserted until precise."""
        mid_pose = seg.pose_at((la + lb) / 2)
        dm, dr = self.deviation((qa + qb) / 2, mid_pose)
        if (dm <= self.o.precision_m and dr <= self.o.precision_rad) or depth >= self.o.max_depth:
            self.steps_m.append(dm)
            self.steps_rad.append(dr)
            return [(lb, qb)]
        qm, _ = self.solve(mid_pose, qa)
        if qm is None:
            return None
        self.inserted += 1
        left = self.refine(seg, la, qa, (la + lb) / 2, qm, depth + 1)
        if left is None:
            return None
        right = self.refine(seg, (la + lb) / 2, qm, lb, qb, depth + 1)
        if right is None:  # forget the left half's deviations too: its points are not kept
            del self.steps_m[len(self.steps_m) - len(left) :], self.steps_rad[len(self.steps_rad) - len(left) :]
            return None
        return left + right


def _solve_without_limits(chain: Chain, target: Array, seed: Array, iterations: int = 300) -> Array | None:
    """A configuration reaching `target` with the joint limits ignored (damped least squares from
    `seed`), or None: tells a pose the limits forbid from one the arm cannot reach at all."""
    q: Array = np.array(seed, dtype=np.float64)
    damping = 1e-2
    for _ in range(iterations):
        T, J = chain.fk_jacobian(q)
        err = np.concatenate([target[:3, 3] - T[:3, 3], rotation_error(T[:3, :3], target[:3, :3])])
        if np.linalg.norm(err[:3]) < 1e-5 and np.linalg.norm(err[3:]) < 1e-4:
            return q
        q = q + J.T @ np.linalg.solve(J @ J.T + damping**2 * np.eye(6), err)
    return None


def _limit_blocking(chain: Chain, q: Array) -> tuple[int, float] | None:
    """The joint of `q` furthest outside its limits (a revolute joint may turn by 2π), and the limit."""
    worst: tuple[float, int, float] | None = None
    for j in range(chain.n):
        if chain.continuous[j]:
            continue
        lo, hi, v = float(chain.lower[j]), float(chain.upper[j]), float(q[j])
        if chain.revolute[j]:  # the same angle one turn away may lie inside
            v = min((v + k * 2 * math.pi for k in (-2, -1, 0, 1, 2)), key=lambda a: max(lo - a, a - hi, 0.0))
        excess = max(lo - v, v - hi)
        if excess > 1e-6 and (worst is None or excess > worst[0]):
            worst = (excess, j, lo if v < lo else hi)
    return None if worst is None else (worst[1], worst[2])


def _reach_m(chain: Chain) -> float:
    """An upper bound of the distance from the first joint to the tool: the sum of the offsets."""
    offsets = [float(np.linalg.norm(j.origin[:3, 3])) for j in chain.joints[1:]]
    prismatic = [max(abs(float(j.lower)), abs(float(j.upper))) for j in chain.joints if j.kind == "prismatic"]
    return sum(offsets) + float(np.linalg.norm(chain.tip_offset[:3, 3])) + sum(prismatic)


def sigma_min(chain: Chain, q: Array) -> float:
    """The smallest singular value of the chain's Jacobian at q: 0 at a singularity."""
    return float(np.linalg.svd(chain.jacobian(q), compute_uv=False)[-1])


def _why(chain: Chain, q: Array, target: Array, reason: str) -> tuple[StopReason, str]:
    """Why the pose `target` could not be reached from `q` (the last point of the path)."""
    sigma = sigma_min(chain, q)
    if sigma < SINGULAR_SIGMA:
        return (
            "singularity",
            f"near a singularity (σ_min of the Jacobian = {sigma:.2e}): the tool cannot move along the path there",
        )
    free = _solve_without_limits(chain, target, q)
    if free is not None:
        blocking = _limit_blocking(chain, free)
        if blocking is not None:
            j, limit = blocking
            unit = "rad" if chain.revolute[j] else "m"
            return (
                "joint limit",
                f"joint '{chain.joint_names[j]}' would have to pass its limit {limit:.4g} {unit} "
                f"(it is at {q[j]:.4g} {unit}) to follow the path",
            )
        return "unreachable", f"the IK solver failed ({reason or 'no solution'}) though the pose is within the limits"
    at_limit = np.flatnonzero((((q - chain.lower) < 1e-3) | ((chain.upper - q) < 1e-3)) & ~chain.continuous)
    if at_limit.size:
        j = int(at_limit[0])
        return "joint limit", f"joint '{chain.joint_names[j]}' is at its limit ({q[j]:.4g}); {reason}"
    first = chain.joints[0].origin[:3, 3]
    distance, reach = float(np.linalg.norm(target[:3, 3] - first)), _reach_m(chain)
    if distance > reach:
        return (
            "unreachable",
            f"the path leaves the arm's reach: the target is {distance:.3f} m from the first joint, the arm reaches "
            f"at most {reach:.3f} m",
        )
    return (
        "unreachable",
        "the pose there is out of the arm's workspace for the tool's orientation along the path: IK finds "
        "no solution even with the joint limits ignored",
    )


def compute_cartesian(
    chain: Chain, solver: PoseSolver, start_q: Array, segments: list[Segment], options: CartesianOptions
) -> CartesianResult:
    """Follow `segments` from the configuration `start_q` (their first pose must be FK(start_q))."""
    o = options
    if not (o.eef_step_m > 0 and o.eef_step_rad > 0):
        raise ArmtoolError("--eef-step must be positive", hint="e.g. --eef-step 0.01 (m) and --eef-step-rad 0.05")
    total = sum(max(s.length_m, 1e-12) for s in segments)
    stepper = _Stepper(chain, solver, o)
    qs: list[Array] = [np.asarray(start_q, dtype=np.float64)]
    poses: list[Array] = [segments[0].pose_at(0.0)]
    params: list[float] = [0.0]
    reason: StopReason = ""
    detail = ""
    done = 0.0
    for seg in segments:
        steps = max(1, math.ceil(max(seg.length_m / o.eef_step_m, seg.rotation_rad / o.eef_step_rad) - 1e-9))
        la = 0.0
        for k in range(1, steps + 1):
            lb = k / steps
            target = seg.pose_at(lb)
            qb, why = stepper.solve(target, qs[-1])
            if qb is None:
                reason, detail = _why(chain, qs[-1], target, why)
                break
            pts = stepper.refine(seg, la, qs[-1], lb, qb, 0)
            if pts is None:
                reason, detail = _why(chain, qs[-1], seg.pose_at((la + lb) / 2), "IK failed at an inserted midpoint")
                break
            for lam, q in pts:
                qs.append(q)
                poses.append(seg.pose_at(lam))
                params.append((done + lam * max(seg.length_m, 1e-12)) / total)
            la = lb
        if reason:
            break
        done += max(seg.length_m, 1e-12)
    q = np.asarray(qs)
    relative, absolute = jump_steps(q, o.jump_factor, None)
    lim = None
    if o.max_step_rad is not None or o.max_step_m is not None:
        lim = np.where(
            chain.revolute,
            o.max_step_rad if o.max_step_rad is not None else np.inf,
            o.max_step_m if o.max_step_m is not None else np.inf,
        )
        absolute = np.flatnonzero((np.abs(np.diff(q, axis=0)) > lim).any(axis=1)).tolist()
    jumps = sorted(set(relative) | set(absolute))
    switches = branch_switches(chain, q, np.asarray(params), set(jumps), lim) if stepper.closed_form else []
    cut = len(q)
    if jumps:
        k = jumps[0]
        cut = k + 1
        d = np.abs(q[k + 1] - q[k])
        j = int(np.argmax(d))
        rules = [name for name, hits in (("relative", relative), ("absolute", absolute)) if k in hits]
        reason, detail = (
            "jump",
            (
                f"joint '{chain.joint_names[j]}' jumps {d[j]:.4f} from point {k} to {k + 1} at path parameter "
                f"{params[k + 1]:.4f} ({' and '.join(rules)} rule{'s' if len(rules) > 1 else ''})"
                + next((f": {b.text().partition(': ')[2]}" for b in switches if b.step == k), "")
            ),
        )
    fraction = 1.0 if not reason else float(params[cut - 1])
    # The deviations of the achieved steps only: not of a step cut off as a jump, nor of the
    # halves of a step whose other half failed (refine forgets those).
    kept_m, kept_rad = np.asarray(stepper.steps_m[: cut - 1]), np.asarray(stepper.steps_rad[: cut - 1])
    return CartesianResult(
        q[:cut],
        np.asarray(poses[:cut]),
        np.asarray(params[:cut]),
        fraction,
        reason,
        detail,
        stepper.inserted,
        float(kept_m.max(initial=0.0)),
        float(kept_rad.max(initial=0.0)),
        relative,
        absolute,
        kept_m,
        kept_rad,
        stepper.closed_form,
        switches,
    )
