"""Record each joint's real range (`armtool limits`): `request` (the options checked before the
bus opens), `record` (the run, from bus to written files), `arm_file` (the arm description and
`JointRange`), `manual` (by hand, torque off), `auto` (a torque-limited seek to each stop),
`document` (ticks to radians, the limits YAML), `lerobot_files` (LeRobot calibration files),
`urdf` (recorded limits into a URDF's text) and `choices` (`Mode`, numpy-free).
The command and the tests use the names below; each lives in one of those modules."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from armtool.servo.limits.arm_file import ArmFile, Joint, JointRange, load_arm, parse_ids
    from armtool.servo.limits.auto import RANGE_END, AutoParams, Progress, seek_joint
    from armtool.servo.limits.document import LIMITS_VERSION, SCHEMA, convert, dump_yaml, limits_document, write_atomic
    from armtool.servo.limits.manual import ManualRecorder
    from armtool.servo.limits.urdf import UrdfJoint, check_urdf_names, patch_urdf, urdf_joints

# Loaded on first use: `armtool --help` and `armtool lint` import `servo.limits.choices`, and this
# package's modules would otherwise come with it (the bus, models, motion: ~60 ms of start-up).
_WHERE = {
    "ArmFile": "arm_file",
    "Joint": "arm_file",
    "JointRange": "arm_file",
    "load_arm": "arm_file",
    "parse_ids": "arm_file",
    "RANGE_END": "auto",
    "AutoParams": "auto",
    "Progress": "auto",
    "seek_joint": "auto",
    "LIMITS_VERSION": "document",
    "SCHEMA": "document",
    "convert": "document",
    "dump_yaml": "document",
    "limits_document": "document",
    "write_atomic": "document",
    "ManualRecorder": "manual",
    "UrdfJoint": "urdf",
    "check_urdf_names": "urdf",
    "patch_urdf": "urdf",
    "urdf_joints": "urdf",
}


def __getattr__(name: str) -> Any:
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib

    return getattr(importlib.import_module(f"{__name__}.{module}"), name)


__all__ = [
    "LIMITS_VERSION",
    "RANGE_END",
    "SCHEMA",
    "ArmFile",
    "AutoParams",
    "Joint",
    "JointRange",
    "ManualRecorder",
    "Progress",
    "UrdfJoint",
    "check_urdf_names",
    "convert",
    "dump_yaml",
    "limits_document",
    "load_arm",
    "parse_ids",
    "patch_urdf",
    "seek_joint",
    "urdf_joints",
    "write_atomic",
]
