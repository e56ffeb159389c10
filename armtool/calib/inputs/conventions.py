"""How a file states a measured pose or point, and turning its rows into poses and points.

Pose conventions differ between labs and are rarely written down: camera-in-board or
board-in-camera, quaternions xyzw or wxyz, roll-pitch-yaw multiplied in one order or another,
millimetres or metres. A dataset states each one (`observations:` in dataset.yaml) and nothing is
guessed; `alternatives` lists the readings that a mistake in one or more of them would have been
(what `convention_check` tries when the residual is implausible).

Rotations are built with plain matrices so that the order is visible: `rpy_order: zyx` is the
product R = Rz(yaw)·Ry(pitch)·Rx(roll) (URDF, ROS tf, Pinocchio, UFactory's xArm manual), `xyz`
is R = Rx(roll)·Ry(pitch)·Rz(yaw). Roll, pitch and yaw always turn about x, y and z.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, replace
from enum import Enum

import numpy as np

from armtool.calib.model.se3 import Array


class PoseFrame(str, Enum):
    """Which pose each row holds."""

    SENSOR_IN_TARGET = "sensor_in_target"  # the sensor's pose in the target frame (camera in board)
    TARGET_IN_SENSOR = "target_in_sensor"  # the target's pose in the sensor frame (board in camera, a tracker's body)

    @property
    def other(self) -> PoseFrame:
        return PoseFrame.TARGET_IN_SENSOR if self is PoseFrame.SENSOR_IN_TARGET else PoseFrame.SENSOR_IN_TARGET


class LengthUnit(str, Enum):
    M = "m"
    MM = "mm"

    @property
    def metres(self) -> float:
        return 1.0 if self is LengthUnit.M else 1e-3


class AngleUnit(str, Enum):
    RAD = "rad"
    DEG = "deg"

    @property
    def radians(self) -> float:
        return 1.0 if self is AngleUnit.RAD else math.pi / 180.0


class RotationForm(str, Enum):
    MATRIX = "matrix"  # nine elements, row by row
    QUATERNION = "quaternion"  # with quaternion_order
    RPY = "rpy"  # roll, pitch, yaw about x, y, z, with rpy_order and angle_units
    ROTATION_VECTOR = "rotation_vector"  # axis × angle (UR's rx ry rz), with angle_units


class QuaternionOrder(str, Enum):
    XYZW = "xyzw"  # ROS, Eigen's coeffs(), SciPy
    WXYZ = "wxyz"  # Eigen's constructor, MATLAB, ABB (Pinocchio's XYZQUAT is xyzw)


RPY_ORDERS = ("zyx", "xyz", "zxy", "yxz", "yzx", "xzy")  # the product's axes, left to right

DEFAULT_POSITION_COLUMNS = ("x", "y", "z")
MATRIX_COLUMNS = ("r00", "r01", "r02", "r10", "r11", "r12", "r20", "r21", "r22")


def default_rotation_columns(form: RotationForm, order: QuaternionOrder | None) -> tuple[str, ...]:
    """The rotation's column names when the dataset does not list them."""
    if form is RotationForm.MATRIX:
        return MATRIX_COLUMNS
    if form is RotationForm.QUATERNION:
        return ("qw", "qx", "qy", "qz") if order is QuaternionOrder.WXYZ else ("qx", "qy", "qz", "qw")
    if form is RotationForm.RPY:
        return ("roll", "pitch", "yaw")
    return ("rx", "ry", "rz")


ROTATION_SIZE = {
    RotationForm.MATRIX: 9,
    RotationForm.QUATERNION: 4,
    RotationForm.RPY: 3,
    RotationForm.ROTATION_VECTOR: 3,
}

MATRIX_TOLERANCE = 1e-3  # |RᵀR − I| and |‖q‖ − 1| beyond this is not rounding: another column or a scale


def _axis_rotation(axis: str, angles: Array) -> Array:
    """Rotations (N, 3, 3) about x, y or z."""
    c, s = np.cos(angles), np.sin(angles)
    R = np.zeros((len(angles), 3, 3))
    i = "xyz".index(axis)
    j, k = (i + 1) % 3, (i + 2) % 3
    R[:, i, i] = 1.0
    R[:, j, j], R[:, k, k] = c, c
    R[:, k, j], R[:, j, k] = s, -s
    return R


@dataclass(frozen=True)
class PoseConvention:
    """Everything needed to read a row of a pose file without guessing."""

    frame: PoseFrame
    position_units: LengthUnit
    rotation: RotationForm
    quaternion_order: QuaternionOrder | None = None
    rpy_order: str | None = None
    angle_units: AngleUnit | None = None
    position_columns: tuple[str, ...] = DEFAULT_POSITION_COLUMNS
    rotation_columns: tuple[str, ...] = MATRIX_COLUMNS
    transposed: bool = False  # the check's alternative for a matrix stored column by column
    columns_listed: bool = True  # the dataset listed rotation_columns (else: the defaults, named by meaning)

    @property
    def columns(self) -> tuple[str, ...]:
        return (*self.position_columns, *self.rotation_columns)

    def rotations(self, values: Array) -> Array:
        """Rotation matrices (N, 3, 3) of the rotation columns (N, k), not yet checked."""
        if self.rotation is RotationForm.MATRIX:
            R = values.reshape(-1, 3, 3)
            return np.swapaxes(R, -1, -2) if self.transposed else R
        if self.rotation is RotationForm.QUATERNION:
            q = values / np.linalg.norm(values, axis=1, keepdims=True)
            w, x, y, z = q.T if self.quaternion_order is QuaternionOrder.WXYZ else q[:, [3, 0, 1, 2]].T
            return np.stack(
                [
                    np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
                    np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
                    np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
                ],
                axis=1,
            )
        angles = values * (self.angle_units or AngleUnit.RAD).radians
        if self.rotation is RotationForm.ROTATION_VECTOR:
            from armtool.calib.model.se3 import exp3_batch

            return exp3_batch(angles)
        order = self.rpy_order or "zyx"
        R = np.broadcast_to(np.eye(3), (len(values), 3, 3))
        for axis in order:  # the product left to right: R = R_a(.) R_b(.) R_c(.)
            R = R @ _axis_rotation(axis, angles[:, "xyz".index(axis)])
        return R

    def row_problem(self, values: Array) -> str | None:
        """Why one row's rotation is not a rotation, or None."""
        rot = values[len(self.position_columns) :]
        if self.rotation is RotationForm.QUATERNION:
            norm = float(np.linalg.norm(rot))
            if abs(norm - 1.0) > MATRIX_TOLERANCE:
                return f"the quaternion's norm is {norm:.4g}, not 1: are these the quaternion's columns?"
        if self.rotation is RotationForm.MATRIX:
            R = rot.reshape(3, 3)
            off = float(np.abs(R.T @ R - np.eye(3)).max())
            if off > MATRIX_TOLERANCE or np.linalg.det(R) < 0:
                return (
                    f"the rotation is not a rotation matrix (RᵀR differs from I by {off:.3g}, det {np.linalg.det(R):.3g}): "
                    "are these its nine elements, row by row?"
                )
        return None

    def poses(self, values: Array) -> Array:
        """Target-in-sensor poses (N, 4, 4), in metres, of checked rows (N, 3 + k)."""
        R = self.rotations(values[:, 3:])
        U, _s, Vt = np.linalg.svd(R)  # the nearest rotation: files round their elements
        R = U @ Vt
        T = np.broadcast_to(np.eye(4), (len(values), 4, 4)).copy()
        T[:, :3, :3] = R
        T[:, :3, 3] = values[:, :3] * self.position_units.metres
        if self.frame is PoseFrame.SENSOR_IN_TARGET:
            from armtool.calib.model.se3 import inv

            T = inv(T)
        out: Array = T
        return out

    def differences(self, other: PoseConvention) -> list[str]:
        """The dataset.yaml lines that turn this convention into `other`."""
        out = []
        if other.frame is not self.frame:
            out.append(f"observations.pose: {other.frame.value}")
        if other.position_units is not self.position_units:
            out.append(f"observations.position_units: {other.position_units.value}")
        if other.quaternion_order is not self.quaternion_order and other.quaternion_order is not None:
            out.append(f"observations.quaternion_order: {other.quaternion_order.value}")
            if not self.columns_listed:  # default columns follow the order: name the file's columns to keep them
                out.append(
                    f"observations.rotation_columns: [{', '.join(self.rotation_columns)}] (they hold {other.quaternion_order.value})"
                )
        if other.rpy_order != self.rpy_order and other.rpy_order is not None:
            out.append(f"observations.rpy_order: {other.rpy_order}")
        if other.angle_units is not self.angle_units and other.angle_units is not None:
            out.append(f"observations.angle_units: {other.angle_units.value}")
        if other.transposed != self.transposed:
            by_column = [self.rotation_columns[3 * c + r] for r in range(3) for c in range(3)]
            out.append(
                f"observations.rotation_columns: [{', '.join(by_column)}] (the matrix is stored column by column)"
            )
        return out

    def alternatives(self) -> list[PoseConvention]:
        """Every other reading of the same columns: the frame inverted, the other length unit, the
        other quaternion order, another rpy order or angle unit, a transposed matrix; and their
        combinations (two mistakes at once are common: a camera-in-board file in millimetres)."""
        rotations: list[PoseConvention] = []
        if self.rotation is RotationForm.MATRIX:
            rotations = [replace(self, transposed=t) for t in (False, True)]
        elif self.rotation is RotationForm.QUATERNION:
            rotations = [replace(self, quaternion_order=o) for o in QuaternionOrder]
        elif self.rotation is RotationForm.RPY:
            rotations = [replace(self, rpy_order=o, angle_units=u) for o in RPY_ORDERS for u in AngleUnit]
        else:
            rotations = [replace(self, angle_units=u) for u in AngleUnit]
        out = [replace(r, frame=f, position_units=u) for r, f, u in itertools.product(rotations, PoseFrame, LengthUnit)]
        return [c for c in out if c != self]


@dataclass(frozen=True)
class PointConvention:
    """How a file states a measured point: its columns and their unit."""

    position_units: LengthUnit
    position_columns: tuple[str, ...] = DEFAULT_POSITION_COLUMNS

    @property
    def columns(self) -> tuple[str, ...]:
        return self.position_columns

    def row_problem(self, values: Array) -> str | None:
        return None

    def points(self, values: Array) -> Array:
        """Points (N, 3) in metres."""
        out: Array = values[:, :3] * self.position_units.metres
        return out

    def differences(self, other: PointConvention) -> list[str]:
        if other.position_units is not self.position_units:
            return [f"observations.position_units: {other.position_units.value}"]
        return []

    def alternatives(self) -> list[PointConvention]:
        return [replace(self, position_units=u) for u in LengthUnit if u is not self.position_units]
