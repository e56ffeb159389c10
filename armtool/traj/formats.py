"""Trajectory files in and out: CSV, ROS JointTrajectory YAML (ROS 2 and ROS 1), MoveIt RobotTrajectory
YAML, JSON. The format is detected from the content, not the file name.

CSV: an optional `time_s` column, then per joint `<joint>_rad` (or `<joint>_m` for a prismatic
joint) and optionally `<joint>_rad_s` / `<joint>_rad_s2` (`_m_s`, `_m_s2`): the column names
`armtool servo-lut apply --column <joint>_rad` reads. ROS YAML as `ros2 topic echo` prints a
`trajectory_msgs/JointTrajectory` (`time_from_start: {sec, nanosec}`) or as `rostopic echo`
does (`{secs, nsecs}`); a MoveIt `RobotTrajectory` holds one under `joint_trajectory`.
A path without timing has no `time_s` column (CSV) or every `time_from_start` zero.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from armtool.errors import ArmtoolError
from armtool.traj.choices import TrajFormat
from armtool.traj.trajectory import Array, Trajectory

SCHEMA_VERSION = 1
_SUFFIXES = (
    ("_rad_s2", "acc", False),
    ("_m_s2", "acc", True),
    ("_rad_s", "vel", False),
    ("_m_s", "vel", True),
    ("_rad", "pos", False),
    ("_m", "pos", True),
)


# ---- reading ---------------------------------------------------------------------------------
MAX_TRAJ_BYTES = 256 * 1024 * 1024  # ~2 million points of a 7-joint CSV; more is not a trajectory file


class LoadedTrajectory(NamedTuple):
    """A trajectory and the format it was read in (the default output format)."""

    trajectory: Trajectory
    format: TrajFormat


def read_trajectory(path: Path | str, text: str | None = None) -> LoadedTrajectory:
    """Read a trajectory file (or `text` named `path`, e.g. stdin), detecting its format."""
    source = str(path)
    if text is None:
        from armtool.fileio import read_text

        text = read_text(path, "trajectory file", MAX_TRAJ_BYTES)
    fmt = detect_format(text, source)
    if fmt is TrajFormat.CSV:
        return LoadedTrajectory(_read_csv(text, source), fmt)
    return LoadedTrajectory(_read_structured(text, source, fmt), fmt)


def detect_format(text: str, source: str = "<text>") -> TrajFormat:
    body = [ln.strip() for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not body:
        raise ArmtoolError(
            "trajectory file is empty", source, "write a CSV header (time_s,<joint>_rad,...) or a JointTrajectory"
        )
    first = body[0]
    if first.startswith(("{", "[")):
        return TrajFormat.JSON
    if first.startswith("---") or (":" in first and "," not in first.split(":")[0]):
        head = "\n".join(body[:400])
        if "joint_trajectory" in head and "joint_names" not in first:
            return TrajFormat.MOVEIT
        return TrajFormat.ROS1 if "secs:" in head and "nanosec" not in head else TrajFormat.ROS2
    return TrajFormat.CSV


def _float(cell: str, what: str, where: str) -> float:
    try:
        value = float(cell)
    except ValueError:
        raise ArmtoolError(f"{what} is not a number: {cell.strip()!r}", where) from None
    if not math.isfinite(value):
        raise ArmtoolError(f"{what} is {cell.strip()}", where, "every value must be a finite number")
    return value


def _read_csv(text: str, source: str) -> Trajectory:
    lines = text.splitlines()
    first = 0
    while first < len(lines) and (not lines[first].strip() or lines[first].lstrip().startswith("#")):
        first += 1
    from armtool.csvrows import csv_rows

    if first == len(lines):
        raise ArmtoolError("no header row", source, "the first line names the columns, e.g. time_s,joint1_rad")
    numbered = csv_rows(lines[first:], source, first + 1, "trajectory CSV")
    header = [h.strip() for h in numbered[0][1]]
    hwhere = f"{source}:{first + 1}"
    columns: dict[str, dict[str, int]] = {}
    prismatic: dict[str, bool] = {}
    time_col: int | None = None
    for c, name in enumerate(header):
        if name == "time_s":
            time_col = c
            continue
        for suffix, kind, is_m in _SUFFIXES:
            if name.endswith(suffix) and len(name) > len(suffix):
                joint = name[: -len(suffix)]
                if kind in columns.setdefault(joint, {}):
                    raise ArmtoolError(f"column '{name}' appears twice", hwhere)
                columns[joint][kind] = c
                if kind == "pos":
                    prismatic[joint] = is_m
                break
        else:
            hint = "name columns time_s, <joint>_rad (or _m), <joint>_rad_s, <joint>_rad_s2"
            if name.endswith("_deg"):
                hint = f"write radians: {name[:-4]}_rad"
            raise ArmtoolError(f"column '{name}' is not a time or joint column", hwhere, hint)
    joints = [j for j in columns if "pos" in columns[j]]
    orphans = [j for j in columns if "pos" not in columns[j]]
    if orphans:
        raise ArmtoolError(
            f"joint '{orphans[0]}' has velocity/acceleration columns but no position column",
            hwhere,
            f"add a column {orphans[0]}_rad",
        )
    if not joints:
        raise ArmtoolError(
            "no joint position column", hwhere, "name columns <joint>_rad (or <joint>_m), e.g. time_s,joint1_rad"
        )
    if len(set(joints)) != len(joints):
        raise ArmtoolError("duplicate joint", hwhere)
    for kind in ("vel", "acc"):
        have = [j for j in joints if kind in columns[j]]
        if have and len(have) != len(joints):
            lack = next(j for j in joints if kind not in columns[j])
            raise ArmtoolError(
                f"joint '{lack}' lacks its {'velocity' if kind == 'vel' else 'acceleration'} column while others have one",
                hwhere,
            )
    rows: list[list[float]] = []
    line_nos: list[int] = []
    for offset, row in numbered[1:]:
        if not any(cell.strip() for cell in row) or row[0].lstrip().startswith("#"):
            continue
        where = f"{source}:{offset}"
        if len(row) != len(header):
            raise ArmtoolError(f"row has {len(row)} fields, the header has {len(header)}", where)
        rows.append([_float(cell, f"'{header[c]}'", where) for c, cell in enumerate(row)])
        line_nos.append(offset)
    if not rows:
        raise ArmtoolError("no trajectory points", source, "add rows below the header")
    data = np.asarray(rows, dtype=np.float64)

    def pick(kind: str) -> Array | None:
        return data[:, [columns[j][kind] for j in joints]] if kind in columns[joints[0]] else None

    return Trajectory(
        tuple(joints),
        data[:, [columns[j]["pos"] for j in joints]],
        None if time_col is None else data[:, time_col],
        pick("vel"),
        pick("acc"),
        source,
        tuple(line_nos),
        tuple(prismatic[j] for j in joints),
    )


def _point_lines(text: str, moveit: bool) -> list[int]:
    """Source line of each item of `points` (YAML marks; JSON is YAML enough for this)."""
    import yaml

    from armtool.yamlload import compose_all

    try:
        docs = compose_all(text)
    except yaml.YAMLError:
        return []
    if not docs or not isinstance(docs[0], yaml.MappingNode):
        return []
    node: Any = docs[0]
    for key in ("joint_trajectory", "points") if moveit else ("points",):
        found = [v for k, v in node.value if isinstance(k, yaml.ScalarNode) and k.value == key]
        if not found:
            return []
        node = found[0]
    if not isinstance(node, yaml.SequenceNode):
        return []
    return [item.start_mark.line + 1 for item in node.value]


def _load_structured(text: str, source: str, fmt: TrajFormat) -> Any:
    if fmt is TrajFormat.JSON:
        try:
            return json.loads(text)
        except json.JSONDecodeError as exc:
            raise ArmtoolError(f"trajectory file is not valid JSON: {exc.msg}", f"{source}:{exc.lineno}") from None
    import yaml

    from armtool.yamlload import safe_load_all

    try:
        docs = safe_load_all(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"{source}:{mark.line + 1}" if mark is not None else source
        raise ArmtoolError(
            f"trajectory file is not valid YAML: {getattr(exc, 'problem', None) or exc}", where
        ) from None
    return docs[0] if docs else None


def _seconds(value: Any, where: str) -> float:
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return _float(str(value), "time_from_start", where)
    if isinstance(value, dict):
        if "sec" in value or "nanosec" in value:
            return (
                _float(str(value.get("sec", 0)), "sec", where)
                + _float(str(value.get("nanosec", 0)), "nanosec", where) * 1e-9
            )
        if "secs" in value or "nsecs" in value:
            return (
                _float(str(value.get("secs", 0)), "secs", where)
                + _float(str(value.get("nsecs", 0)), "nsecs", where) * 1e-9
            )
    raise ArmtoolError(f"time_from_start is not {{sec, nanosec}} or {{secs, nsecs}}: {value!r}", where)


def _read_structured(text: str, source: str, fmt: TrajFormat) -> Trajectory:
    doc = _load_structured(text, source, fmt)
    moveit = isinstance(doc, dict) and isinstance(doc.get("joint_trajectory"), dict)
    lines = _point_lines(text, moveit)
    msg = doc["joint_trajectory"] if moveit else doc
    if not isinstance(msg, dict) or "joint_names" not in msg or "points" not in msg:
        raise ArmtoolError(
            "not a trajectory: expected joint_names and points (JointTrajectory), or joint_trajectory (MoveIt RobotTrajectory)",
            source,
            "write time_s,<joint>_rad CSV, or a JointTrajectory as `ros2 topic echo` prints it",
        )
    names = msg["joint_names"]
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise ArmtoolError("joint_names must be a non-empty list of names", source)
    points = msg["points"]
    if not isinstance(points, list) or not points:
        raise ArmtoolError("no trajectory points", source)
    n = len(names)
    pos, vel, acc, times = [], [], [], []
    for i, p in enumerate(points):
        where = f"{source}:{lines[i]}" if i < len(lines) else f"{source} point {i}"
        if not isinstance(p, dict):
            raise ArmtoolError(f"point {i} is not a mapping", where)

        def vector(key: str, required: bool) -> list[float] | None:
            raw = p.get(key)
            if raw is None or raw == [] or raw == "[]":
                if required:
                    raise ArmtoolError(f"point {i} has no {key}", where)
                return None
            if not isinstance(raw, list) or len(raw) != n:
                raise ArmtoolError(
                    f"point {i}: {key} has {len(raw) if isinstance(raw, list) else 'no list of'} values for {n} joints",
                    where,
                )
            return [_float(str(v), f"{key}[{k}] ({names[k]})", where) for k, v in enumerate(raw)]

        pos.append(vector("positions", True))
        vel.append(vector("velocities", False))
        acc.append(vector("accelerations", False))
        if "time_from_start_s" in p:
            times.append(_seconds(p["time_from_start_s"], where))
        elif "time_from_start" in p:
            times.append(_seconds(p["time_from_start"], where))
        else:
            times.append(0.0)

    def stack(rows: list[list[float] | None], what: str) -> Array | None:
        have = [r is not None for r in rows]
        if not any(have):
            return None
        if not all(have):
            i = have.index(False)
            raise ArmtoolError(
                f"point {i} has no {what} while other points have them",
                f"{source}:{lines[i]}" if i < len(lines) else source,
            )
        return np.asarray(rows, dtype=np.float64)

    t = np.asarray(times, dtype=np.float64)
    timed = len(points) == 1 or bool(np.any(t != 0.0))
    return Trajectory(
        tuple(names),
        np.asarray(pos, dtype=np.float64),
        t if timed else None,
        stack(vel, "velocities"),
        stack(acc, "accelerations"),
        source,
        tuple(lines[: len(points)]),
    )


# ---- writing ---------------------------------------------------------------------------------
def _num(x: float) -> str:
    return repr(float(x) + 0.0)  # no "-0.0"


def format_trajectory(traj: Trajectory, fmt: TrajFormat) -> str:
    """The trajectory as text in `fmt`. An untimed path is refused as a ROS or MoveIt trajectory:
    every time_from_start would be 0, and ros2_controllers' joint_trajectory_controller rejects the
    goal ("Time between points 0 and 1 is not strictly increasing", validate_trajectory_msg)."""
    if fmt is TrajFormat.CSV:
        return _csv(traj)
    if fmt is TrajFormat.JSON:
        return _json(traj)
    if traj.times is None and traj.n_points > 1:
        raise ArmtoolError(
            f"an untimed path cannot be written as a {fmt.value} trajectory: every time_from_start would be 0, "
            "which a joint_trajectory_controller rejects (time must increase strictly from point to point)",
            hint="time it first (armtool traj time PATH --urdf URDF -o timed.yaml), "
            "or write the path as CSV or JSON (-o path.csv, --to csv)",
        )
    return _yaml(traj, fmt)


def _csv(traj: Trajectory) -> str:
    header = ["time_s"] if traj.times is not None else []
    units = [traj.unit(j) for j in range(len(traj.joint_names))]
    header += [f"{name}_{u}" for name, u in zip(traj.joint_names, units)]
    if traj.velocities is not None:
        header += [f"{name}_{u}_s" for name, u in zip(traj.joint_names, units)]
    if traj.accelerations is not None:
        header += [f"{name}_{u}_s2" for name, u in zip(traj.joint_names, units)]
    out = [",".join(header)]
    for i in range(traj.n_points):
        row = ([traj.times[i]] if traj.times is not None else []) + list(traj.positions[i])
        row += list(traj.velocities[i]) if traj.velocities is not None else []
        row += list(traj.accelerations[i]) if traj.accelerations is not None else []
        out.append(",".join(_num(v) for v in row))
    return "\n".join(out) + "\n"


def _json(traj: Trajectory) -> str:
    points = []
    for i in range(traj.n_points):
        p: dict[str, Any] = {}
        if traj.times is not None:
            p["time_from_start_s"] = float(traj.times[i])
        p["positions"] = [float(v) for v in traj.positions[i]]
        if traj.velocities is not None:
            p["velocities"] = [float(v) for v in traj.velocities[i]]
        if traj.accelerations is not None:
            p["accelerations"] = [float(v) for v in traj.accelerations[i]]
        points.append("    " + json.dumps(p))
    head = json.dumps({"schema_version": SCHEMA_VERSION, "joint_names": list(traj.joint_names)})[:-1]
    return head + ', "points": [\n' + ",\n".join(points) + "\n]}\n"


def _yaml(traj: Trajectory, fmt: TrajFormat) -> str:
    sec, nsec = ("secs", "nsecs") if fmt is TrajFormat.ROS1 else ("sec", "nanosec")
    indent = "  " if fmt is TrajFormat.MOVEIT else ""
    out: list[str] = []
    if fmt is TrajFormat.MOVEIT:
        out.append("joint_trajectory:")
    stamp = f"{{{sec}: 0, {nsec}: 0}}"
    out.append(f"{indent}header:")
    if fmt is TrajFormat.ROS1:
        out.append(f"{indent}  seq: 0")
    out.append(f"{indent}  stamp: {stamp}")
    out.append(f"{indent}  frame_id: ''")
    out.append(f"{indent}joint_names:")
    out += [f"{indent}- {name}" for name in traj.joint_names]
    out.append(f"{indent}points:")

    def flow(a: Array | None, i: int) -> str:
        return "[]" if a is None else "[" + ", ".join(_num(v) for v in a[i]) + "]"

    for i in range(traj.n_points):
        t = float(traj.times[i]) if traj.times is not None else 0.0
        whole = math.floor(t)
        nanos = int(round((t - whole) * 1e9))
        if nanos >= 1_000_000_000:
            whole, nanos = whole + 1, nanos - 1_000_000_000
        out.append(f"{indent}- positions: {flow(traj.positions, i)}")
        out.append(f"{indent}  velocities: {flow(traj.velocities, i)}")
        out.append(f"{indent}  accelerations: {flow(traj.accelerations, i)}")
        out.append(f"{indent}  effort: []")
        out.append(f"{indent}  time_from_start: {{{sec}: {whole}, {nsec}: {nanos}}}")
    if fmt is TrajFormat.MOVEIT:
        out.append("multi_dof_joint_trajectory:")
        out.append("  header:")
        out.append(f"    stamp: {stamp}")
        out.append("    frame_id: ''")
        out.append("  joint_names: []")
        out.append("  points: []")
    return "\n".join(out) + "\n"


def format_for_output(output: Path | None, requested: TrajFormat | None, fallback: TrajFormat) -> TrajFormat:
    """The explicit format, else the output file's extension (.csv, .json, .yaml), else `fallback`."""
    if requested is not None:
        return requested
    if output is not None:
        ext = output.suffix.lower()
        if ext == ".csv":
            return TrajFormat.CSV
        if ext == ".json":
            return TrajFormat.JSON
        if ext in (".yaml", ".yml") and fallback in (TrajFormat.CSV, TrajFormat.JSON):
            return TrajFormat.ROS2
    return fallback
