"""Joint compliance under gravity: a joint yields to the torque that gravity puts on it.

    θ_j = q_j − g_j(q) / k_j

g(q) is the generalized gravity of the URDF's inertials (Pinocchio's `computeGeneralizedGravity`,
gravity along the URDF root's −z): the torque the joint must hold at the reading q, which its
elastic element (gearbox, belt, cable) carries by deflecting. On a real UR5 (laser tracker, 1000
grid poses) geometry + compliance gives the shoulder 37 ± 2 kN·m/rad and the elbow −33 ± 4. There
the elbow's sag moves the point by 0.116 mm RMS, all but 0.011 mm of it as a geometric error would,
and that rest stands in for a wrist-1 error periodic in its angle, which the grid ties to the
forearm's tilt (q2 + q3 + q4 = −4 ± 12°). With `harmonics` fitted too, neither sag is determined
(docs/calibrate.md, "Beyond geometry").

The parameter is the sag at the joint's largest gravity torque, `sag_j = τmax_j / k_j` in rad
(τmax_j: the largest |g_j| over the joint ranges, a property of the robot, not of the data), so
that it is an angle like every other term and its precision reads in degrees; the report gives
k_j = τmax_j / sag_j in kN·m/rad with its σ where the sag is determined (see `report`). A joint
that gravity never loads (a vertical axis) has a zero regressor: the identifiability analysis
drops it as changing no measurement. The tool's own mass is not in a URDF: a heavy end effector
not modelled there loads the joints more than g(q) says, and the fitted k comes out lower than
the joint's.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from armtool.calib.model.joint_term import RegressorCache
from armtool.calib.model.params import Family, ParamKind
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError
from armtool.model.chain import Chain

_SCALE_POSES = 200  # random joint vectors within the limits that find each joint's largest gravity torque
DETERMINED_SIGMAS = 2.0  # a sag this many σ from zero has a sign; within it, k = τmax/sag has no value


class Compliance:
    family = Family.COMPLIANCE
    kind = ParamKind.COMPLIANCE
    components: tuple[str, ...] = ("sag",)

    def __init__(self, chain: Chain, urdf_xml: str) -> None:
        import pinocchio as pin

        try:
            self._model = pin.buildModelFromXML(urdf_xml)
        except (RuntimeError, ValueError) as exc:
            raise ArmtoolError(
                f"--params compliance: Pinocchio cannot read the URDF's dynamics ({exc})",
                hint="run `armtool lint` on the URDF, or leave compliance out of --params",
            ) from None
        self._data = self._model.createData()
        self._pin = pin
        names = list(self._model.names)
        missing = [name for name in chain.joint_names if name not in names]
        if missing:
            raise ArmtoolError(
                f"--params compliance: joint(s) {', '.join(missing)} not in Pinocchio's model of the URDF"
            )
        joints = [self._model.joints[names.index(name)] for name in chain.joint_names]
        self._q_index = [(j.idx_q, j.nq) for j in joints]
        self._v_index = np.array([j.idx_v for j in joints])
        massless = [name for name, m in zip(chain.joint_names, self._moved_mass(names, chain)) if m <= 0.0]
        if len(massless) == chain.n:
            raise ArmtoolError(
                "--params compliance needs the URDF's <inertial> masses: no link after the chain's joints has one",
                hint="add the links' inertials (the arm maker's URDF has them), or leave compliance out of --params",
            )
        torques = np.abs(self.gravity(chain.random(np.random.default_rng(0), _SCALE_POSES)))
        largest = torques.max(axis=0)
        self.max_torque_nm: Array = largest
        self._scale = np.where(largest > 1e-9, largest, math.inf)  # never loaded: a zero regressor
        self._cache = RegressorCache()

    def _moved_mass(self, names: list[str], chain: Chain) -> list[float]:
        """Mass that each chain joint carries (its subtree's), from Pinocchio's model."""
        out = []
        for name in chain.joint_names:
            j = names.index(name)
            subtree = self._model.subtrees[j]
            out.append(float(sum(self._model.inertias[k].mass for k in subtree)))
        return out

    def gravity(self, Q: Array) -> Array:
        """g(q) of the chain's joints (N, n), N·m (N for a prismatic joint): the torque each must hold."""
        pin, model, data = self._pin, self._model, self._data
        q = pin.neutral(model)
        out = np.empty((len(Q), len(self._q_index)))
        for row, values in enumerate(Q):
            for (start, size), v in zip(self._q_index, values):
                if size == 2:  # a continuous joint: cos, sin
                    q[start], q[start + 1] = math.cos(v), math.sin(v)
                else:
                    q[start] = v
            out[row] = pin.computeGeneralizedGravity(model, data, q)[self._v_index]
        return out

    def regressors(self, Q: Array) -> Array:
        def compute(readings: Array) -> Array:
            out: Array = (-self.gravity(readings) / self._scale)[:, :, None]
            return out

        return self._cache.get(Q, compute)

    def report(self, j: int, values: Array, sigmas: Array) -> dict[str, Any]:
        """The sag at the largest gravity torque, its σ, and the stiffness it means (only when fitted).

        k = τmax / sag, so its σ by linear propagation (k·σ/sag) holds only while the sag is well
        away from zero. A sag within 2 σ of zero bounds k from below only, by the sag's upper
        bound: k ≥ τmax / (sag + 2σ); a value there would read as a stiffness the data do not
        give (the UR5 tracker grid with harmonics: an elbow sag of 0.13 ± 0.12 mrad, which the
        linear σ wrote as 123 ± 119 kN·m/rad, as if k could be 4)."""
        sag, torque = float(values[0]), float(self.max_torque_nm[j])
        sigma = float(sigmas[0]) if math.isfinite(float(sigmas[0])) else None
        entry: dict[str, Any] = {
            "gravity_sag_rad": sag,
            "sigma_gravity_sag_rad": sigma,
            "max_gravity_torque_nm": torque,
        }
        if sigma is None or torque <= 0.0:
            return entry
        if abs(sag) > DETERMINED_SIGMAS * sigma:
            k = torque / sag
            entry["stiffness_knm_per_rad"] = {"value": k / 1e3, "sigma": abs(k) * sigma / abs(sag) / 1e3}
        elif sag + DETERMINED_SIGMAS * sigma > 0.0:
            entry["stiffness_min_knm_per_rad"] = torque / (sag + DETERMINED_SIGMAS * sigma) / 1e3
        return entry
