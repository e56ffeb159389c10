"""Which URDF an SRDF describes, and which SRDF a kinematics.yaml belongs to.

As a user of the package would find them: MoveIt's `.setup_assistant` file (it names the URDF's
package, relative path and xacro arguments, and the SRDF), then the package's own layout
(`config/<robot>.urdf.xacro` beside `config/<robot>.srdf`, `urdf/` and `srdf/` beside `config/`).
Candidates are returned best first; the engine takes the first that loads as a robot with links
(a `<robot>.ros2_control.xacro` defines none and is never the URDF). When that one lacks names
the SRDF uses and other candidates were found beside it (`solo.srdf` beside `solo.urdf` and
`solo12.urdf`, both `<robot name="solo">`), the one that knows the most of them is taken: an
SRDF describes the URDF whose joints and links it names (`unknown_names`).
"""

from __future__ import annotations

import functools
import re
from pathlib import Path
from typing import NamedTuple

from lxml import etree

from armtool.fileio import read_regular
from armtool.model.packages import PackageResolver

URDF_SUFFIXES = (".urdf.xacro", ".urdf", ".xacro")
SRDF_SUFFIXES = (".srdf", ".srdf.xacro")


class Candidate(NamedTuple):
    path: Path
    xacro_args: dict[str, str]
    why: str  # how it was found, for messages ("named by .setup_assistant")


class SetupAssistant(NamedTuple):
    """What a MoveIt config package's .setup_assistant says (ROS 1 and ROS 2 key spellings)."""

    package_dir: Path
    urdf_package: str | None
    urdf_relative: str | None
    urdf_xacro_args: dict[str, str]
    srdf_relative: str | None


def srdf_names(root: etree._Element) -> tuple[set[str], set[str]]:
    """The joint and link names an SRDF refers to (groups, group states, chains, end effectors,
    passive joints, disabled collisions); joints its own <virtual_joint>s declare are left out."""
    joints: set[str] = set()
    links: set[str] = set()
    virtual: set[str] = set()
    for el in root.iter(etree.Element):
        tag = etree.QName(el).localname
        if tag == "virtual_joint":
            virtual.add(el.get("name", ""))
        elif tag in ("joint", "passive_joint"):
            joints.add(el.get("name", ""))
        elif tag == "link":
            links.add(el.get("name", ""))
        elif tag == "chain":
            links.update((el.get("base_link", ""), el.get("tip_link", "")))
        elif tag == "end_effector":
            links.add(el.get("parent_link", ""))
        elif tag == "disable_collisions":
            links.update((el.get("link1", ""), el.get("link2", "")))
    return joints - virtual - {""}, links - {""}


def unknown_names(wanted: tuple[set[str], set[str]], joint_names: set[str], link_names: set[str]) -> int:
    """How many of an SRDF's names (`srdf_names`) a URDF with these joints and links lacks."""
    joints, links = wanted
    return len(joints - joint_names) + len(links - link_names)


def parse_xacro_args(text: str) -> dict[str, str]:
    """`a:=1 b:=2` (as .setup_assistant and the xacro command line write them) as a dict."""
    out: dict[str, str] = {}
    for item in text.split():
        name, sep, value = item.partition(":=")
        if sep and name:
            out[name] = value
    return out


def _section(data: dict[object, object], name: str) -> dict[object, object]:
    for key, value in data.items():
        if str(key).lower() == name and isinstance(value, dict):
            return value
    return {}


def read_setup_assistant(start: Path) -> SetupAssistant | None:
    """The .setup_assistant of the MoveIt config package that holds `start` (a directory); None
    when there is none, or it cannot be read as YAML (an alias bomb included: it is read with
    armtool.yamlload's guard). Parsed once per content: every file of a package asks for it."""
    for directory in [start, *start.parents][:4]:
        marker = directory / ".setup_assistant"
        if marker.is_file():
            break
        if (directory / "package.xml").is_file():
            return None  # the package root, and no .setup_assistant in it
    else:
        return None
    try:
        text = marker.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None
    fields = _setup_fields(text)
    if fields is None:
        return None
    urdf_package, urdf_relative, urdf_xacro_args, srdf_relative = fields
    return SetupAssistant(directory, urdf_package, urdf_relative, dict(urdf_xacro_args), srdf_relative)


def present_instead(missing: Path) -> str | None:
    """The file beside a missing one that it most likely became: the same name with another
    ending (`wxai.srdf` -> `wxai.srdf.xacro`), else the closest name; None when none is close."""
    from armtool.suggest import closest

    try:
        names = sorted(p.name for p in missing.parent.iterdir() if p.is_file())
    except OSError:
        return None
    stem = missing.name.split(".")[0]
    grown = [n for n in names if n.startswith(missing.name + ".") or missing.name.startswith(n + ".")]
    if grown:
        return grown[0]
    same_stem = [n for n in names if n.split(".")[0] == stem and n.endswith(tuple(URDF_SUFFIXES + SRDF_SUFFIXES))]
    return same_stem[0] if len(same_stem) == 1 else closest(missing.name, names)


def setup_assistant_line(package_dir: Path, relative: str) -> int:
    """The line of a package's .setup_assistant that writes `relative` (1 when not found)."""
    try:
        lines = (package_dir / ".setup_assistant").read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        return 1
    return next((i for i, line in enumerate(lines, 1) if relative in line), 1)


@functools.lru_cache(maxsize=64)  # keyed on the text: a file changed since is parsed again
def _setup_fields(text: str) -> tuple[str | None, str | None, dict[str, str], str | None] | None:
    """The URDF's package, relative path and xacro arguments and the SRDF's relative path that a
    .setup_assistant's text names; None when it is not YAML or not a mapping."""
    import yaml

    from armtool.yamlload import safe_load

    try:
        data = safe_load(text)
    except yaml.YAMLError:
        return None
    if not isinstance(data, dict):
        return None
    config = _section(data, "moveit_setup_assistant_config")
    urdf, srdf = _section(config, "urdf"), _section(config, "srdf")
    args = urdf.get("xacro_args")
    return (
        str(urdf["package"]) if urdf.get("package") else None,
        str(urdf["relative_path"]) if urdf.get("relative_path") else None,
        parse_xacro_args(str(args)) if args else {},
        str(srdf["relative_path"]) if srdf.get("relative_path") else None,
    )


def _files(directory: Path, suffixes: tuple[str, ...]) -> list[Path]:
    try:
        return sorted(p for p in directory.iterdir() if p.is_file() and p.name.lower().endswith(suffixes))
    except OSError:
        return []


def _stem(path: Path) -> str:
    return path.name.split(".")[0]


def _urdf_rank(path: Path) -> int:
    """.urdf.xacro and .urdf name robots; a plain .xacro may be anything (macros, ros2_control)."""
    name = path.name.lower()
    if name.endswith((".urdf.xacro", ".urdf")):
        return 0
    return 1 if name.count(".") == 1 else 2  # `robot.xacro` before `robot.ros2_control.xacro`


def urdf_candidates(srdf: Path, robot_name: str | None, resolver: PackageResolver) -> list[Candidate]:
    """URDFs an SRDF may describe, best first."""
    out: list[Candidate] = []
    setup = read_setup_assistant(srdf.parent)
    if setup is not None and setup.urdf_package and setup.urdf_relative:
        pkg = resolver.find(setup.urdf_package, srdf.parent)
        if pkg is not None:
            out.append(Candidate(pkg / setup.urdf_relative, setup.urdf_xacro_args, "named by .setup_assistant"))
    here = srdf.parent
    places = [here, here.parent]
    try:
        places += sorted(p for p in here.parent.iterdir() if p.is_dir() and p != here and not p.name.startswith("."))
    except OSError:
        pass
    found: list[Path] = []
    for place in places:
        found += [p for p in _files(place, URDF_SUFFIXES) if not p.name.lower().endswith(".srdf.xacro")]
    ranked: list[Path] = []
    # The SRDF's own file name is the strongest hint (anymal-kinova.srdf says robot "anymal"),
    # then a file named like its robot, then a file that declares that robot name.
    for stem in dict.fromkeys(s for s in (_stem(srdf), robot_name) if s):
        ranked += sorted((p for p in found if _stem(p) == stem), key=_urdf_rank)
    if robot_name:
        pattern = re.compile(rb"<robot[^>]*\sname\s*=\s*[\"']" + re.escape(robot_name.encode()) + rb"[\"']")
        for cand in sorted(found, key=_urdf_rank):
            try:
                head = read_regular(cand, 4096)
            except OSError:
                continue
            if pattern.search(head):
                ranked.append(cand)
    same_dir = [c for c in found if c.parent == here and c.name.lower().endswith(".urdf")]
    if len(same_dir) == 1:
        ranked.append(same_dir[0])
    for path in dict.fromkeys(ranked):
        out.append(Candidate(path, {}, "found beside the SRDF"))
    return out


def srdf_candidates(kinematics: Path) -> list[list[Candidate]]:
    """SRDFs (or SRDF xacros) a kinematics.yaml may belong to, in tiers, nearest first: the one
    .setup_assistant names, those beside it, those in the package's srdf/ directory."""
    tiers: list[list[Candidate]] = []
    setup = read_setup_assistant(kinematics.parent)
    if setup is not None and setup.srdf_relative:
        tiers.append([Candidate(setup.package_dir / setup.srdf_relative, {}, "named by .setup_assistant")])
    for place in (kinematics.parent, kinematics.parent.parent / "srdf"):
        tiers.append([Candidate(path, {}, "found beside it") for path in _files(place, SRDF_SUFFIXES)])
    return tiers
