"""The measurement model: which pixel each tag corner should land on, given joints and parameters.

Eye-to-hand (camera fixed, tag on the flange):  cMt = cMb · bMf(q) · fMt
Eye-in-hand (camera on the flange, tag fixed):   cMt = cMf · bMf(q)⁻¹ · bMt
Both are `cMt = L · F(q)^±1 · R` with two free "measurement frames" L and R, which also carry the
base and tool gauge (FIGAROH's metrology frames); they are fitted but never written to the URDF.

bMf(q) is the URDF chain with, per moving joint j, `origin_j · SE3(exp(r_j), t_j)` (6-D origin
correction), the reading turned into `gain_j · q_j + offset_j` (zero offset, optional gain),
plus the model's joint terms `Σ p_jc · f_jc(q)` (compliance under gravity, harmonics: see
`joint_term`). The parameter vector holds only corrections, so 0 is the nominal robot.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from armtool.calib.choices import Setup
from armtool.calib.model import se3
from armtool.calib.model.joint_term import JointTerm
from armtool.calib.model.params import Family, Parameter, ParamKind, ParamLayout, Split
from armtool.calib.model.se3 import Array
from armtool.model.chain import Chain, axis_angle_batch


@dataclass
class CalibModel:
    """Chain + setup + the layout of the full parameter vector (all candidates, free or not)."""

    chain: Chain
    setup: Setup
    L0: Array  # nominal left frame: cMb (eye-to-hand) or cMf (eye-in-hand)
    R0: Array  # nominal right frame: fMt (eye-to-hand) or bMt (eye-in-hand)
    params: list[Parameter] = field(default_factory=list)
    sensor: str = "camera"  # what measures (camera, tracker, ...): names the left frame's parameters
    target: str = "tag"  # what is measured (tag, board, point, ...): names the right frame's
    terms: tuple[JointTerm, ...] = ()  # joint terms beyond geometry, in the vector after the joints
    _last_chain: tuple[bytes, list[Array]] | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not self.params:
            self.params = self._layout()

    @property
    def left_name(self) -> str:
        return self.sensor if self.setup is Setup.EYE_TO_HAND else f"{self.sensor}_in_flange"

    @property
    def right_name(self) -> str:
        return self.target if self.setup is Setup.EYE_TO_HAND else f"{self.target}_in_base"

    def frame_names(self) -> tuple[str, str]:
        """The fitted placements as calibration.yaml and the hints name them: the sensor's pose
        (`camera_in_base`, `camera_in_flange`) and the target's (`tag_in_flange`, `tag_in_base`)."""
        if self.setup is Setup.EYE_TO_HAND:
            return f"{self.sensor}_in_base", f"{self.target}_in_flange"
        return f"{self.sensor}_in_flange", f"{self.target}_in_base"

    def base_side_frame(self) -> list[int]:
        """Indices of the frame fixed to the robot's base (the camera or tracker of eye-to-hand, the
        target of eye-in-hand): a registration of the whole arm into the measurements' frame."""
        frames = self.layout.frames
        half = len(frames) // 2
        return frames[:half] if self.setup is Setup.EYE_TO_HAND else frames[half:]

    def _layout(self) -> list[Parameter]:
        joints = [(j.name, j.kind == "prismatic") for j in self.chain.joints]
        terms = [(t.kind, t.components) for t in self.terms]
        return self.layout.parameters(self.left_name, self.right_name, joints, terms)

    @property
    def layout(self) -> ParamLayout:
        """Where each parameter sits in the vector (the one place that knows the offsets)."""
        return ParamLayout(self.chain.n, tuple(len(t.components) for t in self.terms))

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

    def angle_corrections(self, x: Array, Q: Array) -> Array:
        """(N, n) what the joint terms add to each joint's angle at the readings Q (zeros without terms)."""
        out = np.zeros(Q.shape)
        for term, p in zip(self.terms, self.split(x).terms):
            out += np.einsum("njc,jc->nj", term.regressors(Q), p)
        return out

    def mean_correction(self, x: Array, Q: Array) -> Array:
        """(n,) what the gains and joint terms add to each joint's reading, on average over the
        readings Q: moved into the zero offsets, a URDF read at the readings is the arm on average."""
        out: Array = (self.split(x).gain_error * Q + self.angle_corrections(x, Q)).mean(axis=0)
        return out

    def urdf_part(self, x: Array) -> Array:
        """x with what a URDF cannot hold (gains, joint terms) at nominal: the calibrated URDF's kinematics."""
        out: Array = x.copy()
        parts = self.split(out)
        parts.gain_error[:] = 0.0
        for p in parts.terms:
            p[:] = 0.0
        return out

    def flange(self, x: Array, Q: Array) -> Array:
        """bMf for every row of Q (N,n): (N,4,4)."""
        out: Array = self._chain(x, Q)[-1] @ self.chain.tip_offset
        return out

    def _chain(self, x: Array, Q: Array) -> list[Array]:
        """The chain for every row of Q: [i] up to joint i's origin (N, 4, 4), [n] to the last
        joint's motion. The last one is kept: a fit's step takes the residuals and then the
        Jacobian at the same point, and built twice the chain was a fifth of a plain fit's time."""
        key = b"".join([x.tobytes(), str(Q.shape).encode(), Q.tobytes()])
        if self._last_chain is not None and self._last_chain[0] == key:
            return self._last_chain[1]
        origins, offsets, gains = self.joint_terms(x)
        extra = self.angle_corrections(x, Q)
        prefix = [np.broadcast_to(np.eye(4), (Q.shape[0], 4, 4))]
        for i in range(self.chain.n):
            prefix.append(prefix[i] @ origins[i] @ self._motion(i, gains[i], offsets[i], Q[:, i], extra[:, i]))
        self._last_chain = (key, prefix)
        return prefix

    def tag_in_camera(self, x: Array, Q: Array) -> Array:
        """cMt for every row of Q: (N,4,4)."""
        L, R = self.frames(x)
        F = self.flange(x, Q)
        if self.setup is Setup.EYE_IN_HAND:
            F = se3.inv(F)
        out: Array = L @ F @ R
        return out

    def twists(self, x: Array, Q: Array, indices: Sequence[int]) -> tuple[Array, Array]:
        """cMt (N, 4, 4), and how each parameter moves it, as a twist on its left: (N, 6, len(indices)),
        per unit of the parameter, (v, ω) as `se3.delta` orders them: cMt(x + dx·e_i) ≈ exp(dx·ε̂_i) · cMt(x).

        Why: every measurement depends on the parameters only through cMt, so the fit's Jacobian
        is (residuals per left twist of cMt, 6 columns by central differences) × these twists:
        its cost barely grows with the number of parameters. Each parameter's twist is its
        factor's derivative carried to the left of the chain by the adjoint of what precedes it.
        """
        return self._twists(x, Q, indices, of_flange=False)

    def flange_twists(self, x: Array, Q: Array, indices: Sequence[int]) -> tuple[Array, Array]:
        """bMf (N, 4, 4), and how each parameter moves it, as a twist on its left (N, 6, len(indices)),
        as `twists` gives them for cMt: the frames' columns are zero (they do not move the flange)."""
        return self._twists(x, Q, indices, of_flange=True)

    def _twists(self, x: Array, Q: Array, indices: Sequence[int], of_flange: bool) -> tuple[Array, Array]:
        layout, parts = self.layout, self.split(x)
        n, N = self.chain.n, Q.shape[0]
        wanted = np.asarray(indices, dtype=np.intp)
        origins = self.joint_terms(x)[0]
        prefix = self._chain(x, Q)  # prefix[i]: the chain up to joint i's origin
        F = prefix[n] @ self.chain.tip_offset
        L, R = self.frames(x)
        if of_flange:
            C, to_c = F, np.broadcast_to(np.eye(6), (N, 6, 6))
        elif self.setup is Setup.EYE_TO_HAND:
            C = L @ F @ R
            to_c = np.broadcast_to(_adjoint_matrix(L), (N, 6, 6))  # a left twist ψ on F is Ad_L ψ on C
        else:
            G = L @ se3.inv(F)
            C = G @ R
            to_c = -_adjoint_matrix(G)  # F⁻¹ turns a left twist ψ on F into −Ad_{L F⁻¹} ψ on C
        out = np.zeros((N, 6, len(wanted)))
        term_regressors = [t.regressors(Q) for t in self.terms]
        frame = layout.FRAME_SIZE
        cols = np.flatnonzero(wanted < frame)
        if cols.size and not of_flange:
            xi = _right_derivatives(parts.left, wanted[cols])  # δ(l)⁻¹ ∂δ(l)/∂l_k, so ε = Ad_L ξ
            out[:, :, cols] = (_adjoint_matrix(L) @ xi)[None]
        cols = np.flatnonzero((wanted >= frame) & (wanted < 2 * frame))
        if cols.size and not of_flange:
            xi = _right_derivatives(parts.right, wanted[cols] - frame)  # a right twist on C
            out[:, :, cols] = _adjoint_matrix(C) @ xi
        for i, j in enumerate(self.chain.joints):
            start = 2 * frame + layout.PER_JOINT * i
            cols = np.flatnonzero((wanted >= start) & (wanted < start + layout.PER_JOINT))
            term_cols = [np.flatnonzero(np.isin(wanted, layout.term(k, i))) for k in range(len(self.terms))]
            if cols.size == 0 and not any(c.size for c in term_cols):
                continue
            unit = np.concatenate([j.axis, np.zeros(3)] if j.kind == "prismatic" else [np.zeros(3), j.axis])
            moved = _adjoint_matrix(prefix[i + 1]) @ unit  # (N, 6): the joint's own motion, per radian
            for k, found in enumerate(term_cols):  # a joint term turns the joint by its regressor per unit
                if found.size:
                    f = term_regressors[k][:, i, wanted[found] - layout.term(k, i)[0]]  # (N, c)
                    out[:, :, found] = to_c @ (moved[:, :, None] * f[:, None, :])
            if cols.size == 0:
                continue
            components = wanted[cols] - start
            psi = np.zeros((N, 6, cols.size))
            origin_cols = components < 6
            if origin_cols.any():
                xi = _right_derivatives(parts.origin[i], components[origin_cols])
                psi[:, :, origin_cols] = _adjoint_matrix(prefix[i] @ origins[i]) @ xi
            for c in np.flatnonzero(~origin_cols):  # the offset, or the gain (θ moves by q per unit of gain)
                psi[:, :, c] = moved * (Q[:, i, None] if components[c] == 7 else 1.0)
            out[:, :, cols] = to_c @ psi
        return C, out

    def _motion(self, i: int, gain: float, offset: float, q: Array, extra: Array) -> Array:
        """Joint i's motion transforms for the readings q, with the joint terms' `extra` angle: (N, 4, 4)."""
        j = self.chain.joints[i]
        value = gain * q + offset + extra
        M = np.broadcast_to(np.eye(4), (len(q), 4, 4)).copy()
        if j.kind == "prismatic":
            M[:, :3, 3] = value[:, None] * j.axis
        else:
            M[:, :3, :3] = axis_angle_batch(j.axis, value)
        out: Array = M
        return out

    def corners_in_camera(self, x: Array, Q: Array, tag_points: Array) -> Array:
        """Tag corners in the camera frame: (N,4,3)."""
        C = self.tag_in_camera(x, Q)
        out: Array = np.einsum("nij,kj->nki", C[:, :3, :3], tag_points) + C[:, None, :3, 3]
        return out

    def with_frames(self, L0: Array, R0: Array) -> CalibModel:
        return CalibModel(self.chain, self.setup, L0, R0, self.params, self.sensor, self.target, self.terms)


def _right_derivatives(v: Array, components: NDArray[np.intp]) -> Array:
    """δ(v)⁻¹ ∂δ(v)/∂v_k as twists (6, len(components)): how a correction's component moves the
    frame, seen from the frame itself. δ(v) = SE3(exp(ω), t): a translation component moves it by
    Rᵀ e_k, a rotation component turns it by J_r(ω) e_k (the right Jacobian of SO(3))."""
    R = se3.exp3(v[3:6])
    w = v[3:6]
    angle = float(np.linalg.norm(w))
    K = se3.skew(w)
    if angle < 1e-6:
        Jr = np.eye(3) - 0.5 * K + (K @ K) / 6.0
    else:
        Jr = np.eye(3) - (1.0 - math.cos(angle)) / angle**2 * K + (angle - math.sin(angle)) / angle**3 * (K @ K)
    full = np.zeros((6, 6))
    full[:3, :3] = R.T
    full[3:, 3:] = Jr
    out: Array = full[:, components]
    return out


def _adjoint_matrix(T: Array) -> Array:
    """Ad_T (..., 6, 6) of one or many transforms: (v, ω) ↦ (R v + p × R ω, R ω)."""
    R, p = T[..., :3, :3], T[..., :3, 3]
    P = np.zeros((*p.shape[:-1], 3, 3))
    P[..., 0, 1], P[..., 0, 2], P[..., 1, 2] = -p[..., 2], p[..., 1], -p[..., 0]
    P[..., 1, 0], P[..., 2, 0], P[..., 2, 1] = p[..., 2], -p[..., 1], p[..., 0]
    out = np.zeros((*R.shape[:-2], 6, 6))
    out[..., :3, :3] = R
    out[..., :3, 3:] = P @ R
    out[..., 3:, 3:] = R
    return out
