"""`traj cartesian` from its options to a joint path: the start configuration, the segments the
tool must follow (a line, a circle or arc, or waypoint poses), IK along them, and the report lines.
The CLI parses flags into a `PathSpec` and prints; everything here raises ArmtoolError on bad input."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from armtool.errors import ArmtoolError
from armtool.model.chain import Chain, rpy_matrix
from armtool.traj import cartesian as cart
from armtool.traj.start import Srdf
from armtool.traj.trajectory import Array, Trajectory

MAX_WAYPOINT_BYTES = 16 * 1024 * 1024  # ~300 000 poses: far more than a taught path holds


@dataclass(frozen=True)
class PathSpec:
    """The tool path as given on the command line (exactly one of line, circle, arc, waypoints)."""

    line: str | None = None  # X,Y,Z (m, base frame)
    relative: bool = False  # --line is an offset from the start position
    center: str | None = None
    center_offset: str | None = None
    radius: float | None = None
    normal: str = "1,0,0"
    angle: float = 2 * math.pi
    arc_via: str | None = None
    arc_to: str | None = None
    waypoints: Path | None = None

    @property
    def circle(self) -> bool:
        return self.center is not None or self.center_offset is not None or self.radius is not None

    def check(self) -> None:
        if self.center is not None and self.center_offset is not None:
            raise ArmtoolError("give --center or --center-offset, not both")
        chosen = [x for x in (self.line, self.circle or None, self.arc_to, self.waypoints) if x is not None]
        if len(chosen) != 1:
            raise ArmtoolError(
                "give exactly one path: --line, a circle (--center/--center-offset, or --radius), --arc-via/--arc-to, or --waypoints",
                hint="e.g. --center-offset 0,-0.1,0 --normal 1,0,0 for the lecture's circle of radius 0.1 m",
            )
        if (self.arc_via is None) != (self.arc_to is None):
            raise ArmtoolError("an arc needs both --arc-via and --arc-to")


@dataclass(frozen=True)
class CartesianPlan:
    chain: Chain  # the chain IK solves: with --lock, the locked one (its q lacks the locked joints)
    result: cart.CartesianResult
    trajectory: Trajectory  # the achieved joint path (untimed), every joint, the locked ones at their values
    start_how: str = "--start"  # where the start configuration came from
    chain_how: str = "--base/--tip"  # where the chain came from: a group of the SRDF, the default chain
    solver_how: str = ""  # which solver stepped the path, and why


def floats(text: str, n: int, option: str) -> list[float]:
    """`text` as n finite comma-separated numbers, else an error naming `option`."""
    try:
        values = [float(v) for v in text.replace(" ", "").split(",") if v != ""]
    except ValueError:
        raise ArmtoolError(f"{option} {text!r}: not {n} comma-separated numbers") from None
    if len(values) != n or not all(math.isfinite(v) for v in values):
        raise ArmtoolError(f"{option} {text!r}: expected {n} finite comma-separated numbers")
    return values


def _start(
    chain: Chain,
    start: str | None,
    urdf: Path,
    srdf: Srdf | None,
    xacro_args: Mapping[str, str] | None,
    package_paths: Sequence[Path],
) -> tuple[Array, str]:
    """--start, else the default start of `armtool.traj.start` (never a singular one). With locked
    joints --start gives the free joints, or every joint with the locked ones at their values."""
    if start is None:
        from armtool.traj.start import default_start

        chosen = default_start(chain, urdf, srdf, chain.name, xacro_args, package_paths)
        return chosen.q, chosen.how
    if chain.locks and len([v for v in start.split(",") if v.strip()]) == chain.n + len(chain.locks):
        from armtool.ik.locks import full_joint_names

        given = dict(zip(full_joint_names(chain), floats(start, chain.n + len(chain.locks), "--start")))
        for _, name, value in chain.locks:
            if abs(given[name] - value) > 1e-9:
                raise ArmtoolError(
                    f"--start gives {name} = {given[name]:g}, but --lock holds it at {value:g}",
                    hint=f"give {name} = {value:g} in --start, or only the {chain.n} joints that move",
                )
        start = ",".join(repr(given[name]) for name in chain.joint_names)
    q0 = np.asarray(floats(start, chain.n, "--start"), dtype=np.float64)
    if not chain.within_limits(q0):
        raise ArmtoolError(
            "--start is outside the joint limits",
            hint="limits: "
            + ", ".join(f"{n} [{lo:.3g}, {hi:.3g}]" for n, lo, hi in zip(chain.joint_names, chain.lower, chain.upper)),
        )
    return q0, "--start"


def segments(spec: PathSpec, T0: Array) -> list[cart.Segment]:
    """The segments of `spec`, starting at the tool pose T0."""
    if spec.line is not None:
        T1 = T0.copy()
        p = np.asarray(floats(spec.line, 3, "--line"))
        T1[:3, 3] = T0[:3, 3] + p if spec.relative else p
        if np.linalg.norm(T1[:3, 3] - T0[:3, 3]) < 1e-9:
            raise ArmtoolError("the line ends where it starts", hint="give another end point")
        return [cart.line_segment(T0, T1)]
    if spec.circle:
        c = T0[:3, 3].copy()
        if spec.center_offset is not None:
            c = c + np.asarray(floats(spec.center_offset, 3, "--center-offset"))
        elif spec.center is not None:
            c = np.asarray(floats(spec.center, 3, "--center"))
        axis = np.asarray(floats(spec.normal, 3, "--normal"))
        if spec.radius is None:
            return [cart.circle_segment(T0, c, axis, spec.angle)]
        return cart.circle_about(T0, c, spec.radius, axis, spec.angle)
    if spec.arc_to is not None and spec.arc_via is not None:
        via, to = floats(spec.arc_via, 3, "--arc-via"), floats(spec.arc_to, 3, "--arc-to")
        return [cart.arc_through(T0, np.asarray(via), np.asarray(to))]
    assert spec.waypoints is not None
    return waypoint_segments(spec.waypoints, T0)


def waypoint_segments(path: Path, T0: Array) -> list[cart.Segment]:
    """Straight segments through the poses of a CSV (x_m,y_m,z_m[,roll_rad,pitch_rad,yaw_rad])."""
    from armtool.fileio import read_text

    text = read_text(path, "waypoints file", MAX_WAYPOINT_BYTES)
    from armtool.csvrows import csv_rows

    rows = [
        (n, r)
        for n, r in csv_rows(text.splitlines(), str(path), 1, "waypoints CSV")
        if r and not r[0].lstrip().startswith("#")
    ]
    if not rows:
        raise ArmtoolError("no waypoints", str(path))
    header = [h.strip() for h in rows[0][1]]
    if header[:3] != ["x_m", "y_m", "z_m"] or header[3:] not in ([], ["roll_rad", "pitch_rad", "yaw_rad"]):
        raise ArmtoolError("waypoint header must be x_m,y_m,z_m[,roll_rad,pitch_rad,yaw_rad]", f"{path}:{rows[0][0]}")
    poses = [np.asarray(T0)]
    for line_no, row in rows[1:]:
        where = f"{path}:{line_no}"
        if len(row) != len(header):
            raise ArmtoolError(f"row has {len(row)} fields, the header has {len(header)}", where)
        try:
            v = [float(c) for c in row]
        except ValueError:
            raise ArmtoolError("not a number in the row", where) from None
        if not all(math.isfinite(x) for x in v):
            raise ArmtoolError("the row holds a NaN or infinity", where)
        T = poses[-1].copy()
        T[:3, 3] = v[:3]
        if len(v) == 6:
            T[:3, :3] = rpy_matrix(*v[3:])
        poses.append(T)
    segs = [cart.line_segment(a, b) for a, b in zip(poses, poses[1:]) if np.abs(a - b).max() > 1e-12]
    if not segs:
        raise ArmtoolError("the waypoints do not move the tool", str(path))
    return segs


def plan_cartesian(
    urdf: Path,
    base: str | None,
    tip: str | None,
    start: str | None,
    spec: PathSpec,
    options: cart.CartesianOptions,
    solver: str,
    srdf: Path | None = None,
    xacro_args: Mapping[str, str] | None = None,
    package_paths: Sequence[Path] = (),
    *,
    group: str | None = None,
    group_why: str = "",
    srdf_xacro_args: Mapping[str, str] | None = None,
    locks: Mapping[str, float] | None = None,
) -> CartesianPlan:
    """The joint path along `spec` from `start`, as far as it could be followed. The chain is
    `group`'s of the SRDF, built as MoveIt builds it (`armtool.ik.group`), else base → tip (by
    default the longest chain from the root), with `locks` held (`armtool.ik.locks`). The SRDF (a
    .srdf.xacro expanded with `srdf_xacro_args`, else `xacro_args`) also gives the default start.
    `solver` "auto": the closed form where the chain has one, else lm (`path_solver`)."""
    from armtool.ik.locks import full_joint_names, lock
    from armtool.model.chain import chain_from_xml
    from armtool.model.load import load_robot_xml
    from armtool.traj.start import read_srdf

    if not urdf.is_file():
        raise ArmtoolError("URDF not found", str(urdf))
    spec.check()
    if group is not None and (base is not None or tip is not None):
        raise ArmtoolError(
            f"give either --group or --base/--tip, not both (group '{group}'{group_why and f': {group_why}'})"
        )
    if group is not None and srdf is None:
        raise ArmtoolError(
            "--group needs --srdf", hint="pass the MoveIt SRDF that defines the group, or --moveit-config DIR"
        )
    if srdf is not None and not srdf.is_file():
        raise ArmtoolError("SRDF not found", str(srdf))
    root = load_robot_xml(urdf, xacro_args, package_paths)
    semantic = None
    if srdf is not None:
        semantic = read_srdf(srdf, srdf_xacro_args if srdf_xacro_args is not None else xacro_args, package_paths)
    how = (
        "--base/--tip"
        if base is not None or tip is not None
        else "the default chain (pass --base/--tip or --group for another)"
    )
    if group is not None and semantic is not None:
        from armtool.ik.group import group_chain

        found = group_chain(semantic.root, group, root, source=str(srdf))
        base, tip = found.base, found.tip
        how = f"group '{group}' of {semantic.path.name}" + (f" ({group_why})" if group_why else "")
    whole = chain_from_xml(root, base, tip, source=urdf.name)
    chain = lock(whole, locks or {})
    q0, start_how = _start(chain, start, urdf, semantic, xacro_args, package_paths)
    segs = segments(spec, chain.fk(q0))
    ik, solver_how = path_solver(solver, chain)
    result = cart.compute_cartesian(chain, ik, q0, segs, options)
    prismatic = tuple(not r for r in whole.revolute)
    return CartesianPlan(
        chain,
        result,
        Trajectory(tuple(full_joint_names(chain)), chain.expand(result.q), source=str(urdf), prismatic=prismatic),
        start_how,
        how,
        solver_how,
    )


def path_solver(name: str, chain: Chain) -> tuple[cart.PoseSolver, str]:
    """The solver that steps the path, and what to tell about it. `auto`: `analytic` where the chain
    has a closed form, else `search` where its 1-D search applies (each point then the nearest of
    every solution), else `lm`, saying why."""
    from armtool.ik.registry import make_solver

    if name == "auto":
        try:
            return make_solver("analytic", chain), _CLOSED_FORM
        except ArmtoolError as exc:  # no closed form: the 1-D search where it applies, else iterative
            try:
                return make_solver("search", chain), _SEARCH
            except ArmtoolError:
                return _lm(chain), f"lm (iterative; no closed form for this chain: {exc.what})"
    if name == "lm":
        return _lm(chain), "lm"
    if name == "analytic":
        try:
            return make_solver(name, chain), _CLOSED_FORM
        except ArmtoolError as exc:  # the same reason, told in traj cartesian's options
            raise ArmtoolError(
                exc.what, exc.where, "--lock JOINT=VALUE holds a 7-DoF arm's joint; or --solver auto (lm here)"
            ) from None
    return make_solver(name, chain), name


_CLOSED_FORM = "analytic (closed form: each point takes the solution nearest the previous one)"
_SEARCH = (
    "search (every solution by a 1-D search, no closed form: each point takes the solution nearest the previous one)"
)


def _lm(chain: Chain) -> cart.PoseSolver:
    """lm without its table of poses until a point needs it: a path's next point is near its seed."""
    from armtool.ik.registry import make_solver

    return make_solver("lm", chain, lazy_table=True)


def require_fraction(result: cart.CartesianResult, min_fraction: float) -> None:
    """Below `min_fraction` of the path (or a single point) there is nothing to write: an error."""
    if len(result.q) < 2 or result.fraction < min_fraction:
        raise ArmtoolError(
            f"only {result.fraction:.4f} of the path achieved: stopped after point {len(result.q) - 1} "
            f"({result.reason}: {result.detail}); nothing written",
            hint="check that the path is reachable from --start (another --start, or --lock a joint of a 7-DoF arm), "
            "or pass --min-fraction 0 to write the part achieved",
        )


def report_lines(result: cart.CartesianResult, plan: CartesianPlan | None = None) -> list[str]:
    """What `traj cartesian` tells on stderr: the chain and its start, fraction, precision, jumps,
    and where and why it stopped (plain text)."""
    rel = ", ".join(map(str, result.relative_jumps)) or "none"
    ab = ", ".join(map(str, result.absolute_jumps)) or "none"
    lines = []
    if plan is not None:
        chain = plan.chain
        lines += [
            f"chain: {plan.chain_how}: base '{chain.base}' -> tip '{chain.tip}', {chain.n} joints "
            f"({', '.join(chain.joint_names)})",
            f"start: {plan.start_how}: " + ", ".join(f"{v:.4g}" for v in plan.trajectory.positions[0]),
        ]
        if chain.locks:
            from armtool.ik.locks import describe

            lines.append(f"locked: {describe(chain)} (held at that value in the output)")
        if plan.solver_how:
            lines.append(f"solver: {plan.solver_how}")
    lines += [
        f"fraction {result.fraction:.4f}: {len(result.q)} points ({result.inserted} inserted by the precision check), "
        f"worst deviation {result.max_deviation_m * 1000:.3f} mm / {result.max_deviation_rad:.4f} rad",
        f"jumps (step k: point k → k+1): relative rule {rel}; absolute rule {ab}",
    ]
    if result.closed_form:
        switches = result.branch_switches
        lines.append(f"branch switches: {len(switches) or 'none'}" + (":" if switches else ""))
        lines += [f"  {b.text()}" for b in switches]
    if result.reason:
        lines.append(
            f"stopped at point {len(result.q) - 1} (fraction {result.fraction:.4f}): {result.reason}: {result.detail}"
        )
    return lines


def report_json(plan: CartesianPlan) -> str:
    """`traj cartesian --report`: what report_lines says, for scripts (`schema_version` 1; steps k are
    point k → k+1 of the achieved path's points, params the path parameter 0..1)."""
    import json

    r, chain = plan.result, plan.chain
    doc = {
        "schema_version": 1,
        "chain": {
            "base": chain.base,
            "tip": chain.tip,
            "joints": list(plan.trajectory.joint_names),
            "how": plan.chain_how,
        },
        "locked": {name: value for _, name, value in chain.locks},
        "solver": plan.solver_how,
        "closed_form": r.closed_form,
        "start": {"how": plan.start_how, "positions": plan.trajectory.positions[0].tolist()},
        "fraction": r.fraction,
        "points": len(r.q),
        "inserted": r.inserted,
        "max_deviation_m": r.max_deviation_m,
        "max_deviation_rad": r.max_deviation_rad,
        "jumps": {"relative_rule": r.relative_jumps, "absolute_rule": r.absolute_jumps},
        "branch_switches": [
            {
                "step": b.step,
                "param": b.param,
                "jump": b.jump,
                "flips": [{"joint": f.joint, "from": f.from_value, "to": f.to_value} for f in b.flips],
                "note": b.note,
            }
            for b in r.branch_switches
        ],
        "stopped": {"reason": r.reason, "detail": r.detail} if r.reason else None,
    }
    return json.dumps(doc, indent=2) + "\n"
