"""Rows become poses exactly as their stated conventions say, and every other reading is enumerated."""

from __future__ import annotations

import math

import numpy as np
import pytest

from armtool.calib.inputs.conventions import (
    RPY_ORDERS,
    AngleUnit,
    LengthUnit,
    PointConvention,
    PoseConvention,
    PoseFrame,
    QuaternionOrder,
    RotationForm,
)
from armtool.calib.model import se3
from armtool.model.chain import rpy_matrix

ROLL, PITCH, YAW = 0.3, -0.4, 1.1
T_TARGET_IN_SENSOR = se3.make(rpy_matrix(ROLL, PITCH, YAW), np.array([0.1, -0.2, 0.5]))


def _row(position: list[float], rotation: list[float]) -> np.ndarray:
    return np.array([[*position, *rotation]], dtype=float)


def test_urdf_rpy_is_the_zyx_product() -> None:
    c = PoseConvention(
        PoseFrame.TARGET_IN_SENSOR, LengthUnit.M, RotationForm.RPY, rpy_order="zyx", angle_units=AngleUnit.RAD
    )
    T = c.poses(_row([0.1, -0.2, 0.5], [ROLL, PITCH, YAW]))[0]
    assert np.allclose(T, T_TARGET_IN_SENSOR, atol=1e-12)


def test_the_xyz_product_is_another_rotation() -> None:
    c = PoseConvention(
        PoseFrame.TARGET_IN_SENSOR, LengthUnit.M, RotationForm.RPY, rpy_order="xyz", angle_units=AngleUnit.DEG
    )
    R = c.poses(_row([0, 0, 0], [math.degrees(ROLL), math.degrees(PITCH), math.degrees(YAW)]))[0][:3, :3]
    expected = se3.exp3(np.array([ROLL, 0, 0])) @ se3.exp3(np.array([0, PITCH, 0])) @ se3.exp3(np.array([0, 0, YAW]))
    assert np.allclose(R, expected, atol=1e-12)
    assert not np.allclose(R, T_TARGET_IN_SENSOR[:3, :3], atol=1e-3)


@pytest.mark.parametrize("order", list(QuaternionOrder))
def test_quaternions_in_either_declared_order(order: QuaternionOrder) -> None:
    axis = np.array([1.0, 2.0, -2.0]) / 3.0
    angle = 0.7
    w, xyz = math.cos(angle / 2), axis * math.sin(angle / 2)
    q = [w, *xyz] if order is QuaternionOrder.WXYZ else [*xyz, w]
    c = PoseConvention(PoseFrame.TARGET_IN_SENSOR, LengthUnit.MM, RotationForm.QUATERNION, quaternion_order=order)
    T = c.poses(_row([100.0, -200.0, 500.0], q))[0]
    assert np.allclose(T[:3, :3], se3.exp3(axis * angle), atol=1e-12)
    assert np.allclose(T[:3, 3], [0.1, -0.2, 0.5])


def test_a_rotation_vector_and_the_inverse_frame() -> None:
    r = np.array([0.2, -0.1, 0.4])
    c = PoseConvention(
        PoseFrame.SENSOR_IN_TARGET, LengthUnit.M, RotationForm.ROTATION_VECTOR, angle_units=AngleUnit.RAD
    )
    T = c.poses(_row([0.3, 0.0, 0.2], list(r)))[0]  # stored: the sensor in the target
    assert np.allclose(se3.inv(T), se3.make(se3.exp3(r), np.array([0.3, 0.0, 0.2])), atol=1e-12)


def test_a_matrix_is_read_row_by_row_and_rounding_is_projected_away() -> None:
    R = T_TARGET_IN_SENSOR[:3, :3] + 1e-5  # six printed digits
    c = PoseConvention(PoseFrame.TARGET_IN_SENSOR, LengthUnit.M, RotationForm.MATRIX)
    values = _row([0, 0, 0], list(R.ravel()))
    assert c.row_problem(values[0]) is None
    out = c.poses(values)[0][:3, :3]
    assert np.allclose(out @ out.T, np.eye(3), atol=1e-12) and np.allclose(out, R, atol=1e-4)


def test_rows_that_are_no_rotation_are_named() -> None:
    matrix = PoseConvention(PoseFrame.TARGET_IN_SENSOR, LengthUnit.M, RotationForm.MATRIX)
    why = matrix.row_problem(_row([0, 0, 0], [1, 0, 0, 0, 1, 0, 0, 0, -1])[0])  # a reflection
    assert why is not None and "det -1" in why
    quaternion = PoseConvention(
        PoseFrame.TARGET_IN_SENSOR, LengthUnit.M, RotationForm.QUATERNION, quaternion_order=QuaternionOrder.XYZW
    )
    why = quaternion.row_problem(_row([0, 0, 0], [0.5, 0.5, 0.5, 0.9])[0])
    assert why is not None and "norm is 1.2" in why


def test_alternatives_cover_every_single_and_double_mistake() -> None:
    c = PoseConvention(
        PoseFrame.SENSOR_IN_TARGET, LengthUnit.M, RotationForm.RPY, rpy_order="zyx", angle_units=AngleUnit.RAD
    )
    alternatives = c.alternatives()
    assert c not in alternatives
    assert len(alternatives) == 2 * 2 * len(RPY_ORDERS) * 2 - 1
    inverted_in_mm = next(
        a
        for a in alternatives
        if a.frame is PoseFrame.TARGET_IN_SENSOR
        and a.position_units is LengthUnit.MM
        and a.rpy_order == "zyx"
        and a.angle_units is AngleUnit.RAD
    )
    assert c.differences(inverted_in_mm) == ["observations.pose: target_in_sensor", "observations.position_units: mm"]


def test_a_transposed_matrix_is_fixed_by_listing_the_columns_by_column() -> None:
    c = PoseConvention(PoseFrame.TARGET_IN_SENSOR, LengthUnit.M, RotationForm.MATRIX)
    transposed = next(
        a for a in c.alternatives() if a.transposed and a.frame is c.frame and a.position_units is c.position_units
    )
    (line,) = c.differences(transposed)
    assert line.startswith("observations.rotation_columns: [r00, r10, r20, r01, r11, r21, r02, r12, r22]")


def test_points_have_only_the_unit_to_get_wrong() -> None:
    c = PointConvention(LengthUnit.MM)
    assert np.allclose(c.points(np.array([[1000.0, 0.0, -500.0]])), [[1.0, 0.0, -0.5]])
    assert [a.position_units for a in c.alternatives()] == [LengthUnit.M]
