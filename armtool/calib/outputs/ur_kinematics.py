"""Universal Robots' calibration file (`default_kinematics.yaml`) from a calibrated URDF.

UR's description packages build the six arm joints' `<origin>`s from one YAML file,
`kinematics: {shoulder, upper_arm, forearm, wrist_1, wrist_2, wrist_3: {x, y, z, roll, pitch,
yaw}, hash}` (metres, radians), passed as `ur.urdf.xacro kinematics_params:=FILE`. Each entry is
the `<origin>` of one joint, shoulder_pan_joint … wrist_3_joint, so the calibrated URDF's origins
are the file. The `hash` identifies the robot's factory calibration: the driver compares it with
the controller's and it cannot be recomputed, so the original one is kept.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from armtool.errors import ArmtoolError

if TYPE_CHECKING:
    from armtool.calib.inputs.dataset import Dataset
    from armtool.model.chain import Chain

# yaml key -> joint name (after an optional tf_prefix), in chain order
UR_JOINTS = {
    "shoulder": "shoulder_pan_joint",
    "upper_arm": "shoulder_lift_joint",
    "forearm": "elbow_joint",
    "wrist_1": "wrist_1_joint",
    "wrist_2": "wrist_2_joint",
    "wrist_3": "wrist_3_joint",
}


@dataclass(frozen=True)
class UrTarget:
    """What `--ur-kinematics` needs, found before the fit: the arm's joints and the hash to keep."""

    joints: dict[str, str]  # yaml key -> chain joint name
    hash: str
    source: Path  # the robot's current kinematics file (an input: never overwritten)


def ur_target(ds: Dataset, chain: Chain, out: Path | None, given: Path | None) -> UrTarget | None:
    """For --ur-kinematics OUT, checked before the fit: the chain is a UR arm's, and the hash to keep
    (from --ur-kinematics-in, or the file the dataset's kinematics_params xacro argument names)."""
    if out is None:
        if given is not None:
            raise ArmtoolError(
                "--ur-kinematics-in needs --ur-kinematics", hint="add --ur-kinematics FILE for the calibrated file"
            )
        return None
    if out.parent != Path("") and not out.parent.is_dir():
        raise ArmtoolError(
            "--ur-kinematics's directory does not exist", str(out), "create it, or write the file elsewhere"
        )
    joints = ur_joint_names(chain.joint_names, str(ds.urdf))
    if given is None:
        value = ds.xacro_args.get("kinematics_params")
        if value is None:
            raise ArmtoolError(
                "--ur-kinematics needs the robot's current kinematics file, to keep its hash",
                hint="pass --ur-kinematics-in FILE (the robot's default_kinematics.yaml, or ur_calibration's output), "
                "or --xacro-arg kinematics_params:=FILE",
            )
        given = kinematics_params_path(value, ds.root, ds.package_paths)
    return UrTarget(joints, read_hash(given), given)


def ur_joint_names(chain_joints: list[str], source: str) -> dict[str, str]:
    """yaml key -> the chain's joint name; refuses a chain that is not a UR arm's six joints."""
    suffixes = list(UR_JOINTS.values())
    prefix = chain_joints[0][: -len(suffixes[0])] if chain_joints and chain_joints[0].endswith(suffixes[0]) else None
    if prefix is None or chain_joints != [prefix + s for s in suffixes]:
        raise ArmtoolError(
            f"--ur-kinematics needs a Universal Robots arm: the chain's joints are {', '.join(chain_joints)}",
            source,
            "a UR chain is " + ", ".join(suffixes) + " (with a common tf_prefix); drop --ur-kinematics for other arms",
        )
    return {key: prefix + name for key, name in UR_JOINTS.items()}


def read_hash(path: Path) -> str:
    """The `kinematics.hash` of a UR kinematics file."""
    from armtool.fileio import read_yaml

    if not path.is_file():
        raise ArmtoolError(
            "UR kinematics file not found",
            str(path),
            "pass the robot's default_kinematics.yaml (or the file ur_calibration wrote)",
        )
    doc = read_yaml(path, "UR kinematics file")
    kin = doc.get("kinematics") if isinstance(doc, dict) else None
    value = kin.get("hash") if isinstance(kin, dict) else None
    if not isinstance(value, str) or not value:
        raise ArmtoolError(
            "no kinematics.hash in the UR kinematics file",
            str(path),
            "use the file ur_calibration or the robot's description package provides",
        )
    return value


def kinematics_params_path(value: str, dataset_root: Path, package_paths: list[Path]) -> Path:
    """The file a `kinematics_params` xacro argument names: `$(find pkg)` resolved, a relative path
    tried against the working directory, then the dataset."""
    from armtool.model.packages import PackageResolver

    resolver = PackageResolver(package_paths)

    def find(m: re.Match[str]) -> str:
        found = resolver.find(m.group(1), dataset_root)
        if found is None:
            raise ArmtoolError(
                f"package '{m.group(1)}' in kinematics_params:={value} not found", hint="pass --package-path DIR"
            )
        return str(found)

    path = Path(re.sub(r"\$\(find\s+([^)\s]+)\s*\)", find, value))
    if not path.is_absolute() and not path.is_file() and (dataset_root / path).is_file():
        path = dataset_root / path
    return path


def ur_kinematics_yaml(urdf_text: str, joints: dict[str, str], hash_value: str, source: str) -> str:
    """The YAML text: each key the `<origin>` of its joint in `urdf_text`, full precision."""
    import yaml

    from armtool.calib.model import se3
    from armtool.model.chain import origin_matrix
    from armtool.model.xmlsource import parse_xml

    root = parse_xml(urdf_text.encode("utf-8"))
    by_name = {el.get("name"): el for el in root.findall("joint")}
    kinematics: dict[str, object] = {}
    for key, name in joints.items():
        el = by_name.get(name)
        if el is None:
            raise ArmtoolError(f"joint '{name}' not in {source}", hint="report this with the dataset")
        T = origin_matrix(el.find("origin"))
        xyz = [float(v) for v in T[:3, 3]]
        rpy = [float(v) for v in se3.rpy_of(T[:3, :3])]
        if not all(math.isfinite(v) for v in xyz + rpy):
            raise ArmtoolError(f"joint '{name}' has a non-finite origin", source)
        kinematics[key] = dict(zip(("x", "y", "z", "roll", "pitch", "yaw"), xyz + rpy))
    kinematics["hash"] = hash_value
    header = (
        "# Calibrated by armtool calibrate fit. Use it as the arm's kinematics:\n"
        "#   xacro ur.urdf.xacro ur_type:=... name:=... kinematics_params:=THIS_FILE\n"
        "# (or the kinematics_params launch argument of ur_robot_driver / ur_description).\n"
        "# The hash is the robot's original one, kept so the driver's calibration check still matches.\n"
    )
    text: str = yaml.safe_dump({"kinematics": kinematics}, sort_keys=False)
    return header + text
