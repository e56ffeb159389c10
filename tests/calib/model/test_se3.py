"""Exponential map, inverse and URDF rpy round trips."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from armtool.calib.model import se3
from armtool.model.chain import rpy_matrix

vec = st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3)


@settings(max_examples=200, deadline=None)
@given(vec)
def test_log3_inverts_exp3(r: list[float]) -> None:
    r = np.array(r)
    if np.linalg.norm(r) >= math.pi - 1e-3:  # the log returns the equivalent vector of angle < π
        r = r / np.linalg.norm(r) * (math.pi - 1e-3)
    R = se3.exp3(r)
    assert np.allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert np.allclose(se3.log3(R), r, atol=1e-7)


def test_log3_near_pi_keeps_the_axis() -> None:
    axis = np.array([1.0, 2.0, -2.0]) / 3.0
    R = se3.exp3(axis * (math.pi - 1e-6))
    assert np.allclose(se3.exp3(se3.log3(R)), R, atol=1e-6)


@settings(max_examples=200, deadline=None)
@given(st.floats(-3.1, 3.1), st.floats(-1.5, 1.5), st.floats(-3.1, 3.1))
def test_rpy_round_trip(roll: float, pitch: float, yaw: float) -> None:
    R = rpy_matrix(roll, pitch, yaw)
    assert np.allclose(rpy_matrix(*se3.rpy_of(R)), R, atol=1e-9)


def test_inverse_of_many() -> None:
    rng = np.random.default_rng(0)
    Ts = np.stack([se3.delta(rng.normal(size=6)) for _ in range(5)])
    assert np.allclose(se3.inv(Ts) @ Ts, np.eye(4), atol=1e-12)


def test_batched_maps_equal_the_single_ones() -> None:
    rng = np.random.default_rng(1)
    r = rng.normal(size=(4, 5, 3))
    r[0, 0] = 0.0  # the identity
    r[0, 1] = [1e-9, 0.0, 0.0]  # below the small-angle switch
    r[0, 2] = [0.0, 0.0, math.pi - 1e-7]  # near π: the axis comes from the symmetric part
    r[1] *= 3.0 / np.linalg.norm(r[1], axis=-1, keepdims=True)  # large angles, below π
    R = se3.exp3_batch(r)
    for idx in np.ndindex(4, 5):
        assert np.allclose(R[idx], se3.exp3(r[idx]), atol=1e-12)
        assert np.allclose(se3.log3_batch(R)[idx], se3.log3(R[idx]), atol=1e-9)
    v = rng.normal(size=(3, 6))
    assert np.allclose(se3.delta_batch(v), np.stack([se3.delta(row) for row in v]), atol=1e-12)
