"""The values that launch substitutions in a MoveIt package's YAML files take when launched.

ROS 1: roslaunch loads a file with `<rosparam command="load" file="..." subst_value="true"/>` and
replaces `$(arg NAME)` in it by the enclosing launch file's argument (roslaunch's loader,
`subst_value`): franka_ros's panda_moveit_config writes `$(arg arm_id)_arm` as kinematics.yaml's
group and `$(arg arm_id)_joint1` as its controllers' joints, and planning_context.launch loads
them with arm_id's default "panda". The values are the `<arg>`s (`default` or `value`) of the
package's launch files that load the file so. Where the package ships no launch file that does,
the `<xacro:arg>` defaults of its SRDF xacros stand in: the launch passes the same argument to
xacro (arm_id), and the package's files were written for the same defaults.

ROS 2 keys (`$(var tf_prefix)joint_1`, substituted by launch's ParameterFile) get their values
from the xacro arguments the robot is expanded with (armtool.moveit.params.name_ref), as before.
Only literal values count: a default that is itself a substitution is left unknown.
"""

from __future__ import annotations

import functools
from pathlib import Path

from lxml import etree

from armtool.fileio import read_regular

MAX_LAUNCH_BYTES = 1 << 20
MAX_LAUNCH_FILES = 200
_LAUNCH_SUFFIXES = (".launch", ".launch.xml", ".xml")
_XACRO_NS = ("http://www.ros.org/wiki/xacro", "http://ros.org/wiki/xacro", "http://wiki.ros.org/xacro")


def _root(path: Path) -> etree._Element | None:
    from armtool.model.xmlsource import XmlSyntaxProblem, parse_xml

    try:
        return parse_xml(read_regular(path, MAX_LAUNCH_BYTES))
    except (OSError, XmlSyntaxProblem):
        return None


def _literal(value: str | None) -> str | None:
    return value if value is not None and "$(" not in value and "${" not in value else None


def _launch_values(launch: Path, yaml_name: str) -> dict[str, str] | None:
    """The literal arguments of a ROS 1 launch file that loads `yaml_name` with subst_value;
    None when it does not load it so."""
    root = _root(launch)
    if root is None or root.tag != "launch":
        return None
    loads = any(
        el.get("subst_value", "").lower() in ("true", "1", "yes")
        and el.get("file", "").replace("\\", "/").rsplit("/", 1)[-1] == yaml_name
        for el in root.iter("rosparam")
    )
    if not loads:
        return None
    out: dict[str, str] = {}
    for arg in root.iter("arg"):
        name, value = arg.get("name"), _literal(arg.get("value", arg.get("default")))
        if name and value is not None:
            out.setdefault(name, value)
    return out


def xacro_arg_defaults(path: Path) -> dict[str, str]:
    """The literal defaults of the `<xacro:arg>`s a xacro file declares at its top level."""
    root = _root(path)
    out: dict[str, str] = {}
    if root is None:
        return out
    for el in root:
        tag = el.tag
        if not isinstance(tag, str) or not tag.startswith("{") or tag[1:].split("}", 1)[0] not in _XACRO_NS:
            continue
        if tag.rsplit("}", 1)[1] == "arg":
            name, value = el.get("name"), _literal(el.get("default"))
            if name and value is not None:
                out[name] = value
    return out


def _package_dir(path: Path) -> Path | None:
    from armtool.model.packages import package_root

    return package_root(path.parent, 4)


def launch_values(path: Path) -> dict[str, str]:
    """The values `$(arg NAME)` takes in the package YAML file `path` when its launch loads it:
    the launch files' arguments, over the package's SRDF xacro defaults (see the module)."""
    root = _package_dir(path)
    if root is None:
        return {}
    return dict(_values(root.resolve(), path.name))


@functools.lru_cache(maxsize=64)
def _values(root: Path, yaml_name: str) -> tuple[tuple[str, str], ...]:
    out: dict[str, str] = {}
    for place in (root / "config", root / "srdf", root):
        try:
            srdfs = sorted(p for p in place.iterdir() if p.name.lower().endswith(".srdf.xacro") and p.is_file())
        except OSError:
            continue
        for srdf in srdfs:
            for name, value in xacro_arg_defaults(srdf).items():
                out.setdefault(name, value)
    launch_dir = root / "launch"
    if launch_dir.is_dir():
        files = sorted(p for p in launch_dir.rglob("*") if p.name.endswith(_LAUNCH_SUFFIXES) and p.is_file())
        for launch in files[:MAX_LAUNCH_FILES]:
            values = _launch_values(launch, yaml_name)
            if values:
                out.update(values)
    return tuple(out.items())
