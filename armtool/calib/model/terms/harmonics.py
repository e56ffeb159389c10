"""Joint errors periodic in the joint angle: once and twice per turn.

    θ_j = q_j + a1·sin q_j + b1·cos q_j + a2·sin 2q_j + b2·cos 2q_j

Why: an encoder or gear mounted off-centre (once per turn), an elliptical bearing or cable drum
(twice per turn) and a cable that winds onto a pulley (Barrett WAM) turn the joint by an error
that repeats with the joint angle and that no origin, offset or gain can hold. Low orders only:
each amplitude is one parameter in rad, and the k-fold choice and the identifiability analysis
keep the ones the poses determine (over a joint range much below a turn, cos q barely differs
from a constant, and the analysis drops it against the zero offset). A prismatic joint has none.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from armtool.calib.model.params import Family, ParamKind
from armtool.calib.model.se3 import Array
from armtool.model.chain import Chain


class Harmonics:
    family = Family.HARMONICS
    kind = ParamKind.HARMONIC
    components: tuple[str, ...] = ("sin1", "cos1", "sin2", "cos2")

    def __init__(self, chain: Chain) -> None:
        self._revolute = chain.revolute.astype(float)

    def regressors(self, Q: Array) -> Array:
        out = np.stack([np.sin(Q), np.cos(Q), np.sin(2 * Q), np.cos(2 * Q)], axis=-1)
        result: Array = out * self._revolute[None, :, None]
        return result

    def report(self, j: int, values: Array, sigmas: Array) -> dict[str, Any]:
        """Each amplitude in degrees, with its σ (None: not fitted)."""
        return {
            "harmonics_deg": {c: math.degrees(float(v)) for c, v in zip(self.components, values)},
            "sigma_harmonics_deg": {
                c: math.degrees(float(s)) if math.isfinite(float(s)) else None for c, s in zip(self.components, sigmas)
            },
        }
