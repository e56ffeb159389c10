"""Principal moments of a 3x3 inertia tensor in pure Python (numpy would cost `lint` 100 ms of start-up)."""

from __future__ import annotations

import math
from typing import Any

_KEYS = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")


def principal_moments(
    ixx: float, iyy: float, izz: float, ixy: float, ixz: float, iyz: float
) -> tuple[float, float, float]:
    """Eigenvalues of the symmetric tensor, ascending (closed form, trigonometric method)."""
    p1 = ixy * ixy + ixz * ixz + iyz * iyz
    if p1 == 0.0:
        return tuple(sorted((ixx, iyy, izz)))  # type: ignore[return-value]
    q = (ixx + iyy + izz) / 3.0
    p2 = (ixx - q) ** 2 + (iyy - q) ** 2 + (izz - q) ** 2 + 2.0 * p1
    p = math.sqrt(p2 / 6.0)
    # B = (A - qI) / p, element by element (scalars, not a nested list: this runs for every link).
    b00, b01, b02 = (ixx - q) / p, ixy / p, ixz / p
    b11, b12 = (iyy - q) / p, iyz / p
    b22 = (izz - q) / p
    det_b = b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02)
    r = max(-1.0, min(1.0, det_b / 2.0))
    phi = math.acos(r) / 3.0
    e_max = q + 2.0 * p * math.cos(phi)
    e_min = q + 2.0 * p * math.cos(phi + 2.0 * math.pi / 3.0)
    e_mid = 3.0 * q - e_max - e_min
    return tuple(sorted((e_min, e_mid, e_max)))  # type: ignore[return-value]


_ZEROS = ("0",) * len(_KEYS)


def read_inertia(el: Any) -> tuple[float, ...] | None:
    """(ixx, iyy, izz, ixy, ixz, iyz), or None when one is missing-but-malformed or not finite."""
    try:
        values = tuple(map(float, map(el.get, _KEYS, _ZEROS)))
    except ValueError:
        return None
    return values if all(map(math.isfinite, values)) else None
