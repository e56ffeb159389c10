"""The calibration parameter vector: which scalar sits where, what kind it is, how to name it.

    x = [ left frame (6) | right frame (6) | joint 0: origin tx ty tz rx ry rz, offset, gain | joint 1 …
          | joint terms: term kind 0, joint 0 (its components) | joint 1 … | term kind 1 … ]

`ParamLayout` is the only place that knows these offsets: every reader and writer of `x` asks
it (`split(x)` for views by meaning, `offset(j)`… for single indices), so a new per-joint
parameter is one change here. Every entry is a correction, so `x = 0` is the nominal robot.
Joint terms (`calib/model/terms/`: compliance under gravity, harmonics of the joint angle) are
in the vector only when `--params` asks for them; each is a change of a joint's angle in rad.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import ClassVar, Literal, NamedTuple

from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError

Component = str  # "tx" "ty" "tz" "rx" "ry" "rz" (origin, frame), "offset", "gain", or a joint term's ("sag", "sin1", …)
ORIGIN_COMPONENTS: tuple[Component, ...] = ("tx", "ty", "tz", "rx", "ry", "rz")
Unit = Literal["m", "rad", "1"]


class ParamKind(str, Enum):
    FRAME = "frame"  # a measurement frame component (camera or tag), never written to the URDF
    ORIGIN = "origin"  # a joint's 6-D origin correction component
    OFFSET = "offset"  # a joint's zero offset
    GAIN = "gain"  # a joint's gain error (transmission ratio)
    COMPLIANCE = "compliance"  # a joint's deflection under gravity (terms/compliance.py)
    HARMONIC = "harmonic"  # a joint's angle error periodic in its angle (terms/harmonics.py)


class Family(str, Enum):
    """Parameter families the user can free with `--params`."""

    ORIGINS = "origins"  # 6-D origin correction per moving joint
    OFFSETS = "offsets"  # joint zero offset
    GAINS = "gains"  # joint gain (transmission ratio error)
    COMPLIANCE = "compliance"  # joint deflection under the gravity torque of the URDF's inertials
    HARMONICS = "harmonics"  # joint angle error periodic in the joint angle (once and twice per turn)

    @property
    def kind(self) -> ParamKind:
        """The parameter kind this family frees."""
        return _FAMILY_KIND[self]


_FAMILY_KIND = {
    Family.ORIGINS: ParamKind.ORIGIN,
    Family.OFFSETS: ParamKind.OFFSET,
    Family.GAINS: ParamKind.GAIN,
    Family.COMPLIANCE: ParamKind.COMPLIANCE,
    Family.HARMONICS: ParamKind.HARMONIC,
}


NO_FAMILY = "none"  # `--params none`: hand-eye only, the robot held nominal


def parse_families(text: str) -> tuple[Family, ...]:
    """`--params origins,offsets` as families, in order, each once; `--params none` as no family
    (only the measurement frames are fitted: the baseline every calibration is compared with)."""
    parts = [p.strip() for p in text.split(",") if p.strip()]
    if NO_FAMILY in parts:
        if len(parts) > 1:
            raise ArmtoolError(
                f"--params {text}: 'none' fits no kinematic parameter, so it cannot be combined with others",
                hint="--params none (hand-eye only), or families such as --params origins,offsets",
            )
        return ()
    out = []
    for part in parts:
        try:
            out.append(Family(part))
        except ValueError:
            raise ArmtoolError(
                f"unknown parameter family '{part}' in --params",
                hint="choose from: " + ", ".join([*(f.value for f in Family), NO_FAMILY]),
            ) from None
    if not out:
        raise ArmtoolError(
            "--params is empty", hint="e.g. --params origins,offsets, or --params none for hand-eye only"
        )
    return tuple(dict.fromkeys(out))


@dataclass(frozen=True)
class Parameter:
    """One scalar unknown: where it lives and how to name it to a person."""

    name: str  # e.g. "elbow_joint.origin.tz", "camera.rx"
    group: str  # "camera", "tag", or a joint name
    kind: ParamKind
    component: Component
    unit: Unit

    @property
    def is_rotation(self) -> bool:
        return self.component.startswith("r")

    @property
    def is_translation(self) -> bool:
        return self.component.startswith("t")

    def describe(self) -> str:
        if self.kind is ParamKind.OFFSET:
            return f"zero offset of joint '{self.group}'"
        if self.kind is ParamKind.GAIN:
            return f"gain of joint '{self.group}'"
        if self.kind is ParamKind.COMPLIANCE:
            return f"deflection under gravity of joint '{self.group}'"
        if self.kind is ParamKind.HARMONIC:
            return f"{self.component} harmonic of joint '{self.group}' angle"
        what = ("rotation" if self.is_rotation else "translation") + " " + self.component[1]
        if self.kind is ParamKind.ORIGIN:
            return f"{what} of joint '{self.group}' origin"
        return f"{what} of the {self.group} frame"


class Split(NamedTuple):
    """The parameter vector by meaning; every field is a view into the vector (writes go through)."""

    left: Array  # (6,) correction of the left measurement frame (tx ty tz rx ry rz)
    right: Array  # (6,) correction of the right measurement frame
    origin: Array  # (n, 6) joint origin corrections: translation (m), then rotation vector (rad)
    offset: Array  # (n,) joint zero offsets (rad, or m for a prismatic joint)
    gain_error: Array  # (n,) joint gain − 1
    terms: tuple[Array, ...] = ()  # per joint-term kind: (n, its components) coefficients, rad


@dataclass(frozen=True)
class ParamLayout:
    """Offsets of every parameter in the vector of a chain with `joints` moving joints, and
    `terms[k]` parameters per joint of the model's k-th joint-term kind."""

    joints: int
    terms: tuple[int, ...] = ()
    FRAME_SIZE: ClassVar[int] = 6
    PER_JOINT: ClassVar[int] = 8  # 6 origin components, zero offset, gain
    _JOINTS_START: ClassVar[int] = 2 * FRAME_SIZE

    @property
    def _terms_start(self) -> int:
        return self._JOINTS_START + self.PER_JOINT * self.joints

    @property
    def size(self) -> int:
        return self._terms_start + self.joints * sum(self.terms)

    def term(self, k: int, j: int) -> list[int]:
        """Indices of joint j's parameters of the k-th joint-term kind."""
        start = self._terms_start + self.joints * sum(self.terms[:k]) + self.terms[k] * j
        return list(range(start, start + self.terms[k]))

    @property
    def frames(self) -> list[int]:
        """Indices of both measurement frames' components."""
        return list(range(self._JOINTS_START))

    def origin(self, j: int) -> list[int]:
        """Indices of joint j's origin correction: tx ty tz rx ry rz."""
        start = self._JOINTS_START + self.PER_JOINT * j
        return list(range(start, start + 6))

    def origin_rotation(self, j: int) -> list[int]:
        return self.origin(j)[3:]

    def offset(self, j: int) -> int:
        return self._JOINTS_START + self.PER_JOINT * j + 6

    def gain(self, j: int) -> int:
        return self._JOINTS_START + self.PER_JOINT * j + 7

    def split(self, x: Array) -> Split:
        """Views of `x` by meaning (x must be this layout's size and contiguous)."""
        if x.shape != (self.size,):
            raise ValueError(f"parameter vector of shape {x.shape}, layout of size {self.size}")
        k = x[self._JOINTS_START : self._terms_start].reshape(self.joints, self.PER_JOINT)
        terms = []
        for t in range(len(self.terms)):
            start = self.term(t, 0)[0] if self.terms[t] else self._terms_start
            terms.append(x[start : start + self.joints * self.terms[t]].reshape(self.joints, self.terms[t]))
        return Split(x[0:6], x[6:12], k[:, :6], k[:, 6], k[:, 7], tuple(terms))

    def parameters(
        self,
        left: str,
        right: str,
        joints: Sequence[tuple[str, bool]],
        terms: Sequence[tuple[ParamKind, Sequence[str]]] = (),
    ) -> list[Parameter]:
        """The named parameters in vector order; `joints` are (name, prismatic) in chain order,
        `terms` each joint-term kind with its components, in the model's order."""
        out: list[Parameter] = []
        for frame in (left, right):
            out += _origin_like(frame, frame, ParamKind.FRAME)
        for name, prismatic in joints:
            out += _origin_like(f"{name}.origin", name, ParamKind.ORIGIN)
            out.append(Parameter(f"{name}.offset", name, ParamKind.OFFSET, "offset", "m" if prismatic else "rad"))
            out.append(Parameter(f"{name}.gain", name, ParamKind.GAIN, "gain", "1"))
        for kind, components in terms:
            for name, _prismatic in joints:
                out += [Parameter(f"{name}.{c}", name, kind, c, "rad") for c in components]
        if len(out) != self.size:
            raise ValueError(f"{len(out)} parameters for a layout of size {self.size}")
        return out


def _origin_like(prefix: str, group: str, kind: ParamKind) -> Iterable[Parameter]:
    for c in ORIGIN_COMPONENTS:
        yield Parameter(f"{prefix}.{c}", group, kind, c, "m" if c.startswith("t") else "rad")
