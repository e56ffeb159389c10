"""Principal moments of a 3x3 inertia tensor in pure Python (numpy would cost `lint` 100 ms of start-up)."""

from __future__ import annotations

import math
from typing import Any


_KEYS = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")


def principal_moments(ixx: float, iyy: float, izz: float, ixy: float, ixz: float, iyz: float) -> tuple[float, float, float]:
    """Eigenvalues of the symmetric tensor, ascending (closed form, trigonometric method)."""
    p1 = ixy * ixy + ixz * ixz + iyz * iyz
    if p1 == 0.0:
        return tuple(sorted((ixx, iyy, izz)))  # type: ignore[return-value]
    q = (ixx + iyy + izz) / 3.0
    p2 = (ixx - q) ** 2 + (iyy - q) ** 2 + (izz - q) ** 2 + 2.0 * p1
    p = math.sqrt(p2 / 6.0)
    b = [[(ixx - q) / p, ixy / p, ixz / p], [ixy / p, (iyy - q) / p, iyz / p], [ixz / p, iyz / p, (izz - q) / p]]
    det_b = (
        b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1])
        - b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0])
        + b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0])
    )
    r = max(-1.0, min(1.0, det_b / 2.0))
    phi = math.acos(r) / 3.0
    e_max = q + 2.0 * p * math.cos(phi)
    e_min = q + 2.0 * p * math.cos(phi + 2.0 * math.pi / 3.0)
    e_mid = 3.0 * q - e_max - e_min
    return tuple(sorted((e_min, e_mid, e_max)))  # type: ignore[return-value]


def read_inertia(el: Any) -> tuple[float, ...] | None:
    """(ixx, iyy, izz, ixy, ixz, iyz), or None when one is missing-but-malformed or not finite."""
    get = el.get
    try:
        values = tuple(float(get(key, "0")) for key in _KEYS)
    except ValueError:
        return None
    return values if all(map(math.isfinite, values)) else None
