"""Lint a MoveIt config package's YAML files beyond kinematics.yaml: joint_limits.yaml, the Pilz
Cartesian limits and the controllers files, each read as MoveIt reads it and checked against the
robot (the SRDF found as for kinematics.yaml, and the URDF paired with that SRDF).

A file whose content is not MoveIt's (Franka's `joint1: limit:` files, Kinova's `joint_names`
lists, a controllers file of another tool) is left alone, as kinematics.yaml files are.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from armtool.lint.file_findings import LOADER_CODE, invalid_yaml
from armtool.lint.finding import Finding
from armtool.lint.rule import Target

if TYPE_CHECKING:
    import yaml

    from armtool.lint.context import FileContext, UrdfContext
    from armtool.lint.moveit_context import PackageControllers
    from armtool.lint.srdf_context import SrdfContext
    from armtool.model.packages import PackageResolver


class Linter(Protocol):
    """What these checks need of the linter (armtool.lint.engine.Linter) that calls them."""

    resolver: PackageResolver
    package_cache: dict[Path, Any]  # MoveIt config package root -> its controllers, read once per run
    yaml_documents: dict[Path, Any]  # resolved path -> its YAML nodes or the error parsing them, once per run

    def read_text(self, path: Path) -> str: ...

    def xacro_args_for(self, path: Path, extra: dict[str, str] | None = None) -> dict[str, str]: ...

    def srdf_for_package_file(self, path: Path) -> SrdfContext | None: ...

    def paired_srdf(self, path: Path) -> SrdfContext | None: ...

    def given_urdf(self, path: Path) -> Path | None: ...

    def urdf_model(self, path: Path) -> UrdfContext | None: ...

    def note_counterparts(self, path: Path, urdf: Path | None, srdf: Path | None, kind: str) -> None: ...

    def run_rules(self, ctx: FileContext, target: Target) -> Iterator[Finding]: ...


def _document(linter: Linter, path: Path) -> yaml.Node | None:
    """The file's YAML nodes, parsed once per run (a controllers file is read for its package's
    controllers and again when it is linted). Raises yaml.YAMLError or RecursionError as
    params.parse does, each time it is asked."""
    import yaml

    from armtool.moveit.params import parse

    key = path.resolve()
    known = linter.yaml_documents.get(key)
    if known is None:
        try:
            known = (parse(linter.read_text(path)), None)
        except (yaml.YAMLError, RecursionError) as exc:
            known = (None, exc)
        linter.yaml_documents[key] = known
    node, error = known
    if error is not None:
        raise error
    return node


def _parse(linter: Linter, path: Path, target: Target) -> tuple[yaml.Node | None, list[Finding]]:
    """The file's YAML nodes, or its loader finding (invalid YAML)."""
    import yaml

    try:
        return _document(linter, path), []
    except yaml.YAMLError as exc:
        return None, [invalid_yaml(LOADER_CODE[target.value], path, exc)]


def _ros(path: Path, ros2_params: bool) -> int | None:
    """2 for a ROS 2 package or a ROS 2 parameter file, 1 for a catkin package, else None."""
    from armtool.moveit.params import ros_version

    return 2 if ros2_params else ros_version(path)


def robot_for(linter: Linter, path: Path) -> tuple[SrdfContext | None, UrdfContext | None, dict[str, str]]:
    """The SRDF a package file belongs to (found as kinematics.yaml's is), the URDF paired with
    it, and the values of launch substitutions in its keys: the xacro arguments that URDF is
    expanded with, over what the package's launch files give (armtool.moveit.substitutions)."""
    from armtool.lint.pairing import read_setup_assistant
    from armtool.moveit.substitutions import launch_values

    launched = launch_values(path)  # ROS 1 `$(arg NAME)` as the package's launch fills it in
    srdf = linter.srdf_for_package_file(path)
    if srdf is None:
        return None, None, launched
    paired = linter.paired_srdf(srdf.path)
    if paired is None or paired.urdf is None:
        return srdf, None, launched
    setup = read_setup_assistant(path.parent)
    extra = setup.urdf_xacro_args if setup is not None else {}
    return paired, paired.urdf, {**launched, **linter.xacro_args_for(paired.urdf.path, extra)}


def lint_joint_limits(linter: Linter, path: Path) -> list[Finding]:
    from armtool.lint.moveit_context import JointLimitsContext
    from armtool.moveit.joint_limits import is_moveit_joint_limits, read_joint_limits

    root, findings = _parse(linter, path, Target.JOINT_LIMITS)
    if findings or not is_moveit_joint_limits(root):
        return findings  # not MoveIt's: another tool's limits file
    srdf, urdf, args = robot_for(linter, path)
    doc = read_joint_limits(path, root, args)
    if urdf is None:
        urdf = limits_urdf(linter, path, [e.name.bare for e in doc.joints])
        if urdf is not None:
            doc = read_joint_limits(path, root, {**args, **urdf.xacro_args})
    linter.note_counterparts(
        path, urdf.path if urdf is not None else None, srdf.path if srdf is not None else None, "joint_limits"
    )
    ctx = JointLimitsContext(path, doc, _ros(path, doc.section.ros2_params), srdf, urdf, args)
    ctx.in_moveit_package = srdf is not None or _moveit_package(path)
    return list(linter.run_rules(ctx, Target.JOINT_LIMITS))


URDF_DIRS = ("urdf", "robots", "robot")  # where a description package keeps its robots


def limits_urdf(linter: Linter, path: Path, joints: list[str]) -> UrdfContext | None:
    """The URDF a joint_limits.yaml with no SRDF is compared with: `--urdf` (or the configuration's
    `urdf` for the file), else the one robot of its own ROS package (its urdf/ or robots/
    directory) that has every joint the file names: a description package that keeps its
    limits beside its robot (khi_duaro_description's config/duaro_joint_limits.yaml)."""
    from armtool.model.packages import package_root

    given = linter.given_urdf(path)
    if given is not None:
        return linter.urdf_model(given)
    root = package_root(path.parent, 3)
    if root is None or not joints:
        return None
    found: list[UrdfContext] = []
    for place in URDF_DIRS:
        try:
            files = sorted(p for p in (root / place).iterdir() if p.name.lower().endswith((".urdf", ".urdf.xacro")))
        except OSError:
            continue
        for file in files:
            ctx = linter.urdf_model(file)
            if ctx is not None and ctx.links and set(joints) <= ctx.joint_names:
                found.append(ctx)
    return found[0] if len(found) == 1 else None


def _moveit_package(path: Path) -> bool:
    """True when the package holding `path` is a MoveIt config (a .setup_assistant, or an SRDF in
    it), not a description package whose joint_limits.yaml xacro or ros2_control reads."""
    from armtool.model.packages import package_root as ros_package
    from armtool.moveit.package import package_root
    from armtool.moveit.params import ROS_PACKAGE_LEVELS

    root = ros_package(path.parent, ROS_PACKAGE_LEVELS) or package_root(path)
    if root is None:
        return False
    if (root / ".setup_assistant").is_file():
        return True
    places = [root, *(p for p in root.iterdir() if p.is_dir() and not p.name.startswith("."))]
    return any(any(place.glob("*.srdf")) or any(place.glob("*.srdf.xacro")) for place in places)


def lint_pilz(linter: Linter, path: Path) -> list[Finding]:
    from armtool.lint.moveit_context import PilzContext
    from armtool.moveit.params import child, key_node, moveit_section, position

    root, findings = _parse(linter, path, Target.PILZ)
    if findings:
        return findings
    section = moveit_section(root, "robot_description_planning")
    limits = child(section.mapping, "cartesian_limits")
    if limits is None:
        return []  # not Pilz's Cartesian limits
    where = key_node(section.mapping, "cartesian_limits")
    ctx = PilzContext(path, limits, position(where) if where is not None else None, _ros(path, section.ros2_params))
    linter.note_counterparts(path, None, None, "pilz")
    return list(linter.run_rules(ctx, Target.PILZ))


def package_controllers(linter: Linter, path: Path) -> PackageControllers | None:
    """Every controllers file of the MoveIt config package that holds `path`, read once."""
    from armtool.lint.moveit_context import PackageControllers
    from armtool.moveit.controllers import read_moveit_controllers, read_robot_controllers
    from armtool.moveit.package import package_root, read_package

    root = package_root(path)
    if root is None or not (root / ".setup_assistant").is_file():
        return None  # controllers files are cross-checked inside a MoveIt config package only
    cached = linter.package_cache.get(root)
    if cached is not None or root in linter.package_cache:
        return cached
    import yaml

    from armtool.errors import ArmtoolError

    try:
        pkg = read_package(root, linter.resolver)
    except ArmtoolError:
        linter.package_cache[root] = None
        return None
    out = PackageControllers(pkg)
    for file in pkg.controller_files:
        try:
            node = _document(linter, file)
        except (yaml.YAMLError, RecursionError):
            continue
        moveit = read_moveit_controllers(file, node)
        if moveit is not None:
            out.moveit[file] = moveit
        robot = read_robot_controllers(file, node)
        if robot is not None:
            out.robot[file] = robot
    linter.package_cache[root] = out
    return out


def lint_controllers(linter: Linter, path: Path) -> list[Finding]:
    from armtool.lint.moveit_context import ControllersContext
    from armtool.moveit.controllers import read_moveit_controllers, read_robot_controllers

    root, findings = _parse(linter, path, Target.CONTROLLERS)
    if findings:
        return findings
    moveit = read_moveit_controllers(path, root)
    robot = read_robot_controllers(path, root)
    if moveit is None and robot is None:
        return []  # not a controllers file MoveIt or a controller manager reads
    package = package_controllers(linter, path)
    srdf, urdf, args = robot_for(linter, path) if package is not None else (None, None, {})
    from armtool.moveit.params import parameter_nodes

    ctx = ControllersContext(
        path, moveit, robot, package, _ros(path, parameter_nodes(root) is not None), srdf, urdf, args
    )
    linter.note_counterparts(
        path, urdf.path if urdf is not None else None, srdf.path if srdf is not None else None, "controllers"
    )
    return list(linter.run_rules(ctx, Target.CONTROLLERS))


def lint_setup_assistant(linter: Linter, path: Path) -> list[Finding]:
    """M101: a MoveIt config package's .setup_assistant naming a URDF or SRDF that does not exist."""
    from armtool.lint.file_findings import file_finding
    from armtool.lint.pairing import present_instead, read_setup_assistant, setup_assistant_line

    linter.read_text(path)  # for inline ignore comments
    setup = read_setup_assistant(path.parent)
    if setup is None or setup.package_dir.resolve() != path.parent.resolve():
        return []
    linter.note_counterparts(path, None, None, "setup_assistant")
    entries: list[tuple[str, str, Path]] = []
    if setup.urdf_package and setup.urdf_relative:
        found = linter.resolver.find(setup.urdf_package, setup.package_dir)
        if found is not None:
            entries.append(("URDF", setup.urdf_relative, found / setup.urdf_relative))
    if setup.srdf_relative:
        entries.append(("SRDF", setup.srdf_relative, setup.package_dir / setup.srdf_relative))
    out = []
    for what, relative, file in entries:
        if file.is_file():
            continue
        instead = present_instead(file)
        line = setup_assistant_line(setup.package_dir, relative)
        out.append(
            file_finding(
                "M101",
                path,
                line,
                1,
                f".setup_assistant names the {what} {relative}, which does not exist"
                + (f" (did you mean '{instead}'?)" if instead else ""),
                f"write relative_path: {Path(relative).parent.joinpath(instead).as_posix()}"
                if instead
                else "write the relative path of the package's file, as the Setup Assistant would",
            )
        )
    return out
