"""Per-joint limits for timing and checking: position and velocity from the URDF, acceleration
(and jerk) from MoveIt's joint_limits.yaml or from options.

The URDF `<limit effort>` is a force or torque, not an acceleration; nothing here reads it. A
joint without an acceleration limit is an error when timing (`require_acceleration`) that says
where to give one; MoveIt's TOTG makes the same demand. Scaling factors scale the limits for
timing only; `check` compares against the unscaled limits.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from armtool.errors import ArmtoolError
from armtool.traj.trajectory import Array

if TYPE_CHECKING:
    from armtool.moveit.joint_limits import JointEntry
    from armtool.moveit.params import Scalar


@dataclass(frozen=True)
class JointLimits:
    names: tuple[str, ...]
    lower: Array  # position limits (-inf/inf for continuous joints)
    upper: Array
    velocity: Array  # nan: unknown
    acceleration: Array  # nan: unknown
    jerk: Array  # nan: unknown
    prismatic: tuple[bool, ...]
    sources: tuple[str, ...]  # per joint: where the limits came from (for messages)
    velocity_scaling: float = 1.0
    acceleration_scaling: float = 1.0

    def index(self, name: str) -> int:
        return self.names.index(name)

    def subset(self, names: Sequence[str]) -> JointLimits:
        idx = [self.names.index(n) for n in names]
        return replace(
            self,
            names=tuple(names),
            lower=self.lower[idx],
            upper=self.upper[idx],
            velocity=self.velocity[idx],
            acceleration=self.acceleration[idx],
            jerk=self.jerk[idx],
            prismatic=tuple(self.prismatic[i] for i in idx),
            sources=tuple(self.sources[i] for i in idx),
        )

    def unit(self, j: int) -> str:
        return "m" if self.prismatic[j] else "rad"

    def require_acceleration(self) -> None:
        missing = [n for n, a in zip(self.names, self.acceleration) if not (math.isfinite(a) and a > 0)]
        if missing:
            raise ArmtoolError(
                f"no acceleration limit for joint(s) {', '.join(missing)}",
                hint="give one in MoveIt's joint_limits.yaml (has_acceleration_limits: true, max_acceleration: ...) with "
                f"--joint-limits, or with --acc-limit {missing[0]}=VALUE (or --acc-limit VALUE for every joint); "
                "the URDF's effort is a force/torque, not an acceleration",
            )
        missing = [n for n, v in zip(self.names, self.velocity) if not (math.isfinite(v) and v > 0)]
        if missing:
            raise ArmtoolError(
                f"no velocity limit for joint(s) {', '.join(missing)}",
                hint=f"set <limit velocity> in the URDF, max_velocity in joint_limits.yaml, or --vel-limit {missing[0]}=VALUE",
            )

    def has_jerk_limits(self) -> bool:
        return bool(np.any(np.isfinite(self.jerk) & (self.jerk > 0)))

    def scaled(self) -> tuple[Array, Array]:
        """Velocity and acceleration limits times their scaling factors (for timing)."""
        return self.velocity * self.velocity_scaling, self.acceleration * self.acceleration_scaling


def _urdf_joints(
    urdf: Path, xacro_args: Mapping[str, str] | None = None, package_paths: Sequence[Path] = ()
) -> dict[str, tuple[str, float, float, float, int]]:
    """name -> (type, lower, upper, velocity, line) for every moving joint."""
    from armtool.model.load import load_robot_xml

    root = load_robot_xml(urdf, xacro_args, package_paths)
    out: dict[str, tuple[str, float, float, float, int]] = {}
    for el in root.iter("joint"):
        kind = el.get("type", "")
        if kind not in ("revolute", "prismatic", "continuous") or el.find("mimic") is not None:
            continue
        limit = el.find("limit")

        def num(key: str, default: float) -> float:
            raw = limit.get(key) if limit is not None else None
            try:
                return float(raw) if raw is not None else default
            except ValueError:
                raise ArmtoolError(
                    f"joint '{el.get('name')}': <limit {key}=\"{raw}\"> is not a number", f"{urdf}:{el.sourceline}"
                ) from None

        lower, upper = (-math.inf, math.inf) if kind == "continuous" else (num("lower", 0.0), num("upper", 0.0))
        velocity = num("velocity", math.nan)
        out[el.get("name", "")] = (kind, lower, upper, velocity if velocity > 0 else math.nan, el.sourceline or 0)
    return out


def _parse_overrides(values: Sequence[str], names: Sequence[str], option: str) -> dict[str, float]:
    """`--acc-limit 5` (every joint) or `--acc-limit joint1=5,joint2=3` -> name -> value."""
    out: dict[str, float] = {}
    for value in values:
        for part in value.split(","):
            part = part.strip()
            if not part:
                continue
            name, eq, raw = part.rpartition("=")
            try:
                number = float(raw)
            except ValueError:
                raise ArmtoolError(
                    f"{option} {part!r}: not a number", hint=f"{option} 5.0 or {option} joint1=5.0,joint2=3"
                ) from None
            if not (math.isfinite(number) and number > 0):
                raise ArmtoolError(f"{option} {part!r}: the limit must be a positive number")
            if not eq:
                out.update({n: number for n in names})
            elif name not in names:
                from armtool.suggest import did_you_mean

                raise ArmtoolError(
                    f"{option}: no joint '{name}'{did_you_mean(name, list(names))}", hint="joints: " + ", ".join(names)
                )
            else:
                out[name] = number
    return out


def load_limits(
    urdf: Path,
    joint_limits: Path | None = None,
    *,
    vel_limits: Sequence[str] = (),
    acc_limits: Sequence[str] = (),
    jerk_limits: Sequence[str] = (),
    velocity_scaling: float | None = None,
    acceleration_scaling: float | None = None,
    xacro_args: Mapping[str, str] | None = None,
    package_paths: Sequence[Path] = (),
) -> JointLimits:
    """Limits of every moving joint of the URDF (or xacro, expanded with `xacro_args`);
    joint_limits.yaml (any layout MoveIt reads) and options override the URDF."""
    joints = _urdf_joints(urdf, xacro_args, package_paths)
    names = list(joints)
    lower = np.array([joints[n][1] for n in names], dtype=np.float64)
    upper = np.array([joints[n][2] for n in names], dtype=np.float64)
    vel = np.array([joints[n][3] for n in names], dtype=np.float64)
    acc = np.full(len(names), math.nan)
    jerk = np.full(len(names), math.nan)
    sources = [f"{urdf.name}:{joints[n][4]}" for n in names]
    file_vs, file_as = None, None
    if joint_limits is not None:
        from armtool.moveit.joint_limits import load_joint_limits

        doc = load_joint_limits(joint_limits, dict(xacro_args or {}))
        unknown = sorted({u for e in doc.joints for u in e.name.unknown})
        if unknown:
            import logging

            logging.getLogger(__name__).warning(
                "%s: %s unknown (no xacro argument of that name): its keys were matched to the URDF's joints by "
                "the rest of the name",
                joint_limits.name,
                ", ".join(f"$(var {u})" for u in unknown),
            )
        file_vs = _factor(doc.scaling.get("default_velocity_scaling_factor"), joint_limits)
        file_as = _factor(doc.scaling.get("default_acceleration_scaling_factor"), joint_limits)
        for i, name in enumerate(names):
            entry = doc.entry_for(name)
            if entry is None:
                continue  # limits of joints outside the URDF (or other groups) do not matter here
            _apply(entry, i, joints[name][0], lower, upper, vel, acc, jerk, joint_limits)
            note = entry.name.note()
            sources[i] += f", {joint_limits.name}:{entry.line}" + (f" ({entry.name.written}: {note})" if note else "")
    for values, arr, option in (
        (vel_limits, vel, "--vel-limit"),
        (acc_limits, acc, "--acc-limit"),
        (jerk_limits, jerk, "--jerk-limit"),
    ):
        for name, number in _parse_overrides(values, names, option).items():
            arr[names.index(name)] = number
    vs = velocity_scaling if velocity_scaling is not None else (file_vs or 1.0)
    as_ = acceleration_scaling if acceleration_scaling is not None else (file_as or 1.0)
    for label, f in (("velocity", vs), ("acceleration", as_)):
        if not (0 < f <= 1):
            raise ArmtoolError(
                f"{label} scaling factor {f} is outside (0, 1]",
                hint="MoveIt's scaling factors are fractions of the limits",
            )
    return JointLimits(
        tuple(names),
        lower,
        upper,
        vel,
        acc,
        jerk,
        tuple(joints[n][0] == "prismatic" for n in names),
        tuple(sources),
        vs,
        as_,
    )


def _factor(value: Scalar | None, path: Path) -> float | None:
    if value is None:
        return None
    number = value.number()
    if number is None:
        raise ArmtoolError(f"scaling factor {value.text!r} is not a number", f"{path}:{value.line}")
    return number if number > 0 else None


def _apply(
    entry: JointEntry,
    i: int,
    kind: str,
    lower: Array,
    upper: Array,
    vel: Array,
    acc: Array,
    jerk: Array,
    path: Path,
) -> None:
    """One joint's overrides, as MoveIt's RobotModelLoader applies them: min/max_position when
    given (not for continuous joints); a velocity, acceleration or jerk limit only when its
    has_*_limits flag is true, and none at all when the flag is false."""
    name = entry.name.written

    def num(key: str) -> float | None:
        value = entry.values.get(key)
        if value is None:
            if key in entry.not_scalar:
                shape, line, _ = entry.not_scalar[key]
                raise ArmtoolError(f"`{key}` of joint '{name}' is {shape}, not a number", f"{path}:{line}")
            return None
        number = value.number()
        if number is None:
            raise ArmtoolError(
                f"`{key}` of joint '{name}' is {value.text!r}, not a number",
                f"{path}:{value.line}",
                f"set {key}: <number>",
            )
        return number

    def flag(key: str) -> bool | None:
        value = entry.values.get(key)
        if value is None:
            return None
        if value.kind != "bool":
            raise ArmtoolError(
                f"`{key}` of joint '{name}' is {value.text!r}, not true or false", f"{path}:{value.line}"
            )
        return value.flag()

    if kind != "continuous":
        for key, arr in (("min_position", lower), ("max_position", upper)):
            number = num(key)
            if number is not None:
                arr[i] = number
    for key, arr in (("velocity", vel), ("acceleration", acc), ("jerk", jerk)):
        on = flag(f"has_{key}_limits")
        if on is False:
            arr[i] = math.nan  # switched off: no limit (MoveIt drops the URDF's velocity too)
        elif on:
            number = num(f"max_{key}")
            if number is None:
                raise ArmtoolError(
                    f"joint '{name}' sets has_{key}_limits but no max_{key}",
                    f"{path}:{entry.line}",
                    f"set max_{key}: <number>",
                )
            arr[i] = number if number > 0 else math.nan
