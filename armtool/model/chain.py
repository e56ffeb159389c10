"""A serial chain base → tip read from a URDF: joint origins, axes, limits; kinematics from Pinocchio.

The chain is T(q) = Π_i (origin_i · motion_i(q_i)) · tip_offset, where origin_i folds in every
fixed joint since the previous moving joint. Pinocchio evaluates it (FK, frame Jacobian);
`fk_batch` evaluates the same product with numpy over many configurations at once.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from lxml import etree
from numpy.typing import NDArray

from armtool.errors import ArmtoolError
from armtool.suggest import did_you_mean

Array = NDArray[np.float64]
JointKind = Literal["revolute", "prismatic", "continuous"]


# Beyond this (m, or rad for a revolute limit) a number is no robot's: 1000 km. Below it, FK and
# squared errors stay far from overflow (an origin of 1e200 m overflowed them; a limit range of
# ±1e308 made sampling the targets fail).
MAX_ABS = 1e6


def _floats(text: str | None, n: int, default: Sequence[float], what: str = "", bound: float = math.inf) -> list[float]:
    """`n` finite numbers from an attribute (default when absent); `what` names it in messages
    ("joint 'elbow' <origin xyz>"); `bound`: the largest magnitude accepted."""
    if text is None:
        return list(default)
    try:
        values = [float(v) for v in text.split()]
    except ValueError:
        values = []
    label = f"{what}: " if what else ""
    if len(values) != n or not all(math.isfinite(v) for v in values):
        raise ArmtoolError(
            f"{label}bad numbers '{text[:80]}' (expected {n} finite number{'s' if n > 1 else ''})",
            hint="run `armtool lint` on the URDF",
        )
    if any(abs(v) > bound for v in values):
        raise ArmtoolError(
            f"{label}'{text[:80]}' is beyond ±{bound:g} (m or rad), larger than any robot",
            hint="check the units, or run `armtool lint` on the URDF",
        )
    return values


def rpy_matrix(roll: float, pitch: float, yaw: float) -> Array:
    """URDF rpy: fixed-axis X, then Y, then Z: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr, cp, sp, cy, sy = (
        math.cos(roll),
        math.sin(roll),
        math.cos(pitch),
        math.sin(pitch),
        math.cos(yaw),
        math.sin(yaw),
    )
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def origin_matrix(el: etree._Element | None, what: str = "") -> Array:
    """The 4x4 transform of an <origin xyz rpy> (identity when absent); `what` names its owner in messages."""
    T = np.eye(4)
    if el is not None:
        T[:3, :3] = rpy_matrix(*_floats(el.get("rpy"), 3, (0, 0, 0), f"{what} <origin rpy>".strip()))
        T[:3, 3] = _floats(el.get("xyz"), 3, (0, 0, 0), f"{what} <origin xyz>".strip(), MAX_ABS)
    return T


@dataclass(frozen=True)
class ChainJoint:
    name: str
    kind: JointKind
    origin: Array  # 4x4, from the previous moving joint's frame (or the base) to this joint's frame
    axis: Array  # unit vector in this joint's frame
    lower: float
    upper: float


@dataclass(frozen=True)
class _PlanStep:
    """One joint of fk_jacobian_soa's plan (see Chain._batch_plan)."""

    o_R: Array
    o_Rt: Array
    o_p: Array
    col: int  # the rotation column the joint's axis lies on
    turned: slice  # the columns a revolute joint turns: 0:2, 1:3 or 0:3:2
    a: int  # which of them is a (turned towards b) and which b, within that slice
    b: int
    sign: float
    prismatic: bool
    undo: Array | None  # an unaligned axis's basis B: R ← R·Bᵀ after the motion (`B @ R` on the (3,N) blocks)


@dataclass(frozen=True)
class _UrdfJoint:
    name: str
    type: str
    parent: str
    child: str
    el: etree._Element


def _urdf_joints(root: etree._Element) -> dict[str, _UrdfJoint]:
    """child link -> joint"""
    out: dict[str, _UrdfJoint] = {}
    for el in root.findall("joint"):
        parent, child = el.find("parent"), el.find("child")
        if parent is None or child is None:
            continue
        j = _UrdfJoint(el.get("name", ""), el.get("type", ""), parent.get("link", ""), child.get("link", ""), el)
        out[j.child] = j
    return out


# Joints that move fingers rather than the arm (Franka fr3_finger_joint1, SO-101 gripper, Robotiq knuckles).
_GRIPPER_JOINT = re.compile(r"finger|gripper|jaw|claw|knuckle|thumb|pinch", re.IGNORECASE)
# Tool frames, best first: where a user means "the end of the arm".
_TOOL_FRAMES = tuple(
    re.compile(p, re.IGNORECASE)
    for p in (r"^(.*_)?tool0$", r"_tcp$|^tcp$", r"tool", r"gripper_frame", r"end_?effector")
)


def looks_like_gripper_joint(name: str) -> bool:
    """A joint name that moves fingers rather than the arm (finger, gripper, jaw, claw, knuckle, ...)."""
    return bool(_GRIPPER_JOINT.search(name))


def _gripper_drives(by_child: Mapping[str, _UrdfJoint]) -> set[str]:
    """Joints that other joints mimic and below which every moving joint is a mimic or finger joint:
    a gripper's drive (xArm's `drive_joint`), not an arm joint driving a parallelogram linkage."""
    below: dict[str, list[_UrdfJoint]] = {}
    for j in by_child.values():
        below.setdefault(j.parent, []).append(j)
    sources = {m.get("joint", "") for j in by_child.values() for m in j.el.findall("mimic")}
    drives = set()
    for j in by_child.values():
        if j.name not in sources:
            continue
        stack, only_fingers, seen = list(below.get(j.child, [])), True, 0
        while stack and only_fingers and seen <= len(by_child):
            k = stack.pop()
            seen += 1
            if k.type != "fixed" and k.el.find("mimic") is None and not looks_like_gripper_joint(k.name):
                only_fingers = False
            stack.extend(below.get(k.child, []))
        if only_fingers:
            drives.add(j.name)
    return drives


def _is_gripper_joint(joint: _UrdfJoint, mimicked: set[str]) -> bool:
    """Finger/gripper by name, a mimic joint, or a joint other joints mimic (xArm's gripper `drive_joint`)."""
    return joint.type != "fixed" and (
        looks_like_gripper_joint(joint.name) or joint.el.find("mimic") is not None or joint.name in mimicked
    )


def _default_chain(links: list[str], by_child: Mapping[str, _UrdfJoint], source: str = "the URDF") -> tuple[str, str]:
    """Root link and the default tip: the end of the arm through the most moving joints, not counting
    finger/gripper joints (nor chains through them), at a tool frame when the arm has one. With
    several roots (a URDF error lint reports), the root whose tree has that arm."""
    roots = [name for name in links if name not in by_child]
    if not roots:
        raise ArmtoolError(
            f"{source} has no root link: every link is the child of a joint (a kinematic loop)",
            hint="run `armtool lint` on it",
        )
    mimicked = _gripper_drives(by_child)
    paths: list[tuple[str, str, int, int, bool]] = []  # root, link, moving joints, depth, passes a gripper joint
    looped: list[str] = []  # links whose walk up never reaches a root
    for link in links:
        moving, depth, gripper, cur = 0, 0, False, link
        while cur in by_child and depth <= len(links):
            joint = by_child[cur]
            moving += joint.type != "fixed"
            gripper = gripper or _is_gripper_joint(joint, mimicked)
            depth += 1
            cur = joint.parent
        if cur in by_child:
            looped.append(link)
        elif cur in roots:
            paths.append((cur, link, moving, depth, gripper))
    arm = [p for p in paths if not p[4]] or paths  # a gripper-only model: its own joints are the chain
    most = max(p[2] for p in arm)
    if most == 0:
        why = (
            f"; links {', '.join(looped[:10])} form a kinematic loop and reach no root"
            if looped
            else "; it has no revolute, prismatic or continuous joint"
        )
        raise ArmtoolError(
            f"{source} has no moving joint below its root link{'s' if len(roots) > 1 else ''} "
            f"{', '.join(repr(r) for r in roots[:10])}{why}",
            hint="run `armtool lint` on it",
        )
    ends = [p for p in arm if p[2] == most]
    order = {name: i for i, name in enumerate(links)}
    root_order = {name: i for i, name in enumerate(roots)}

    def rank(p: tuple[str, str, int, int, bool]) -> tuple[int, int, int, int]:
        tool = next((len(_TOOL_FRAMES) - k for k, pattern in enumerate(_TOOL_FRAMES) if pattern.search(p[1])), 0)
        return (-root_order[p[0]], tool, p[3], -order[p[1]])

    best = max(ends, key=rank)
    return best[0], best[1]


def default_base_tip(root: etree._Element, source: str = "the URDF") -> tuple[str, str]:
    """The chain armtool uses when none is given (ik-bench, calibrate --flange): (base link, tip link).

    The base is the URDF's root link; the tip ends the chain through the most moving joints that
    does not pass a finger/gripper joint (by name, a mimic joint, or one that others mimic), and among the links at that
    end prefers a tool frame (`tool0`, `*_tcp`, `*tool*`, `*gripper_frame*`, `*end_effector*`),
    then the deepest link.
    """
    links = [el.get("name", "") for el in root.findall("link")]
    return _default_chain(links, _urdf_joints(root), source)


class Chain:
    """A serial chain with n moving joints; q is a vector of n joint values (rad or m)."""

    def __init__(self, name: str, base: str, tip: str, joints: list[ChainJoint], tip_offset: Array) -> None:
        if not joints:
            raise ArmtoolError(
                f"no moving joint between '{base}' and '{tip}': only fixed joints join them",
                hint="pick a tip further from the base (`armtool tree` shows the joints)",
            )
        self.name = name
        self.base = base
        self.tip = tip
        self.joints = joints
        self.tip_offset = tip_offset
        self.n = len(joints)
        self.joint_names = [j.name for j in joints]
        self.lower: Array = np.array([j.lower for j in joints])
        self.upper: Array = np.array([j.upper for j in joints])
        self.continuous: NDArray[np.bool_] = np.array([j.kind == "continuous" for j in joints])
        self.revolute: NDArray[np.bool_] = np.array([j.kind != "prismatic" for j in joints])
        self._origins: Array = np.stack([j.origin for j in joints])
        self._axes: Array = np.stack([j.axis for j in joints])
        self._signs: Array = np.array([1.0] * self.n)  # per joint: the sign of its axis in the batch plan
        self._revolute_cols: NDArray[np.intp] | None = None if self.revolute.all() else np.flatnonzero(self.revolute)
        self._pin: Any = None
        self._plan: list[_PlanStep] | None = None
        # Whether the tip offset moves the tip frame: an identity offset costs fk_jacobian_soa two products.
        self._tip_moves = not np.array_equal(tip_offset, np.eye(4))
        self.free_orientation = 0  # trailing virtual joints that make the tip's orientation free (position-only IK)
        # Joints held at a value (Chain.locked): (index in the chain they were locked in, name, value).
        self.locks: tuple[tuple[int, str, float], ...] = ()
        self._full_names = self.joint_names  # that chain's joint names, locked ones included

    def locked(self, values: Mapping[str, float]) -> Chain:
        """This chain with the named joints held at the given values (rad, or m for a prismatic joint).

        Each locked joint, turned to its value, is folded into the transform before the next moving
        joint (or into the tip offset); the other joints keep their order, names and limits. A 7-DOF
        arm's closed form is the 6R chain left at a given value of one joint (EAIK's `fixed_axes`):
        `chain.locked({"panda_joint7": 0.3})`. `expand(q)` gives the whole chain's configuration.
        """
        if self.free_orientation:
            raise ArmtoolError(
                "a position-only chain cannot lock joints", hint="lock joints before with_free_orientation()"
            )
        unknown = [name for name in values if name not in self.joint_names]
        if unknown:
            raise ArmtoolError(
                f"cannot lock joint '{unknown[0]}': not a moving joint of the chain {self.base} → {self.tip}"
                + did_you_mean(unknown[0], self.joint_names),
                hint="joints: " + ", ".join(self.joint_names),
            )
        for j in self.joints:
            if j.name not in values:
                continue
            v = values[j.name]
            if not math.isfinite(v):
                raise ArmtoolError(f"cannot lock joint '{j.name}' at {v}: not a finite number")
            if j.kind != "continuous" and not j.lower - 1e-12 <= v <= j.upper + 1e-12:
                raise ArmtoolError(
                    f"cannot lock joint '{j.name}' at {v:g}: outside its limits [{j.lower:g}, {j.upper:g}]",
                    hint="pick a value within the joint's <limit lower upper>",
                )
        if len(values) >= self.n:
            raise ArmtoolError(
                f"cannot lock every joint of the chain {self.base} → {self.tip}: at least one must move",
                hint="leave one or more joints out of the locked set",
            )
        joints: list[ChainJoint] = []
        pending = np.eye(4)
        for j in self.joints:
            origin = pending @ j.origin
            if j.name in values:
                pending = origin @ _joint_motion(j, float(values[j.name]))
                continue
            joints.append(ChainJoint(j.name, j.kind, origin, j.axis, j.lower, j.upper))
            pending = np.eye(4)
        out = Chain(self.name, self.base, self.tip, joints, pending @ self.tip_offset)
        index = {name: i for i, name in enumerate(self._full_names)}
        out._full_names = self._full_names
        out.locks = tuple(
            sorted([*self.locks, *((index[name], name, float(v)) for name, v in values.items())], key=lambda x: x[0])
        )
        return out

    def expand(self, q: Array) -> Array:
        """A configuration of this chain with its locked joints' values put back: the configuration
        of the chain it was locked from (q itself when nothing is locked)."""
        q = np.asarray(q, dtype=float)
        if not self.locks:
            copy: Array = q.copy()
            return copy
        full = np.empty(q.shape[:-1] + (len(self._full_names),))
        moving = [i for i, name in enumerate(self._full_names) if name in set(self.joint_names)]
        full[..., moving] = q
        for i, _, v in self.locks:
            full[..., i] = v
        return full

    def with_free_orientation(self) -> Chain:
        """This chain plus three virtual continuous joints (about x, y, z) turning the tip in place.

        Position-only IK (MoveIt's position_only_ik) as a full-pose problem every solver can take:
        any orientation is reachable at any position the arm reaches, so a pose solution of this
        chain, without its last three joints, is a position solution of the real one.
        """
        joints = list(self.joints)
        for k, axis in enumerate(("x", "y", "z")):
            origin = self.tip_offset if k == 0 else np.eye(4)
            joints.append(ChainJoint(f"{self.tip}_free_r{axis}", "continuous", origin, np.eye(3)[k], -math.pi, math.pi))
        free = Chain(self.name, self.base, self.tip, joints, np.eye(4))
        free.free_orientation = 3
        return free

    # ---- Pinocchio model ----------------------------------------------------------
    def _model(self) -> Any:
        if self._pin is None:
            import pinocchio as pin

            model = pin.Model()
            model.name = self.name
            parent = 0
            for j in self.joints:
                placement = pin.SE3(j.origin[:3, :3].copy(), j.origin[:3, 3].copy())
                parent = model.addJoint(parent, _joint_model(pin, j), placement, j.name)
            tip = pin.SE3(self.tip_offset[:3, :3].copy(), self.tip_offset[:3, 3].copy())
            frame = model.addFrame(pin.Frame(self.tip, parent, tip, pin.FrameType.OP_FRAME))
            model.lowerPositionLimit = self.lower.copy()
            model.upperPositionLimit = self.upper.copy()
            self._pin = (pin, model, model.createData(), frame)
        return self._pin

    def fk(self, q: Array) -> Array:
        """4x4 pose of the tip in the base frame."""
        pin, model, data, frame = self._model()
        pin.framesForwardKinematics(model, data, q)
        return data.oMf[frame].homogeneous  # type: ignore[no-any-return]

    def fk_jacobian(self, q: Array) -> tuple[Array, Array]:
        """Tip pose and its 6xn Jacobian [v; w] in the base frame at the tip origin."""
        pin, model, data, frame = self._model()
        J = pin.computeFrameJacobian(model, data, q, frame, pin.LOCAL_WORLD_ALIGNED)
        if J.ndim == 1:  # eigenpy returns a 6x1 matrix as a 1-D array: a 1-joint chain's J stays (6, 1)
            J = J.reshape(6, 1)
        pin.updateFramePlacement(model, data, frame)
        return data.oMf[frame].homogeneous, J

    def jacobian(self, q: Array) -> Array:
        return self.fk_jacobian(q)[1]

    # ---- numpy, many configurations at once ---------------------------------------------------
    def fk_batch(self, Q: Array) -> Array:
        """(N, 4, 4) tip poses for (N, n) configurations, without Pinocchio."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        N = Q.shape[0]
        T: Array = np.broadcast_to(np.eye(4), (N, 4, 4)).copy()
        for i, joint in enumerate(self.joints):
            T = T @ joint.origin
            M = np.broadcast_to(np.eye(4), (N, 4, 4)).copy()
            if joint.kind == "prismatic":
                M[:, :3, 3] = Q[:, i : i + 1] * joint.axis
            else:
                M[:, :3, :3] = axis_angle_batch(joint.axis, Q[:, i])
            T = T @ M
        return T @ self.tip_offset

    def fk_jacobian_batch(self, Q: Array, jacobian: bool = True) -> tuple[Array, Array | None]:
        """(N,4,4) tip poses and (N,6,n) Jacobians [v; w] (base frame, at the tip) for (N,n) configurations."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        N = Q.shape[0]
        R, p, Jt = self.fk_jacobian_soa(Q, jacobian)
        T = np.zeros((N, 4, 4))
        T[:, :3, :3] = R.transpose(2, 0, 1)
        T[:, :3, 3] = p.T
        T[:, 3, 3] = 1.0
        return T, (None if Jt is None else np.ascontiguousarray(Jt.transpose(2, 0, 1)))

    def fk_jacobian_soa(self, Q: Array, jacobian: bool = True) -> tuple[Array, Array, Array | None]:
        """fk_jacobian_batch with the configuration index last: R (3,3,N), p (3,N), J (6,n,N).

        Every step is a 3×3 GEMM over N columns or an element-wise update of contiguous rows of
        length N (~0.3 µs per configuration for a 7-joint arm at N = 1000; the (N,3,3) layout
        with strided columns and np.cross took ~2 µs). The batch IK calls it once per step, down
        to ~20 configurations, where its ~12 numpy calls per joint are most of its cost: the plan
        holds every per-joint constant, the first joint's origin is the start (no product with
        the identity), and each joint's position is written where the Jacobian reads it.
        """
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        N, n = Q.shape[0], self.n
        plan = self._batch_plan()
        points = np.empty((3, n, N))  # each joint's origin: where the Jacobian's columns are taken
        J = np.zeros((6, n, N)) if jacobian else None
        signed = Q.T * self._signs[:, None]
        cos, sin = np.cos(signed), np.sin(signed)
        R = np.empty((3, 3, N))
        p: Array = points[:, 0]
        for i, step in enumerate(plan):
            if i == 0:  # R and p start at the identity and zero: the first origin is the frame itself
                R[:] = step.o_R[:, :, None]
                p[:] = step.o_p[:, None]
            else:
                p = np.add(p, step.o_p @ R, out=points[:, i])  # p_i += Σ_k R[i,k] o_p[k]
                R = step.o_Rt @ R  # R[i] ← o_Rᵀ R[i] as (3,N) blocks: R·o_R per configuration
            axis = R[:, step.col]
            if step.prismatic:
                if J is not None:
                    J[:3, i] = axis * step.sign
                p = p + Q[:, i] * step.sign * axis  # a new array: points[:, i] keeps the joint's origin
            else:
                if J is not None:
                    J[3:, i] = axis if step.sign == 1.0 else axis * step.sign
                # The two columns it turns, a and b, as one view (columns 0,1 / 1,2 / 0,2): both
                # products at once, then a ← c·a + s·b and b ← c·b − s·a (4 numpy calls, not 7).
                turned = R[:, step.turned]
                cx, sx = turned * cos[i], turned * sin[i]
                np.add(cx[:, step.a], sx[:, step.b], out=turned[:, step.a])
                np.subtract(cx[:, step.b], sx[:, step.a], out=turned[:, step.b])
            if step.undo is not None:
                R = step.undo @ R
        if self._tip_moves:
            p = p + self.tip_offset[:3, 3] @ R
            R = self.tip_offset[:3, :3].T @ R
        if J is None:
            return R, p, None
        r = p[:, None, :] - points  # (3, n, N): from each joint origin to the tip
        w0, w1, w2 = J[3], J[4], J[5]
        rev = self._revolute_cols
        if rev is None:  # every joint revolute
            np.subtract(w1 * r[2], w2 * r[1], out=J[0])
            np.subtract(w2 * r[0], w0 * r[2], out=J[1])
            np.subtract(w0 * r[1], w1 * r[0], out=J[2])
        else:
            J[0, rev] = (w1 * r[2] - w2 * r[1])[rev]
            J[1, rev] = (w2 * r[0] - w0 * r[2])[rev]
            J[2, rev] = (w0 * r[1] - w1 * r[0])[rev]
        return R, p, J

    def _batch_plan(self) -> list[_PlanStep]:
        """Per joint: origin rotation (times a basis change for unaligned axes) and its transpose,
        origin translation, the column the axis lies on and the two it turns, its sign, and the
        basis change to undo after the motion."""
        if self._plan is None:
            plan: list[_PlanStep] = []
            for j in self.joints:
                o_R, o_p = j.origin[:3, :3].copy(), j.origin[:3, 3].copy()
                col = int(np.argmax(np.abs(j.axis)))
                sign, undo = float(np.sign(j.axis[col])), None
                if abs(abs(j.axis[col]) - 1.0) >= 1e-12:
                    # Unaligned axis: a basis B with B[:, 2] = axis; rotate about its z column, then undo.
                    B = _basis_with_z(j.axis)
                    o_R, col, sign, undo = o_R @ B, 2, 1.0, B
                a, b = (col + 1) % 3, (col + 2) % 3
                turned = slice(min(a, b), max(a, b) + 1, abs(b - a))
                first = 0 if a < b else 1
                plan.append(
                    _PlanStep(o_R, o_R.T, o_p, col, turned, first, 1 - first, sign, j.kind == "prismatic", undo)
                )
            self._plan = plan
            self._signs = np.array([step.sign for step in plan])
        return self._plan

    # ---- helpers -----------------------------------------------------------------------------
    def within_limits(self, q: Array, tol: float = 1e-9) -> bool:
        ok = (q >= self.lower - tol) & (q <= self.upper + tol)
        return bool(np.all(ok | self.continuous))

    def clamp(self, q: Array) -> Array:
        return np.where(self.continuous, q, np.clip(q, self.lower, self.upper))

    def mid(self) -> Array:
        return (self.lower + self.upper) / 2.0

    def random(self, rng: np.random.Generator, count: int | None = None) -> Array:
        shape = (self.n,) if count is None else (count, self.n)
        return rng.uniform(self.lower, self.upper, size=shape)


def _joint_motion(j: ChainJoint, value: float) -> Array:
    """The 4x4 motion of a joint at a value: a rotation about its axis, or a translation along it."""
    M = np.eye(4)
    if j.kind == "prismatic":
        M[:3, 3] = value * j.axis
    else:
        M[:3, :3] = axis_angle_batch(j.axis, np.array([value]))[0]
    return M


def _basis_with_z(axis: Array) -> Array:
    """A rotation whose third column is `axis`."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, axis)
    x /= np.linalg.norm(x)
    y = np.cross(axis, x)
    return np.column_stack([x, y, axis])


def axis_angle_batch(axis: Array, angles: Array) -> Array:
    """Rodrigues' rotation about a fixed unit axis for many angles: (N, 3, 3)."""
    x, y, z = axis
    K: Array = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    s: Array
    c: Array
    s, c = np.sin(angles)[:, None, None], np.cos(angles)[:, None, None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def _joint_model(pin: Any, j: ChainJoint) -> Any:
    aligned = {0: "X", 1: "Y", 2: "Z"}
    idx = int(np.argmax(np.abs(j.axis)))
    if abs(j.axis[idx]) == 1.0 and j.axis[idx] > 0:
        return getattr(pin, ("JointModelP" if j.kind == "prismatic" else "JointModelR") + aligned[idx])()
    if j.kind == "prismatic":
        return pin.JointModelPrismaticUnaligned(j.axis.copy())
    return pin.JointModelRevoluteUnaligned(j.axis.copy())


def chain_from_xml(
    root: etree._Element, base: str | None = None, tip: str | None = None, source: str = "URDF"
) -> Chain:
    links = [el.get("name", "") for el in root.findall("link")]
    by_child = _urdf_joints(root)
    if base is None or tip is None:
        default_base, default_tip = _default_chain(links, by_child, source)
        base = base or default_base
        tip = tip or default_tip
    for role, name in (("base", base), ("tip", tip)):
        if name not in links:
            raise ArmtoolError(
                f"{role} link '{name}' is not in {source}{did_you_mean(name, links)}",
                hint="links: " + ", ".join(links[:30]) + (" …" if len(links) > 30 else ""),
            )
    if base == tip:
        raise ArmtoolError(
            f"base and tip are the same link '{base}' in {source}: a chain needs at least one moving joint between them",
            hint="pick a tip link below the base (`armtool tree` shows the links)",
        )
    path: list[_UrdfJoint] = []
    cur = tip
    while cur != base:
        joint = by_child.get(cur)
        if joint is None:
            raise ArmtoolError(
                f"tip '{tip}' is not below base '{base}' in {source}", hint="swap them, or pick links on one branch"
            )
        path.append(joint)
        cur = joint.parent
        if len(path) > len(links):
            raise ArmtoolError(f"{source} has a kinematic loop", hint="run `armtool lint` on it")
    path.reverse()
    joints: list[ChainJoint] = []
    pending = np.eye(4)
    for uj in path:
        origin = pending @ origin_matrix(uj.el.find("origin"), f"joint '{uj.name}'")
        if uj.type == "fixed":
            pending = origin
            continue
        if uj.type not in ("revolute", "prismatic", "continuous"):
            raise ArmtoolError(
                f"joint '{uj.name}' has type '{uj.type}', which a serial IK chain cannot use",
                hint="choose a chain of revolute/prismatic/continuous joints",
            )
        if uj.el.find("mimic") is not None:
            raise ArmtoolError(
                f"joint '{uj.name}' is a mimic joint",
                hint="IK chains cannot contain mimic joints; choose a tip link above it",
            )
        axis_el = uj.el.find("axis")
        axis = np.array(
            _floats(axis_el.get("xyz") if axis_el is not None else None, 3, (1, 0, 0), f"joint '{uj.name}' <axis xyz>")
        )
        norm = math.hypot(*axis)  # no overflow for `1e200 1e200 0`, no underflow for tiny ones
        if norm < 1e-12:
            raise ArmtoolError(f"joint '{uj.name}' has a zero axis", hint="run `armtool lint` on the URDF")
        if uj.type == "continuous":
            lower, upper = -math.pi, math.pi
        else:
            limit = uj.el.find("limit")
            lower = _floats(
                limit.get("lower") if limit is not None else None,
                1,
                (0.0,),
                f"joint '{uj.name}' <limit lower>",
                MAX_ABS,
            )[0]
            upper = _floats(
                limit.get("upper") if limit is not None else None,
                1,
                (0.0,),
                f"joint '{uj.name}' <limit upper>",
                MAX_ABS,
            )[0]
            if not lower < upper:
                raise ArmtoolError(
                    f"joint '{uj.name}' has limits [{lower}, {upper}], no room to move", hint="fix <limit lower upper>"
                )
        joints.append(ChainJoint(uj.name, uj.type, origin, axis / norm, lower, upper))  # type: ignore[arg-type]
        pending = np.eye(4)
    return Chain(root.get("name", "robot"), base, tip, joints, pending)


def load_chain(
    urdf_path: str | Path,
    base: str | None = None,
    tip: str | None = None,
    *,
    xacro_args: Mapping[str, str] | None = None,
    package_paths: Sequence[Path] = (),
) -> Chain:
    """The chain base → tip of a URDF or xacro (default: the longest chain from the root)."""
    from armtool.model.load import load_robot_xml

    path = Path(urdf_path)
    root = load_robot_xml(path, xacro_args, package_paths)
    return chain_from_xml(root, base, tip, source=path.name)
