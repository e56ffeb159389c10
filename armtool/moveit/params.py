"""One reader for MoveIt's YAML files: ROS 1 flat files and ROS 2 parameter files alike.

MoveIt 1 loads `joint_limits.yaml`, `kinematics.yaml` and the Pilz limits with rosparam into a
namespace (`robot_description_planning`, `robot_description_kinematics`); MoveIt 2 loads the same
flat files into that namespace from Python launch files (MoveItConfigsBuilder), or takes them as
ROS 2 parameter files whose settings sit under a node name (`/**` or `move_group`), then
`ros__parameters`, then the namespace. `moveit_section` finds the settings in every one of these
layouts, so each command reads these files the same way.

Values are typed as ROS 2 types them (rcl_yaml_param_parser's `get_value`): a quoted scalar is a
string, `true`/`yes`/`on` a bool, what `strtoll` reads whole an integer, what `strtod` reads whole a
double. That is the type move_group sees: `max_velocity: 1` is an integer, and a parameter
declared as a double refuses it (rclcpp's InvalidParameterTypeException).

Keys may carry launch substitutions (`$(var tf_prefix)joint_1`, `$(arg prefix)joint_1`):
`name_ref` substitutes the values known from the xacro arguments and matches the rest.

Nodes are read with `armtool.yamlload.compose`: aliases are shared nodes, never expanded copies,
and a document whose aliases would expand it enormously is refused as invalid YAML.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:  # imported on use: PyYAML is not needed to lint a URDF
    import yaml

_TRUE = frozenset({"Y", "y", "yes", "Yes", "YES", "true", "True", "TRUE", "on", "On", "ON"})
_FALSE = frozenset({"N", "n", "no", "No", "NO", "false", "False", "FALSE", "off", "Off", "OFF"})
# strtoll(value, &end, 0) reading the whole text: decimal, 0x hexadecimal or 0 octal, optional sign.
_INT = re.compile(r"\s*[+-]?(?:0[xX][0-9a-fA-F]+|0[0-7]*|[1-9][0-9]*)")
# strtod reading the whole text: decimal or hexadecimal floats, inf/infinity, nan (any case).
_DOUBLE = re.compile(
    r"\s*[+-]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
    r"|0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?[0-9]+)?"
    r"|(?i:inf(?:inity)?|nan(?:\([0-9a-zA-Z_]*\))?))"
)
_YAML_SPECIAL_DOUBLES = frozenset(
    {".nan", ".NaN", ".NAN", *(s + w for s in ("", "+", "-") for w in (".inf", ".Inf", ".INF"))}
)


def scalar_kind(text: str, quoted: bool) -> str:
    """The ROS 2 parameter type of a YAML scalar: "bool", "int", "double" or "string" (rcl's
    get_value: quoted scalars are strings; then bool words, then a whole strtoll, then strtod)."""
    if quoted:
        return "string"
    if text in _TRUE or text in _FALSE:
        return "bool"
    if _INT.fullmatch(text):
        return "int"
    if text in _YAML_SPECIAL_DOUBLES or _DOUBLE.fullmatch(text):
        return "double"
    return "string"


class Scalar(NamedTuple):
    """A scalar as written, with its ROS 2 type and where it is (line and column from 1; start
    and end are character offsets into the file's text, for fixes)."""

    text: str
    kind: str  # "bool", "int", "double", "string"; "null" for a plain empty value (`key:` alone)
    line: int
    column: int
    start: int
    end: int
    tag: str | None = None  # a local tag such as xacro's `!degrees`

    def number(self) -> float | None:
        """The value as a float when it is an integer or a double, else None (`!degrees 90` is
        converted to radians, as xacro's YAML loader does)."""
        value = self._number()
        if value is not None and self.tag == "!degrees":
            return math.radians(value)
        return value

    def _number(self) -> float | None:
        if self.kind == "int":
            return float(int(self.text.strip(), 0) if not is_octal(self.text) else int(self.text.strip(), 8))
        if self.kind == "double":
            text = self.text.strip()
            if text in _YAML_SPECIAL_DOUBLES:
                text = text.replace(".", "")
            try:
                return float.fromhex(text) if "x" in text.lower() else float(text)
            except ValueError:
                return None
        return None

    def flag(self) -> bool | None:
        if self.kind != "bool":
            return None
        return self.text in _TRUE


def is_octal(text: str) -> bool:
    """`010`: an integer strtoll reads as octal (a leading 0 and more digits; sign and spaces allowed)."""
    digits = text.strip().lstrip("+-")
    return len(digits) > 1 and digits[0] == "0" and digits[1:].isdigit()


def parse(text: str) -> yaml.Node | None:
    """The document's node tree (None for an empty file). Raises yaml.YAMLError, also for a
    document that aliases blow up (armtool.yamlload's guard)."""
    from armtool.yamlload import compose

    return compose(text)


def load_document(path: Path, what: str) -> yaml.Node | None:
    """A MoveIt YAML file's nodes for a command, or an ArmtoolError naming `what`, the file and
    the line (not UTF-8, not YAML, nested too deeply)."""
    import yaml

    from armtool.errors import ArmtoolError
    from armtool.fileio import read_text

    text = read_text(path, what)
    try:
        return parse(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"{path}:{mark.line + 1}" if mark is not None else str(path)
        raise ArmtoolError(f"{what} is not valid YAML: {getattr(exc, 'problem', None) or exc}", where) from None
    except RecursionError:
        raise ArmtoolError(f"{what} is nested too deeply", str(path), "flatten it") from None


def as_scalar(node: yaml.Node | None) -> Scalar | None:
    """A scalar node as a Scalar; None for mappings, lists and missing values."""
    import yaml

    if not isinstance(node, yaml.ScalarNode):
        return None
    quoted = node.style in ("'", '"')
    if not quoted and node.value == "":
        kind = "null"
    elif node.tag == "tag:yaml.org,2002:str" and _explicit_str_tag(node):
        kind = "string"
    else:
        kind = scalar_kind(node.value, quoted)
    tag = node.tag if node.tag.startswith("!") and not node.tag.startswith("!!") else None
    return Scalar(
        node.value,
        kind,
        node.start_mark.line + 1,
        node.start_mark.column + 1,
        node.start_mark.index,
        node.end_mark.index,
        tag,
    )


def _explicit_str_tag(node: yaml.ScalarNode) -> bool:
    """`!!str 5`: rcl reads a scalar with the string tag as a string. A plain scalar carries the
    string tag without one only when it would not resolve to anything else."""
    import yaml

    if node.style is not None:
        return False
    implicit = yaml.SafeLoader("").resolve(yaml.ScalarNode, node.value, (True, False))  # type: ignore[no-untyped-call]
    return bool(implicit != "tag:yaml.org,2002:str")


def items(node: yaml.Node | None) -> Iterator[tuple[str, yaml.Node, yaml.Node]]:
    """(key text, key node, value node) of a mapping; nothing for other nodes."""
    import yaml

    if isinstance(node, yaml.MappingNode):
        for key, value in node.value:
            if isinstance(key, yaml.ScalarNode):
                yield str(key.value), key, value


def child(node: yaml.Node | None, key: str) -> yaml.Node | None:
    """The value of `key` in a mapping (the first one), or None."""
    return next((value for k, _, value in items(node) if k == key), None)


def key_node(node: yaml.Node | None, key: str) -> yaml.Node | None:
    """The key node of `key` in a mapping (where a finding about a missing value points)."""
    return next((knode for k, knode, _ in items(node) if k == key), None)


def is_mapping(node: yaml.Node | None) -> bool:
    import yaml

    return isinstance(node, yaml.MappingNode)


def sequence(node: yaml.Node | None) -> list[yaml.Node] | None:
    import yaml

    return list(node.value) if isinstance(node, yaml.SequenceNode) else None


def strings(node: yaml.Node | None) -> list[Scalar] | None:
    """A list of scalars (controller joints), or None when the node is not a list."""
    values = sequence(node)
    if values is None:
        return None
    return [s for s in (as_scalar(v) for v in values) if s is not None]


def shape(node: yaml.Node | None) -> str:
    """What a node is, for a message: 'a list', 'a mapping', 'nothing' or the scalar as written."""
    import yaml

    if isinstance(node, yaml.SequenceNode):
        return "a list"
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.ScalarNode):
        if node.tag == "tag:yaml.org,2002:null":
            return "nothing"
        text = node.value if len(node.value) <= 40 else node.value[:37] + "..."
        return repr(text)
    return "nothing"


def position(node: yaml.Node) -> tuple[int, int]:
    """(line, column) from 1."""
    return node.start_mark.line + 1, node.start_mark.column + 1


# ---- layouts -----------------------------------------------------------------------------


def parameter_nodes(root: yaml.Node | None) -> dict[str, yaml.Node] | None:
    """A ROS 2 parameter file's nodes: node name → its `ros__parameters` mapping. None when the
    file is not one (no top-level entry holds `ros__parameters`)."""
    out: dict[str, yaml.Node] = {}
    for name, _, value in items(root):
        params = child(value, "ros__parameters")
        if params is None:
            # A namespace level (`/my_ns: move_group: ros__parameters:`)
            for inner, _, inner_value in items(value):
                inner_params = child(inner_value, "ros__parameters")
                if inner_params is not None:
                    out.setdefault(f"{name}/{inner}", inner_params)
            continue
        out.setdefault(name, params)
    return out or None


class Section(NamedTuple):
    """Where a MoveIt file's settings are: the mapping, and whether the file is a ROS 2
    parameter file (node → ros__parameters); `node` names that node."""

    mapping: yaml.Node | None
    ros2_params: bool
    node: str | None


def moveit_section(root: yaml.Node | None, namespace: str) -> Section:
    """The settings of a MoveIt file for `namespace` (robot_description_planning for
    joint_limits.yaml and the Pilz limits, robot_description_kinematics for kinematics.yaml).

    ROS 2 parameter file: the first node whose parameters hold `namespace` (its value), else the
    first node's parameters. Flat file: `namespace`'s value when the file starts with it, else
    the whole document."""
    nodes = parameter_nodes(root)
    if nodes is not None:
        for name, params in nodes.items():
            inner = child(params, namespace)
            if inner is not None:
                return Section(inner, True, name)
        name, params = next(iter(nodes.items()))
        return Section(params, True, name)
    inner = child(root, namespace)
    if inner is not None and is_mapping(inner):
        return Section(inner, False, None)
    return Section(root, False, None)


# ---- launch substitutions in keys -------------------------------------------------------

_SUBSTITUTION = re.compile(r"\$\(\s*(var|arg)\s+([A-Za-z_][\w]*)\s*\)")


class NameRef(NamedTuple):
    """A name as written in a MoveIt file, with its launch substitutions worked out."""

    written: str
    resolved: str | None  # every substitution known (or none present)
    unknown: tuple[str, ...]  # substitutions without a known value (`$(var tf_prefix)`)
    pattern: re.Pattern[str] | None  # the name with the unknown substitutions as wildcards

    def matches(self, names: Iterable[str]) -> list[str]:
        """The names this key stands for: the resolved name when it exists; with unknown
        substitutions, the names that match the rest of the key, the one with every
        substitution empty first (a launch argument's usual default)."""
        pool = list(names)
        if self.resolved is not None:
            return [self.resolved] if self.resolved in pool else []
        assert self.pattern is not None
        found = [n for n in pool if self.pattern.fullmatch(n)]
        bare = _SUBSTITUTION.sub("", self.written)
        return sorted(found, key=lambda n: (n != bare, len(n), n))

    @property
    def bare(self) -> str:
        """The name for messages and did-you-mean: resolved, or without its unknown substitutions."""
        return self.resolved if self.resolved is not None else _SUBSTITUTION.sub("", self.written)

    def note(self) -> str:
        """How a key with unknown substitutions was read, for a message ('' when it had none)."""
        if not self.unknown:
            return ""
        subs = ", ".join(f"$(var {u})" for u in self.unknown)
        return f"{subs} unknown: matched by the rest of the name"


def name_ref(written: str, known: dict[str, str] | None = None) -> NameRef:
    """`$(var tf_prefix)joint_1` with tf_prefix known → `joint_1` with its value; unknown → a
    pattern that matches any prefix (the rest of the name must match exactly)."""
    known = known or {}
    if "$(" not in written:
        return NameRef(written, written, (), None)
    unknown: list[str] = []
    parts: list[str] = []
    last = 0
    for match in _SUBSTITUTION.finditer(written):
        parts.append(re.escape(written[last : match.start()]))
        name = match.group(2)
        if name in known:
            parts.append(re.escape(known[name]))
        else:
            unknown.append(name)
            parts.append(r"[\w/]*?")
        last = match.end()
    parts.append(re.escape(written[last:]))
    if not unknown:
        resolved = _SUBSTITUTION.sub(lambda m: known[m.group(2)], written)
        return NameRef(written, resolved, (), None)
    return NameRef(written, None, tuple(dict.fromkeys(unknown)), re.compile("".join(parts)))


# ---- which ROS --------------------------------------------------------------------------

_BUILDTOOL = re.compile(rb"<(?:buildtool_depend|build_type)>\s*([\w-]+)\s*</")
ROS_PACKAGE_LEVELS = 6  # directories looked at for the package.xml of a MoveIt file: its own and 5 above


def ros_version(start: Path) -> int | None:
    """1 for a catkin package, 2 for an ament one (package.xml's buildtool_depend or export
    build_type), None when no package.xml says. `start` is a file or a directory of the package
    (package.xml is looked for in ROS_PACKAGE_LEVELS directories at most)."""
    from armtool.fileio import read_regular
    from armtool.model.packages import package_root

    root = package_root(start if start.is_dir() else start.parent, ROS_PACKAGE_LEVELS)
    if root is None:
        return None
    try:
        data = read_regular(root / "package.xml", 1 << 20)
    except OSError:
        return None
    tools = {m.group(1).decode("ascii", "replace") for m in _BUILDTOOL.finditer(data)}
    if any(t.startswith("ament") for t in tools):
        return 2
    if "catkin" in tools:
        return 1
    return None
