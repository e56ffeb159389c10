"""Which files a MoveIt config package's launch files load, found the way MoveIt finds them.

MoveIt 2 (moveit_configs_utils' MoveItConfigsBuilder, what the Setup Assistant's launch files call):

- URDF: `config/<robot>.urdf.xacro` when the package has it (the Setup Assistant writes it, with
  the ros2_control tags), else the package and relative path `.setup_assistant` names, else
  `config/<robot>.urdf`. `<robot>` is the builder's first argument; its default package name is
  `<robot>_moveit_config`. xacro arguments: `.setup_assistant`'s `xacro_args` (what the Setup
  Assistant expanded the URDF with).
- SRDF: the relative path `.setup_assistant` names, else `config/<robot>.srdf`.
- `config/kinematics.yaml`, `config/joint_limits.yaml`, `config/pilz_cartesian_limits.yaml`.
- trajectory execution: the one `config/*_controllers.yaml`; of several, `moveit_controllers.yaml`,
  then `moveit2_controllers.yaml`, then `<robot>_controllers.yaml`. The generated demo launch
  hands `config/ros2_controllers.yaml` to ros2_control_node.

MoveIt 1 (catkin) packages are read from the same `.setup_assistant`, with ROS 1's file names:
`simple_moveit_controllers.yaml` (or `controllers.yaml`) and `ros_controllers.yaml`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from armtool.errors import ArmtoolError
from armtool.model.packages import PackageResolver, package_name
from armtool.moveit.params import ros_version

_BUILDER = re.compile(r"MoveItConfigsBuilder\(\s*[\"']([^\"']+)[\"']")


@dataclass
class MoveItPackage:
    """A MoveIt config package's files (None where the package has no such file)."""

    root: Path
    name: str | None
    robot_name: str | None
    ros: int | None
    urdf: Path | None = None
    urdf_xacro_args: dict[str, str] = field(default_factory=dict)
    urdf_why: str = ""
    srdf: Path | None = None
    srdf_why: str = ""
    stale: list[tuple[str, str, Path]] = field(default_factory=list)  # (URDF/SRDF, relative path, missing file)
    kinematics: Path | None = None
    joint_limits: Path | None = None
    pilz_limits: Path | None = None
    moveit_controllers: Path | None = None  # the file trajectory execution loads
    controller_files: list[Path] = field(default_factory=list)  # every *controllers*.yaml of config/
    robot_controllers: Path | None = None  # ros2_controllers.yaml / ros_controllers.yaml
    problems: list[str] = field(default_factory=list)  # what could not be found, for messages

    def files(self) -> list[Path]:
        """The package's files that lint checks, each once."""
        found = [
            self.srdf,
            self.kinematics,
            self.joint_limits,
            self.pilz_limits,
            *self.controller_files,
        ]
        return list(dict.fromkeys(p for p in found if p is not None and p.is_file()))


def package_root(start: Path) -> Path | None:
    """The MoveIt config package that holds `start`: the nearest directory with a
    `.setup_assistant`, else with a package.xml and a config/ directory."""
    directory = start if start.is_dir() else start.parent
    for candidate in [directory, *directory.parents][:5]:
        if (candidate / ".setup_assistant").is_file():
            return candidate
        if (candidate / "package.xml").is_file():
            return candidate if (candidate / "config").is_dir() else None
    return None


def _robot_name(root: Path, package: str | None) -> str | None:
    """The builder's first argument in the package's launch files, else what its default package
    name (`<robot>_moveit_config`) implies, else the package name."""
    launch = root / "launch"
    if launch.is_dir():
        for path in sorted(launch.glob("*.py")):
            try:
                match = _BUILDER.search(path.read_text(encoding="utf-8", errors="replace"))
            except OSError:
                continue
            if match:
                return match.group(1)
    if package:
        return package.removesuffix("_moveit_config")
    return None


def _controllers_choice(config: Path, robot: str | None) -> Path | None:
    """MoveItConfigsBuilder.trajectory_execution()'s file: the only `*_controllers.yaml`, or of
    several the one named moveit, moveit2 or after the robot (None when it cannot choose)."""
    matches = sorted(p for p in config.glob("*_controllers.yaml") if p.is_file())
    if len(matches) == 1:
        return matches[0]
    by_stem = {p.name.removesuffix("_controllers.yaml"): p for p in matches}
    for stem in ("moveit", "moveit2", robot):
        if stem and stem in by_stem:
            return by_stem[stem]
    return None


def _package_srdf(config: Path, robot: str | None) -> Path | None:
    """`config/<robot>.srdf` (or its .srdf.xacro), else the only SRDF (or, of none, the only SRDF
    xacro) of config/."""
    for name in (f"{robot}.srdf", f"{robot}.srdf.xacro") if robot else ():
        if (config / name).is_file():
            return config / name
    for pattern in ("*.srdf", "*.srdf.xacro"):
        found = sorted(p for p in config.glob(pattern) if p.is_file())
        if len(found) == 1:
            return found[0]
        if found:
            return None
    return None


def stale_entry_error(pkg: MoveItPackage, what: str) -> ArmtoolError | None:
    """The error for a command that needs the package's URDF or SRDF (`what`) when its
    .setup_assistant names a file that does not exist and nothing took its place."""
    from armtool.lint.pairing import present_instead, setup_assistant_line

    chosen = pkg.urdf if what == "URDF" else pkg.srdf
    for kind, relative, missing in pkg.stale:
        if kind == what and chosen == missing:
            instead = present_instead(missing)
            return ArmtoolError(
                f"the {what} that .setup_assistant names, {relative}, does not exist"
                + (f" (did you mean '{instead}'?)" if instead else ""),
                f"{pkg.root / '.setup_assistant'}:{setup_assistant_line(pkg.root, relative)}",
                f"correct relative_path in .setup_assistant, or pass the {what} with --{what.lower()}",
            )
    return None


def read_package(directory: Path, resolver: PackageResolver) -> MoveItPackage:
    """The files of the MoveIt config package at `directory` (its root or any directory in it).
    Raises ArmtoolError when it is not a MoveIt config package."""
    from armtool.lint.pairing import read_setup_assistant

    if not directory.is_dir():
        raise ArmtoolError(
            "--moveit-config needs a directory", str(directory), "pass the MoveIt config package's directory"
        )
    root = package_root(directory)
    config = root / "config" if root is not None else None
    if root is None or config is None or not config.is_dir():
        raise ArmtoolError(
            "not a MoveIt config package (no .setup_assistant, and no package.xml with a config/ directory)",
            str(directory),
            "pass the directory the Setup Assistant generated (it holds .setup_assistant and config/)",
        )
    name = package_name(root, limit=1 << 20)
    robot = _robot_name(root, name)
    ros = ros_version(root)
    pkg = MoveItPackage(root, name, robot, ros)
    setup = read_setup_assistant(root)
    # URDF
    modified = config / f"{robot}.urdf.xacro" if robot else None
    if modified is not None and modified.is_file():
        pkg.urdf, pkg.urdf_why = modified, f"config/{modified.name} (the Setup Assistant's URDF with ros2_control)"
    elif setup is not None and setup.urdf_package and setup.urdf_relative:
        found = resolver.find(setup.urdf_package, root)
        if found is None:
            pkg.problems.append(
                f".setup_assistant names the URDF of package '{setup.urdf_package}', which was not found"
                " (pass --package-path DIR for the directory that holds it)"
            )
        else:
            pkg.urdf, pkg.urdf_why = found / setup.urdf_relative, "named by .setup_assistant"
            if not pkg.urdf.is_file():
                pkg.stale.append(("URDF", setup.urdf_relative, pkg.urdf))
    elif robot and (config / f"{robot}.urdf").is_file():
        pkg.urdf, pkg.urdf_why = config / f"{robot}.urdf", f"config/{robot}.urdf"
    if setup is not None:
        pkg.urdf_xacro_args = dict(setup.urdf_xacro_args)
    if pkg.urdf is None and not pkg.problems:
        pkg.problems.append("no URDF: .setup_assistant names none and config/ has no <robot>.urdf.xacro")
    # SRDF
    if setup is not None and setup.srdf_relative:
        pkg.srdf, pkg.srdf_why = root / setup.srdf_relative, "named by .setup_assistant"
        if not pkg.srdf.is_file():  # renamed since (wxai.srdf -> wxai.srdf.xacro): the launch's own file
            pkg.stale.append(("SRDF", setup.srdf_relative, pkg.srdf))
            instead = _package_srdf(config, robot)
            if instead is not None:
                pkg.srdf = instead
                pkg.srdf_why = (
                    f"config/{instead.name}: .setup_assistant names {setup.srdf_relative}, which does not exist"
                )
    else:
        pkg.srdf = _package_srdf(config, robot)
        pkg.srdf_why = f"config/{pkg.srdf.name}" if pkg.srdf is not None else ""
    # YAML files
    for attr, file_name in (
        ("kinematics", "kinematics.yaml"),
        ("joint_limits", "joint_limits.yaml"),
        ("pilz_limits", "pilz_cartesian_limits.yaml"),
    ):
        if (config / file_name).is_file():
            setattr(pkg, attr, config / file_name)
    if pkg.pilz_limits is None and (config / "cartesian_limits.yaml").is_file():
        pkg.pilz_limits = config / "cartesian_limits.yaml"  # the name MoveIt used before pilz_cartesian_limits.yaml
    pkg.controller_files = sorted(p for p in config.glob("*controller*.yaml") if p.is_file())
    if ros == 1:
        for file_name in ("simple_moveit_controllers.yaml", "controllers.yaml"):
            if (config / file_name).is_file():
                pkg.moveit_controllers = config / file_name
                break
        if (config / "ros_controllers.yaml").is_file():
            pkg.robot_controllers = config / "ros_controllers.yaml"
    else:
        pkg.moveit_controllers = _controllers_choice(config, robot)
        if (config / "ros2_controllers.yaml").is_file():
            pkg.robot_controllers = config / "ros2_controllers.yaml"
    return pkg
