"""A closed-form path (`traj cartesian` with `analytic`): the solution nearest the previous point, and
where the path changes branch.

Nearest. A closed form returns every solution of a pose. Each is placed as `analytic` places its own
(`armtool.ik.solutions.place`: every revolute angle moved by whole turns to the value nearest the
previous point's, then into the limits if that one is outside), and the path takes the one whose
largest joint step, max_j |q_j − q_prev,j|, is smallest: the quantity the absolute jump rule judges
(a Euclidean distance can prefer one large step of one joint to small steps of all).

Branch switch. A jump of a closed-form path (a step that breaks a jump rule of
`armtool.traj.cartesian`) is a switch to another solution branch: the nearest solution at the next
point is not the previous one carried on, most often because that one leaves the joint limits (a
joint that the previous step, repeated, would take past its limit is named) or its branch's reach. It is reported with the joints that flip
(those over the absolute rule's step, else those moving at least half the largest step), each from →
to, and the path is cut there, as at any jump.

Singular passage. The singular configurations (det J = 0, J the chain's 6×6 Jacobian) divide joint
space into aspects (Borrel & Liégeois 1986); on the non-cuspidal arms `analytic` solves (UR-type,
spherical wrist; Wenger 1992) the aspects are the closed form's branches (shoulder, elbow, wrist
flip). A step over which det J changes sign with small joint steps crosses from one branch to the
other continuously, through a singular configuration: the arm can execute it, so it is listed, not
cut. The joint named is the one whose step alone changes the sign (the middle wrist joint through
zero, the elbow through its stretched angle), else the one that moves most. Points within
SINGULAR_DET of det J = 0 belong to neither side (on a path that runs along a singularity, det J's
sign is rounding). det J alone cannot tell a jump's branches apart: a jump that flips two factors
of det J (shoulder and wrist) keeps its sign.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from armtool.ik.solutions import place
from armtool.model.chain import Chain
from armtool.traj.trajectory import Array

TAU = 2.0 * math.pi
WHOLE_TURN_RAD = 1e-3  # a step this close to a multiple of 2π is the same configuration one turn away
POSE_DOF = 6
SINGULAR_DET = 1e-9  # |det J| below this: at the singularity, on neither side (rounding decides the sign)
LIMIT_NEAR = 1e-6  # rad or m: a joint this close to a limit is at it


def nearest(chain: Chain, solutions: tuple[Array, ...], previous: Array) -> Array:
    """The solution with the smallest largest joint step from `previous` (see the module docstring)."""
    placed = place(chain, np.asarray(solutions, dtype=np.float64), previous)
    if placed.shape[0] == 0:  # each solution passed the check within the limits: none is dropped
        placed = np.asarray(solutions, dtype=np.float64)
    best: Array = placed[int(np.argmin(np.abs(placed - previous).max(axis=1)))]
    return best


@dataclass(frozen=True)
class Flip:
    joint: str
    from_value: float
    to_value: float

    def text(self) -> str:
        return f"'{self.joint}' {self.from_value:.4f} → {self.to_value:.4f} ({self.to_value - self.from_value:+.4f})"


@dataclass(frozen=True)
class BranchSwitch:
    """A step k (point k → k+1) over which the path changes branch: a jump, or a singular passage."""

    step: int
    param: float  # path parameter of point k+1, 0..1 over the whole path
    jump: bool  # the step breaks a jump rule (the path is cut at the first)
    flips: tuple[Flip, ...]  # the joints that flip, the largest step first
    note: str = ""  # a joint at its limit, or a step of whole turns

    def text(self) -> str:
        what = "jump to another branch" if self.jump else "singular passage (small steps, not a jump)"
        return (
            f"step {self.step} (point {self.step} → {self.step + 1}, path parameter {self.param:.4f}): {what}: "
            + ", ".join(f.text() for f in self.flips)
            + (f"; {self.note}" if self.note else "")
        )


def _signs(chain: Chain, Q: Array) -> Array:
    _, J = chain.fk_jacobian_batch(Q)
    assert J is not None
    det = np.linalg.det(J)
    signs: Array = np.where(np.abs(det) < SINGULAR_DET, 0.0, np.sign(det))
    return signs


def branch_switches(
    chain: Chain, q: Array, params: Array, jumps: set[int], max_step: Array | None
) -> list[BranchSwitch]:
    """Every jump step of the closed-form path `q` (M, n) as a branch switch, and the steps over which
    det J changes sign with small steps (6-DoF chains only: J is square). `max_step`: the absolute
    rule's limit per joint (None: off)."""
    out = [_jump(chain, q, params, k, max_step) for k in sorted(jumps)]
    if chain.n == POSE_DOF and len(q) >= 2:
        signs = _signs(chain, q)
        last = 0  # the last point off the singularity
        for k in range(1, len(q)):
            if signs[k] == 0:
                continue
            if signs[last] != 0 and signs[k] != signs[last] and (k - 1) not in jumps:
                # from the last point off the singularity: the points between sit on it
                j = _flipped(chain, q[last], q[k], signs[last])
                flip = Flip(chain.joint_names[j], float(q[last, j]), float(q[k, j]))
                out.append(BranchSwitch(k - 1, float(params[k]), False, (flip,)))
            last = k
    return sorted(out, key=lambda b: b.step)


def _jump(chain: Chain, q: Array, params: Array, k: int, max_step: Array | None) -> BranchSwitch:
    step = q[k + 1] - q[k]
    size = np.abs(step)
    over = np.flatnonzero(size > max_step) if max_step is not None else np.zeros(0, dtype=int)
    if over.size == 0:
        over = np.flatnonzero(size >= 0.5 * size.max())
    order = over[np.argsort(-size[over], kind="stable")]
    flips = tuple(Flip(chain.joint_names[j], float(q[k, j]), float(q[k + 1, j])) for j in order)
    notes = []
    turned = whole_turns(chain, step)
    if turned is not None:
        notes.append(
            f"'{chain.joint_names[turned]}' turns by whole turns: the same angle, one nearer is outside its limits"
        )
    # The branch carried on as it went (the previous step again) would leave the limits here:
    ahead = 2 * q[k] - q[k - 1] if k > 0 else q[k]
    blocked = [
        j
        for j in range(chain.n)
        if not chain.continuous[j]
        and (
            ahead[j] < chain.lower[j] - LIMIT_NEAR
            or ahead[j] > chain.upper[j] + LIMIT_NEAR
            or min(abs(q[k, j] - chain.lower[j]), abs(q[k, j] - chain.upper[j])) < LIMIT_NEAR
        )
    ]
    if blocked:
        notes.append(
            ", ".join(
                f"'{chain.joint_names[j]}' at {q[k, j]:.4f} reaches its limit "
                f"{chain.lower[j] if ahead[j] < q[k, j] else chain.upper[j]:.4f}"
                for j in blocked
            )
            + ": the branch cannot go on within the limits"
        )
    return BranchSwitch(k, float(params[k + 1]), True, flips, "; ".join(notes))


def _flipped(chain: Chain, qa: Array, qb: Array, sign: float) -> int:
    """The joint whose step alone (the others at qa) changes det J's sign from `sign`; of several,
    the one that moves most; of none, the joint that moves most."""
    moved = np.abs(qb - qa)
    trial = np.tile(qa, (chain.n, 1))
    trial[np.arange(chain.n), np.arange(chain.n)] = qb
    alone = np.flatnonzero(_signs(chain, trial) == -sign)
    pool = alone if alone.size else np.arange(chain.n)
    return int(pool[np.argmax(moved[pool])])


def whole_turns(chain: Chain, step: Array) -> int | None:
    """The joint whose step is a non-zero multiple of 2π (the same angle one or more turns away), or None."""
    for j in np.flatnonzero(chain.revolute):
        turns = round(float(step[j]) / TAU)
        if turns and abs(float(step[j]) - turns * TAU) < WHOLE_TURN_RAD:
            return int(j)
    return None
