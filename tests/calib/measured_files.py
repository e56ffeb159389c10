"""Write a measured-pose or -point dataset as a user would: joints.csv, a CSV of measurements in a
stated convention, and dataset.yaml's observations: section."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from armtool.calib.fit.measurements import PointMeasurements, PoseMeasurements
from armtool.calib.inputs.conventions import PoseFrame
from armtool.calib.model import se3
from armtool.model.chain import rpy_matrix
from tests.calib.conftest import CLEAN_ARM
from tests.calib.synthetic import Measured


def _rpy_zyx(R: np.ndarray) -> list[float]:
    return [float(v) for v in se3.rpy_of(R)]


def write_dataset(
    out: Path,
    m: Measured,
    rotation: str = "quaternion",
    frame: PoseFrame = PoseFrame.SENSOR_IN_TARGET,
    units: str = "mm",
    manifest: dict[str, Any] | None = None,
    urdf: Path = CLEAN_ARM,
) -> Path:
    """A dataset directory; the measurements in `frame`, `units` and `rotation` (quaternion wxyz,
    rpy zyx in degrees, or matrix), and dataset.yaml stating exactly that unless `manifest` overrides."""
    out.mkdir(parents=True, exist_ok=True)
    names = m.model.chain.joint_names
    lines = ["id," + ",".join(names)] + [s.id + "," + ",".join(repr(float(v)) for v in s.q) for s in m.samples]
    (out / "joints.csv").write_text("\n".join(lines) + "\n")
    scale = 1000.0 if units == "mm" else 1.0
    section: dict[str, Any] = {
        "kind": "point" if isinstance(m.measurements, PointMeasurements) else "pose",
        "position_units": units,
    }
    if isinstance(m.measurements, PointMeasurements):
        rows = ["id,x,y,z"] + [
            f"{sid},{','.join(repr(float(v) * scale) for v in p)}" for sid, p in m.measurements.points.items()
        ]
        section["file"] = "points.csv"
        (out / "points.csv").write_text("\n".join(rows) + "\n")
    else:
        assert isinstance(m.measurements, PoseMeasurements)
        section.update(
            {"file": "poses.csv", "pose": frame.value, "sensor": "camera", "target": "board", "rotation": rotation}
        )
        header = (
            "id,x,y,z,"
            + {"quaternion": "qw,qx,qy,qz", "rpy": "roll,pitch,yaw", "matrix": "r00,r01,r02,r10,r11,r12,r20,r21,r22"}[
                rotation
            ]
        )
        rows = [header]
        for sid, T in m.measurements.poses.items():  # target in sensor
            P = se3.inv(T) if frame is PoseFrame.SENSOR_IN_TARGET else T
            if rotation == "quaternion":
                angle_axis = se3.log3(P[:3, :3])
                angle = float(np.linalg.norm(angle_axis))
                axis = angle_axis / angle if angle > 0 else np.array([1.0, 0.0, 0.0])
                rot = [math.cos(angle / 2), *(axis * math.sin(angle / 2))]
                section["quaternion_order"] = "wxyz"
            elif rotation == "rpy":
                rot = [math.degrees(v) for v in _rpy_zyx(P[:3, :3])]
                assert np.allclose(rpy_matrix(*[math.radians(v) for v in rot]), P[:3, :3], atol=1e-9)
                section.update({"rpy_order": "zyx", "angle_units": "deg"})
            else:
                rot = list(P[:3, :3].ravel())
            rows.append(sid + "," + ",".join(repr(float(v)) for v in [*(P[:3, 3] * scale), *rot]))
        (out / "poses.csv").write_text("\n".join(rows) + "\n")
    section.update(manifest or {})
    doc = {
        "format": "armtool-calib-dataset/1",
        "setup": m.model.setup.value,
        "robot": {
            "urdf": str(urdf),
            "base_link": m.model.chain.base,
            "flange_link": m.model.chain.tip,
            "joints": names,
            "joint_units": "rad",
        },
        "samples": "joints.csv",
        "observations": section,
    }
    (out / "dataset.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    return out
