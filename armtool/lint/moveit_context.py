"""What the rules for a MoveIt config package's YAML files see: the file as MoveIt reads it
(`armtool.moveit`), which ROS reads it (ROS 2 types parameters, ROS 1 does not), and the robot
it belongs to (the SRDF and the URDF paired with it; None when they were not found)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from armtool.lint.context import FileContext, UrdfContext
from armtool.lint.finding import Edit, Finding
from armtool.lint.locate import Locator, display_path
from armtool.lint.rule import Rule, Target

if TYPE_CHECKING:
    import yaml

    from armtool.lint.srdf_context import SrdfContext
    from armtool.moveit.controllers import MoveItControllers, RobotControllers
    from armtool.moveit.joint_limits import JointLimitsFile
    from armtool.moveit.package import MoveItPackage
    from armtool.moveit.params import Scalar


def as_double(value: Scalar) -> str:
    """An integer scalar written as the same number in double form (`1` -> `1.0`, `0x10` -> `16.0`)."""
    from armtool.moveit.params import is_octal

    text = value.text.strip()
    if text.lstrip("+-").isdigit() and not is_octal(text):
        return text + ".0"
    number = value.number()
    return repr(float(number)) if number is not None else text


class YamlContext(FileContext):
    """A MoveIt YAML file: its path, which ROS loads it (2, 1 or None when nothing says), and the
    robot; findings at a line and column, fixes as text edits of a scalar."""

    def __init__(
        self,
        path: Path,
        ros: int | None,
        srdf: SrdfContext | None,
        urdf: UrdfContext | None,
        known_args: dict[str, str] | None = None,
    ) -> None:
        super().__init__(path, Locator(path))
        self.ros = ros
        self.srdf = srdf
        self.urdf = urdf
        self.known_args = dict(known_args or {})

    def finding_at_scalar(
        self,
        rule: Rule | type[Rule],
        scalar: Scalar,
        message: str,
        *,
        hint: str | None = None,
        replacement: str | None = None,
    ) -> Finding:
        """A finding at a scalar, with an edit that replaces it (a fix) when `replacement` is given."""
        found = self.finding_at(rule, scalar.line, scalar.column, message, hint=hint)
        if replacement is None:
            return found
        return found._replace(edit=Edit(self.path, scalar.start, scalar.end, replacement))

    def integer_finding(self, rule: Rule | type[Rule], value: Scalar, what: str, reader: str) -> Finding:
        """A whole number where a ROS 2 reader declares a double parameter, with the fix `1` -> `1.0`."""
        double = as_double(value)
        return self.finding_at_scalar(
            rule,
            value,
            f"{what}: {value.text} is an integer; {reader} reads it as a double parameter and refuses an "
            "integer (InvalidParameterTypeException: expected [double] got [integer])",
            hint=f"write {double}",
            replacement=double,
        )

    def urdf_note(self) -> str:
        """' (URDF: arm.urdf.xacro)': which URDF names and limits were compared with."""
        return f" (URDF: {display_path(self.urdf.path)})" if self.urdf is not None else ""

    def active_group_joints(self) -> dict[str, list[str]]:
        """Per SRDF group, the joints MoveIt moves: revolute, prismatic or continuous URDF joints that
        are neither mimic nor passive (the variables time parameterization and controllers handle)."""
        if self.srdf is None or self.urdf is None:
            return {}
        passive = {el.get("name", "") for el in self.srdf.elements("passive_joint")}
        out: dict[str, list[str]] = {}
        for group in self.srdf.groups:
            names = []
            for name in self.srdf.group_joints(group):
                joint = self.urdf.joint(name)
                if joint is None or joint.type not in ("revolute", "prismatic", "continuous"):
                    continue
                if joint.mimic_el is not None or name in passive:
                    continue
                names.append(name)
            out[group] = names
        return out


class JointLimitsContext(YamlContext):
    target = Target.JOINT_LIMITS

    def __init__(
        self,
        path: Path,
        doc: JointLimitsFile,
        ros: int | None,
        srdf: SrdfContext | None,
        urdf: UrdfContext | None,
        known_args: dict[str, str] | None = None,
    ) -> None:
        super().__init__(path, ros, srdf, urdf, known_args)
        self.doc = doc
        self.in_moveit_package = False  # beside a .setup_assistant or an SRDF (not a description's limits file)

    def urdf_joint_names(self) -> set[str]:
        return self.urdf.joint_names if self.urdf is not None else set()


class PilzContext(YamlContext):
    target = Target.PILZ
    # The limits Pilz reads from cartesian_limits (its CartesianLimit), all four required.
    KEYS = ("max_trans_vel", "max_trans_acc", "max_trans_dec", "max_rot_vel")

    def __init__(
        self,
        path: Path,
        limits: yaml.Node | None,
        limits_at: tuple[int, int] | None,
        ros: int | None,
    ) -> None:
        super().__init__(path, ros, None, None)
        self.limits = limits  # the cartesian_limits mapping (None when the file has none)
        self.limits_at = limits_at


@dataclass
class PackageControllers:
    """Every controllers file of one MoveIt config package, read once per lint run."""

    package: MoveItPackage
    moveit: dict[Path, MoveItControllers] = field(default_factory=dict)
    robot: dict[Path, RobotControllers] = field(default_factory=dict)


class ControllersContext(YamlContext):
    target = Target.CONTROLLERS

    def __init__(
        self,
        path: Path,
        moveit: MoveItControllers | None,
        robot: RobotControllers | None,
        package: PackageControllers | None,
        ros: int | None,
        srdf: SrdfContext | None,
        urdf: UrdfContext | None,
        known_args: dict[str, str] | None = None,
    ) -> None:
        super().__init__(path, ros, srdf, urdf, known_args)
        self.moveit = moveit
        self.robot = robot
        self.package = package

    def robot_controllers(self) -> RobotControllers | None:
        """The package's ros2_controllers.yaml (ROS 1: ros_controllers.yaml), when it has one."""
        if self.package is None or self.package.package.robot_controllers is None:
            return None
        return self.package.robot.get(self.package.package.robot_controllers)
