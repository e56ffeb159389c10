"""Universal Robots' calibration file (`default_kinematics.yaml`) from a calibrated URDF.

UR's description packages build the six arm joints' `<origin>`s from one YAML file,
`kinematics: {shoulder, upper_arm, forearm, wrist_1, wrist_2, wrist_3: {x, y, z, roll, pitch,
yaw}, hash}` (metres, radians), passed as `ur.urdf.xacro kinematics_params:=FILE`. Each entry is
the `<origin>` of one joint, shoulder_pan_joint … wrist_3_joint, so the calibrated URDF's origins
are the file. The `hash` identifies the robot's factory calibration: the driver compares it with
the controller's and it cannot be recomputed, so the original one is kept.

That holds only for a URDF with the frames of UR's description, and many UR URDFs have others
(example-robot-data's UR5 has no `base_link_inertia` turn and other link frames: its origins, read
into UR's macro, put `tool0` about 1 m from where the URDF has it). So the file is checked the way
it will be used: the arm is built from its values as `ur_macro.xacro` builds it (`base_link` →
`base_link_inertia` turned by π about z → the six joints, each `<origin>` from the file and an
axis along z → `wrist_3_link` → `flange` → `tool0`), and its `tool0` must be the URDF's at every
pose tried, before the fit (the nominal URDF) and before the file is written (the calibrated one).
UR's own description, expanded with its `default_kinematics.yaml`, matches it to 0.000 mm.
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
    from armtool.calib.model.se3 import Array
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
# ur_macro.xacro's fixed joints around the six: base_link → base_link_inertia, wrist_3_link → flange → tool0 (rpy)
_BASE_INERTIA_RPY = (0.0, 0.0, math.pi)
_FLANGE_RPY = (0.0, -math.pi / 2, -math.pi / 2)
_TOOL0_RPY = (math.pi / 2, 0.0, math.pi / 2)
# Beyond this the URDF's frames are not UR's description's (the file's own rounding is ~1e-10 m)
SAME_M = 1e-5
SAME_RAD = 1e-5
_POSES = 100  # random joint vectors within the limits, and the zero pose


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
    target = UrTarget(joints, read_hash(given), given)
    from armtool.model.load import urdf_text

    check_ur_convention(urdf_text(ds.urdf, ds.xacro_args, ds.package_paths), joints, ds.urdf.name)
    return target


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
    """The YAML text: each key the `<origin>` of its joint in `urdf_text`, full precision; refused
    when UR's macro would not build the same arm from it (`check_ur_convention`)."""
    import yaml

    check_ur_convention(urdf_text, joints, source)
    kinematics: dict[str, object] = {**_origins(urdf_text, joints, source), "hash": hash_value}
    header = (
        "# Calibrated by armtool calibrate fit. Use it as the arm's kinematics:\n"
        "#   xacro ur.urdf.xacro ur_type:=... name:=... kinematics_params:=THIS_FILE\n"
        "# (or the kinematics_params launch argument of ur_robot_driver / ur_description).\n"
        "# The hash is the robot's original one, kept so the driver's calibration check still matches.\n"
    )
    text: str = yaml.safe_dump({"kinematics": kinematics}, sort_keys=False)
    return header + text


def _origins(urdf_text: str, joints: dict[str, str], source: str) -> dict[str, dict[str, float]]:
    """yaml key -> {x, y, z, roll, pitch, yaw} of its joint's `<origin>` in `urdf_text`."""
    from armtool.calib.model import se3
    from armtool.model.chain import origin_matrix
    from armtool.model.xmlsource import parse_xml

    root = parse_xml(urdf_text.encode("utf-8"))
    by_name = {el.get("name"): el for el in root.findall("joint")}
    out: dict[str, dict[str, float]] = {}
    for key, name in joints.items():
        el = by_name.get(name)
        if el is None:
            raise ArmtoolError(f"joint '{name}' not in {source}", hint="report this with the dataset")
        T = origin_matrix(el.find("origin"))
        xyz = [float(v) for v in T[:3, 3]]
        rpy = [float(v) for v in se3.rpy_of(T[:3, :3])]
        if not all(math.isfinite(v) for v in xyz + rpy):
            raise ArmtoolError(f"joint '{name}' has a non-finite origin", source)
        out[key] = dict(zip(("x", "y", "z", "roll", "pitch", "yaw"), xyz + rpy))
    return out


def ur_description_tool0(kinematics: dict[str, dict[str, float]], Q: Array) -> Array:
    """base_link → tool0 (N, 4, 4) of the arm that `ur_macro.xacro` builds from these
    `kinematics:` values, at the joint vectors Q (N, 6)."""
    import numpy as np

    from armtool.model.chain import axis_angle_batch, rpy_matrix

    def fixed(rpy: tuple[float, float, float], xyz: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> Array:
        T = np.eye(4)
        T[:3, :3] = rpy_matrix(*rpy)
        T[:3, 3] = xyz
        return T

    T = np.broadcast_to(fixed(_BASE_INERTIA_RPY), (len(Q), 4, 4)).copy()
    z = np.array([0.0, 0.0, 1.0])
    for i, key in enumerate(UR_JOINTS):
        v = kinematics[key]
        motion = np.broadcast_to(np.eye(4), (len(Q), 4, 4)).copy()
        motion[:, :3, :3] = axis_angle_batch(z, Q[:, i])
        T = T @ fixed((v["roll"], v["pitch"], v["yaw"]), (v["x"], v["y"], v["z"])) @ motion
    out: Array = T @ fixed(_FLANGE_RPY) @ fixed(_TOOL0_RPY)
    return out


@dataclass(frozen=True)
class ConventionError:
    """How far UR's macro, fed the file's values, puts tool0 from the URDF's, over the poses tried."""

    mean_m: float
    max_m: float
    max_rad: float

    @property
    def same(self) -> bool:
        return self.max_m <= SAME_M and self.max_rad <= SAME_RAD


def ur_convention_error(urdf_text: str, joints: dict[str, str], source: str) -> ConventionError:
    """The URDF's base_link → tool0 against UR's macro built from the values armtool would write."""
    import numpy as np

    from armtool.calib.model import se3
    from armtool.model.chain import chain_from_xml
    from armtool.model.xmlsource import parse_xml

    prefix = joints["shoulder"][: -len(UR_JOINTS["shoulder"])]  # the tf_prefix ("" for UR's default)
    base, tool0 = prefix + "base_link", prefix + "tool0"
    root = parse_xml(urdf_text.encode("utf-8"))
    links = {el.get("name") for el in root.findall("link")}
    missing = [name for name in (base, tool0) if name not in links]
    if missing:
        raise ArmtoolError(
            f"--ur-kinematics: {source} has no link {' or '.join(repr(m) for m in missing)}, as UR's description "
            "names the frames its kinematics file places",
            source,
            _FIX,
        )
    chain = chain_from_xml(root, base, tool0, source=source)
    if chain.joint_names != list(joints.values()):
        raise ArmtoolError(
            f"--ur-kinematics: the joints from {base} to {tool0} in {source} are {', '.join(chain.joint_names)}, "
            "not UR's six",
            source,
            _FIX,
        )
    values = _origins(urdf_text, joints, source)
    Q = np.vstack([np.zeros(chain.n), chain.random(np.random.default_rng(0), _POSES)])
    ours = ur_description_tool0(values, Q)
    theirs = np.stack([chain.fk(q) for q in Q])
    distance = np.linalg.norm(ours[:, :3, 3] - theirs[:, :3, 3], axis=1)
    relative = np.einsum("nji,njk->nik", ours[:, :3, :3], theirs[:, :3, :3])
    angle = np.linalg.norm(se3.log3_batch(relative), axis=1)
    return ConventionError(float(distance.mean()), float(distance.max()), float(angle.max()))


_FIX = (
    "calibrate with the URDF of UR's description (`xacro ur.urdf.xacro ur_type:=ur5e name:=ur`, the "
    "robot_description the driver publishes), whose joint origins are the kinematics file; or drop --ur-kinematics "
    "and use calibrated.urdf"
)


def check_ur_convention(urdf_text: str, joints: dict[str, str], source: str) -> None:
    """Refuse a URDF whose origins, written as UR's kinematics file, would not be the same arm."""
    error = ur_convention_error(urdf_text, joints, source)
    if not error.same:
        raise ArmtoolError(
            f"--ur-kinematics: {source} does not use the frames of UR's description: its joint origins, read by "
            f"ur_macro.xacro, put tool0 {error.mean_m * 1e3:.1f} mm from the URDF's on average "
            f"({error.max_m * 1e3:.1f} mm and {math.degrees(error.max_rad):.1f}° at worst over {_POSES + 1} poses)",
            source,
            _FIX,
        )
