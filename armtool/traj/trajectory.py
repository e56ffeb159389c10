"""A joint trajectory: names, positions per point, optional times, velocities, accelerations.

One in-memory shape for every file format. `lines` keeps the source line of each point, so a
finding or an error can say file:line. Joints are matched by name (`reorder`), never by position.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from armtool.errors import ArmtoolError

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Trajectory:
    joint_names: tuple[str, ...]
    positions: Array  # (N, n)
    times: Array | None = None  # (N,) seconds from start, or None for a path without timing
    velocities: Array | None = None  # (N, n)
    accelerations: Array | None = None  # (N, n)
    source: str = "<memory>"
    lines: tuple[int, ...] = field(default=())  # source line of each point (0: unknown)
    prismatic: tuple[bool, ...] = field(default=())  # per joint: metres rather than radians

    def __post_init__(self) -> None:
        n_points, n = self.positions.shape
        if n != len(self.joint_names):
            raise ArmtoolError(f"{n} position columns for {len(self.joint_names)} joints", self.source)
        for name, arr in (
            ("times", self.times),
            ("velocities", self.velocities),
            ("accelerations", self.accelerations),
        ):
            if arr is not None and arr.shape[0] != n_points:
                raise ArmtoolError(f"{arr.shape[0]} {name} for {n_points} points", self.source)

    @property
    def n_points(self) -> int:
        return int(self.positions.shape[0])

    @property
    def duration_s(self) -> float:
        return float(self.times[-1] - self.times[0]) if self.times is not None and self.n_points else 0.0

    def where(self, index: int) -> str:
        line = self.lines[index] if index < len(self.lines) else 0
        return f"{self.source}:{line}" if line else f"{self.source} point {index}"

    def line(self, index: int) -> int:
        return self.lines[index] if index < len(self.lines) and self.lines[index] else 1

    def is_prismatic(self, j: int) -> bool:
        return bool(self.prismatic[j]) if j < len(self.prismatic) else False

    def unit(self, j: int) -> str:
        return "m" if self.is_prismatic(j) else "rad"

    def reorder(self, names: list[str] | tuple[str, ...]) -> Trajectory:
        """The same trajectory with its joints in the order of `names` (by name; all must be present)."""
        names = tuple(names)
        if names == self.joint_names:
            return self
        missing = [n for n in names if n not in self.joint_names]
        if missing:
            raise ArmtoolError(
                f"trajectory has no joint(s) {', '.join(missing)}",
                self.source,
                hint="trajectory joints: " + ", ".join(self.joint_names),
            )
        idx = [self.joint_names.index(n) for n in names]
        return replace(
            self,
            joint_names=names,
            positions=self.positions[:, idx].copy(),
            velocities=_columns(self.velocities, idx),
            accelerations=_columns(self.accelerations, idx),
            prismatic=tuple(self.is_prismatic(i) for i in idx),
        )

    def untimed(self) -> Trajectory:
        return replace(self, times=None, velocities=None, accelerations=None)


def _columns(a: Array | None, idx: list[int]) -> Array | None:
    return None if a is None else a[:, idx].copy()
