"""A joint term: a correction of a joint's angle that depends on where the arm is, linear in its
parameters: θ_j = gain_j·q_j + offset_j + Σ_c p_jc · f_jc(q).

Why one shape for all: the measurement model turns the joint by θ_j, so every such term moves a
measurement through the joint's own axis, as a zero offset does, scaled by its regressor
f_jc(q); `CalibModel.twists` gives the Jacobian of any of them from that alone. Geometry that a
URDF holds (origins, zero offsets) is not a joint term. The kinds (one module each) are in
`calib/model/terms/`, registered in `terms/registry.py`; each parameter is in rad of joint angle,
so the identifiability's precision rule reads them as it reads a rotation.
"""

from __future__ import annotations

import hashlib
from typing import Any, Protocol

from armtool.calib.model.params import Family, ParamKind
from armtool.calib.model.se3 import Array


class JointTerm(Protocol):
    family: Family  # the --params family that frees it
    kind: ParamKind
    components: tuple[str, ...]  # its parameters per joint, e.g. ("sag",) or ("sin1", "cos1", …)

    def regressors(self, Q: Array) -> Array:
        """(N, n, len(components)): each joint's angle change (rad) per unit of each parameter, at the readings Q (N, n)."""
        ...

    def report(self, j: int, values: Array, sigmas: Array) -> dict[str, Any]:
        """calibration.yaml's entries for joint j's parameters (a σ is NaN when it was not fitted)."""
        ...


class RegressorCache:
    """The regressors of the last few joint-reading arrays: a fit evaluates the same samples'
    readings thousands of times, and some regressors (gravity torques) cost a dynamics pass."""

    def __init__(self, size: int = 32) -> None:
        self._size = size
        self._values: dict[bytes, Array] = {}

    def get(self, Q: Array, compute: Any) -> Array:
        key = hashlib.blake2b(Q.tobytes(), digest_size=16, person=str(Q.shape).encode()[:16]).digest()
        found = self._values.get(key)
        if found is None:
            found = compute(Q)
            if len(self._values) >= self._size:
                self._values.pop(next(iter(self._values)))
            self._values[key] = found
        return found
