"""Peer `ik-geo`: IK-Geo's subproblem decomposition (Elias & Wen 2022) in Rust, pip `ik-geo` (BSD-3).

Configuration. IK-Geo's Python package has no URDF reader and no detection: a robot is built from
its joint axes H (6×3) and the offsets P (7×3) between points on them, all in the base frame at
q = 0 (product of exponentials), by the constructor of the decomposition that fits the arm; "if you
choose the wrong one, you will get wrong answers" (its README). `decompose` picks it from the
chain's axis lines, the most specific first, as IK-Geo's own `rec_solver_6_DOF.m` lists them
(rpiRobotics/ik-geo, matlab/automatic_IK; 0-based joint indices here):

| constructor | condition | method |
|---|---|---|
| `spherical_two_intersecting` | axes 3, 4, 5 meet in one point, axes 0, 1 meet | closed form |
| `spherical_two_parallel` | axes 3, 4, 5 meet, axes 1 ∥ 2 | closed form |
| `three_parallel_two_intersecting` | axes 1 ∥ 2 ∥ 3, axes 4, 5 meet (UR-type) | closed form |
| `spherical` | axes 3, 4, 5 meet | closed form (quartic) |
| `three_parallel` | axes 1 ∥ 2 ∥ 3 | closed form (quartic) |
| `two_parallel` | axes 1 ∥ 2 | 1-D search |
| `two_intersecting` | axes 4, 5 meet | 1-D search |
| `gen_six_dof` | any 6R arm | 2-D search |

Axes are parallel within ANGLE_TOL, meet within LENGTH_TOL. `two_parallel` comes before
`two_intersecting`: the latter solves joints 0-2 by subproblem 5, which has no solution set when
axes 1 and 2 are parallel. The points of axes that meet are put at their intersection (P's
offsets between them zero), the form IK-Geo's solvers assume.

- Frames: IK-Geo's tool frame is the last point of P with the base's orientation at q = 0 (R6T the
  identity), so chain.fk(q) = IK-Geo's FK(q)·C (`tool_transform`), proven at construction with
  its own `forward_kinematics` (`check_fk`); prepare turns a target T into T·C⁻¹ (untimed).
- Rotations cross its Python boundary column by column (`get_ik(R, t)` reads `R[j][i]` as row i,
  column j; `forward_kinematics` returns it so too): prepare passes Rᵀ as nested lists.
- Its 1-D and 2-D searches (NLopt's MLSL, stopping when the squared residual is below 1e-8: its
  `search_1d`/`search_2d`) return least-squares solutions, about 1e-4 off: above the default 1e-5
  tolerance, so those rows fail armtool's check and say why. Only 6R chains: its Python package
  takes exactly six joints (a 7-DOF arm needs one locked: `ik-bench --lock`, which gives it the
  locked chain's axes; Panda locked at panda_joint7 is its two_intersecting 1-D search, which found
  no solution for any of 200 targets, measured by one `ik-bench --lock panda_joint7=0.3` run).
  On xArm6 (two_parallel) they find none, and 2 of 10 targets end in a Rust panic (an unwrap of
  None in its search), which `call` catches and the answer reports as its reason. Rust's panic
  hook prints each panic on file descriptor 2 first (two lines, a third the first time; a
  backtrace with RUST_BACKTRACE set); `prints_natively` has ik-bench capture that around each
  block of solves, outside the timing, and say once after the run how many lines and panics it
  held back, and the first line (armtool.ik.bench.native_output, native_stderr_note).
- Arms that fit a family only within the tolerances (URDFs with rpy rounded to 1.5708: Lite6)
  get the family's model, whose FK differs from the chain's slightly: the row's method says by
  how much, and armtool's check of every answer decides.
- Joint limits: IK-Geo ignores them; its solutions are placed within them as `analytic`'s are
  (`armtool.ik.solutions.closed_form_answer`). The timed call is `get_ik(R, t)` alone.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any

import numpy as np
from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik.peers import check_closed_form_chain, check_fk, tool_transform
from armtool.ik.solutions import closed_form_answer
from armtool.ik.solver import Answer, Array, Solver
from armtool.model.chain import Chain

ANGLE_TOL = 1e-6  # rad: two axes are parallel
LENGTH_TOL = 1e-6  # m: two axes meet, three meet in one point


def axis_lines(chain: Chain) -> tuple[Array, Array, Array]:
    """Each joint axis at q = 0 as a point and a unit direction in the base frame ((n,3) each), and
    the tip's pose at q = 0."""
    T = np.eye(4)
    points, directions = [], []
    for joint in chain.joints:
        T = T @ joint.origin
        points.append(T[:3, 3].copy())
        directions.append(T[:3, :3] @ joint.axis)
    return np.array(points), np.array(directions), T @ chain.tip_offset


def _parallel(H: Array, i: int, j: int) -> bool:
    return float(np.linalg.norm(np.cross(H[i], H[j]))) < ANGLE_TOL


def _meet(points: Array, H: Array, i: int, j: int) -> Array | None:
    """Where axes i and j meet (within LENGTH_TOL), or None (apart, or parallel)."""
    if _parallel(H, i, j):
        return None
    r = points[i] - points[j]
    b, e, f = float(H[i] @ H[j]), float(H[i] @ r), float(H[j] @ r)
    t = (b * f - e) / (1.0 - b * b)
    on_i, on_j = points[i] + t * H[i], points[j] + (f + t * b) * H[j]
    return (on_i + on_j) / 2.0 if float(np.linalg.norm(on_i - on_j)) < LENGTH_TOL else None


def _wrist(points: Array, H: Array) -> Array | None:
    """The point where axes 3, 4 and 5 meet, or None."""
    a, b = _meet(points, H, 3, 4), _meet(points, H, 4, 5)
    if a is None or b is None or float(np.linalg.norm(a - b)) >= LENGTH_TOL:
        return None
    return (a + b) / 2.0


def _offsets(points: Array, tip: Array) -> Array:
    """P (7,3): the first point, the steps between consecutive points, and the tip from the last."""
    out: Array = np.vstack([points[:1], np.diff(points, axis=0), tip[None, :3, 3] - points[-1:]])
    return out


def decompose(chain: Chain) -> tuple[str, str, Array, Array, Array]:
    """(IK-Geo constructor, its method, H (6,3), P (7,3) as the chain reads, P with the points of
    axes that meet moved to their intersection) for a 6R chain (table in the module doc). The two
    P give the same FK when the axes meet exactly; within the tolerances they differ slightly."""
    points, H, tip = axis_lines(chain)
    wrist, meet45, meet01 = _wrist(points, H), _meet(points, H, 4, 5), _meet(points, H, 0, 1)
    par12 = _parallel(H, 1, 2)
    par123 = par12 and _parallel(H, 2, 3)
    choices: list[tuple[str, str, bool]] = [
        ("spherical_two_intersecting", "closed form", wrist is not None and meet01 is not None),
        ("spherical_two_parallel", "closed form", wrist is not None and par12),
        ("three_parallel_two_intersecting", "closed form", par123 and meet45 is not None),
        ("spherical", "closed form, quartic", wrist is not None),
        ("three_parallel", "closed form, quartic", par123),
        ("two_parallel", "1-D search", par12),
        ("two_intersecting", "1-D search", meet45 is not None),
        ("gen_six_dof", "2-D search", True),
    ]
    family, method = next((f, m) for f, m, fits in choices if fits)
    moved = points.copy()
    if wrist is not None and family.startswith("spherical"):
        moved[3:6] = wrist
    if meet45 is not None and family in ("three_parallel_two_intersecting", "two_intersecting"):
        moved[4:6] = meet45
    if meet01 is not None and family == "spherical_two_intersecting":
        moved[0:2] = meet01
    return family, method, H, _offsets(points, tip), _offsets(moved, tip)


def _ik_geo_fk(robot: Any) -> Callable[[Array], Array]:
    """IK-Geo's own forward kinematics as a 4x4 pose (its rotation comes back column by column)."""

    def fk(q: Array) -> Array:
        R, p = robot.forward_kinematics([float(v) for v in q])
        T = np.eye(4)
        T[:3, :3] = np.array(R).T
        T[:3, 3] = p
        return T

    return fk


class IkGeo(Solver):
    name = "ik-geo"
    summary = "IK-Geo (Rust, pip ik-geo): subproblem decomposition chosen from the axes, closed form or 1-D/2-D search"
    returns_all_solutions = True
    prints_natively = True  # Rust's panic hook writes on fd 2 (module doc)

    def __init__(self, chain: Chain, root: etree._Element, *, timeout: float, tolerance: float) -> None:
        Solver.__init__(self, chain, timeout=timeout, tolerance=tolerance)
        beyond = "its Python package solves 6R chains: lock one joint of a 7-DOF arm (--lock JOINT=VALUE)"
        check_closed_form_chain("IK-Geo", chain, max_joints=6, beyond=beyond)
        if chain.n != 6:
            raise ArmtoolError(f"IK-Geo cannot take {chain.n} joints: its Python package solves 6R chains only")
        # Imported by name: ik_geo's own type hints lack Robot's constructors, and the peer may be absent
        # where mypy runs, so a static import cannot be typed the same way in both places.
        ik_geo: Any = importlib.import_module("ik_geo")

        family, method, H, P_chain, P = decompose(chain)
        constructor = getattr(ik_geo.Robot, family)
        # IK-Geo reads the chain as armtool does: its FK with the chain's own offsets matches ours.
        as_read = _ik_geo_fk(constructor(H.tolist(), P_chain.tolist()))
        self._tool = tool_transform(chain, as_read)
        self._to_ik_geo = np.linalg.inv(self._tool)
        check_fk(self.name, chain, lambda q: as_read(q) @ self._tool)
        robot: Any = constructor(H.tolist(), P.tolist())
        solved = _ik_geo_fk(robot)  # with the points moved onto the intersections: what it solves
        rng = np.random.default_rng(0)
        off = max(float(np.abs(solved(q) @ self._tool - chain.fk(q)).max()) for q in chain.random(rng, 8))
        self.method = f"{family} ({method}" + (f"; its model is off the chain by {off:.1e})" if off > 1e-12 else ")")
        self._ik = robot.get_ik

    def prepare(self, target: Array, seed: Array) -> tuple[list[list[float]], list[float], Array]:
        """IK-Geo's arguments: the target in its tool frame (T·C⁻¹), the rotation's columns and the
        position, as lists of floats."""
        pose = np.asarray(target, dtype=float) @ self._to_ik_geo
        return pose[:3, :3].T.tolist(), pose[:3, 3].tolist(), np.asarray(seed, dtype=float)

    def call(self, prepared: tuple[list[list[float]], list[float], Array]) -> tuple[Any, Array]:
        try:
            return self._ik(prepared[0], prepared[1]), prepared[2]
        except (KeyboardInterrupt, SystemExit):
            raise
        except BaseException as exc:  # a Rust panic (pyo3's PanicException is a BaseException)
            return exc, prepared[2]

    def answer(self, raw: tuple[Any, Array]) -> Answer:
        found, seed = raw
        if isinstance(found, BaseException):
            return Answer(seed, False, 0, f"ik-geo failed inside its solver ({type(found).__name__}: {found})")
        Q = np.array([q for q, _ in found], dtype=float).reshape(-1, self.chain.n)
        return closed_form_answer(self.chain, self.name, Q, [ls for _, ls in found], seed)
