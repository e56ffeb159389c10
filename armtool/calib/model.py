"""The measurement model: which pixel each tag corner should land on, given joints and parameters.

Eye-to-hand (camera fixed, tag on the flange):  cMt = cMb · bMf(q) · fMt
Eye-in-hand (camera on the flange, tag fixed):   cMt = cMf · bMf(q)⁻¹ · bMt
Both are `cMt = L · F(q)^±1 · R` with two free "measurement frames" L and R, which also carry the
base and tool gauge (FIGAROH's metrology frames); they are fitted but never written to the URDF.

bMf(q) is the URDF chain with, per moving joint j, `origin_j · SE3(exp(r_j), t_j)` (6-D origin
correction), the reading turned into `gain_j · q_j + offset_j` (zero offset, optional gain).
The parameter vector holds only corrections, so 0 is the nominal robot.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from armtool.calib import se3
from armtool.calib.choices import Setup
from armtool.calib.params import Family, Parameter, ParamKind, ParamLayout, Split
from armtool.calib.se3 import Array
from armtool.model.chain import Chain, axis_angle_batch


@dataclass
class CalibModel:
    """Chain + setup + the layout of the full parameter vector (all candidates, free or not)."""

    chain: Chain
    setup: Setup
    L0: Array  # nominal left frame: cMb (eye-to-hand) or cMf (eye-in-hand)
    R0: Array  # nominal right frame: fMt (eye-to-hand) or bMt (eye-in-hand)
    params: list[Parameter] = field(default_factory=list)

    def __post_init__(self) -> None:
        if not self.params:
            self.params = self._layout()

    @property
    def left_name(self) -> str:
        return "camera" if self.setup is Setup.EYE_TO_HAND else "camera_in_flange"

    @property
    def right_name(self) -> str:
        return "tag" if self.setup is Setup.EYE_TO_HAND else "tag_in_base"

    def _layout(self) -> list[Parameter]:
        joints = [(j.name, j.kind == "prismatic") for j in self.chain.joints]
        return self.layout.parameters(self.left_name, self.right_name, joints)

    @property
    def layout(self) -> ParamLayout:
        """Where each parameter sits in the vector (the one place that knows the offsets)."""
        return ParamLayout(self.chain.n)

    @property
    def size(self) -> int:
        return len(self.params)

    def split(self, x: Array) -> Split:
        """`x` by meaning: frames, per-joint origins, offsets, gain errors (views into `x`)."""
        return self.layout.split(x)

    def indices(self, families: Sequence[Family]) -> list[int]:
        """Candidate parameters: both frames always, plus the chosen kinematic families."""
        kinds = {ParamKind.FRAME} | {f.kind for f in families}
        return [i for i, p in enumerate(self.params) if p.kind in kinds]

    # -- evaluation ------------------------------------------------------------------------------

    def frames(self, x: Array) -> tuple[Array, Array]:
        parts = self.split(x)
        return self.L0 @ se3.delta(parts.left), self.R0 @ se3.delta(parts.right)

    def joint_terms(self, x: Array) -> tuple[Array, Array, Array]:
        """Per joint: corrected origins (n,4,4), zero offsets (n,), gains (n,)."""
        parts = self.split(x)
        origins = np.stack([j.origin @ se3.delta(parts.origin[i]) for i, j in enumerate(self.chain.joints)])
        return origins, parts.offset, 1.0 + parts.gain_error

    def flange(self, x: Array, Q: Array) -> Array:
        """bMf for every row of Q (N,n): (N,4,4)."""
        origins, offsets, gains = self.joint_terms(x)
        N = Q.shape[0]
        T = np.broadcast_to(np.eye(4), (N, 4, 4)).copy()
        for i, j in enumerate(self.chain.joints):
            value = gains[i] * Q[:, i] + offsets[i]
            M = np.broadcast_to(np.eye(4), (N, 4, 4)).copy()
            if j.kind == "prismatic":
                M[:, :3, 3] = value[:, None] * j.axis
            else:
                M[:, :3, :3] = axis_angle_batch(j.axis, value)
            T = T @ origins[i] @ M
        out: Array = T @ self.chain.tip_offset
        return out

    def tag_in_camera(self, x: Array, Q: Array) -> Array:
        """cMt for every row of Q: (N,4,4)."""
        L, R = self.frames(x)
        F = self.flange(x, Q)
        if self.setup is Setup.EYE_IN_HAND:
            F = se3.inv(F)
        out: Array = L @ F @ R
        return out

    def corners_in_camera(self, x: Array, Q: Array, tag_points: Array) -> Array:
        """Tag corners in the camera frame: (N,4,3)."""
        C = self.tag_in_camera(x, Q)
        out: Array = np.einsum("nij,kj->nki", C[:, :3, :3], tag_points) + C[:, None, :3, 3]
        return out

    def with_frames(self, L0: Array, R0: Array) -> CalibModel:
        return CalibModel(self.chain, self.setup, L0, R0, self.params)
