"""An SRDF written for another argument set of its URDF's xacro (a 6-DOF SRDF against the default
7-DOF expansion): one mismatch finding instead of one S101/S108 per name of the other variant.
When the SRDF names something the expansion lacks and another argument value written down for
the xacro gives an expansion with every one of its names, the SRDF was written for that variant:
it is checked against it. Names no variant explains stay per-name findings (typos), unless most
of them are unknown (another robot).

Which values to try is read from where they are written down: the configuration's argument
sets for the file, the `.setup_assistant` of every MoveIt config package beside this one that
names the same URDF (Kinova's 6-DOF and 7-DOF configs, `dof:=6` and `dof:=7`), and the literals
the xacro sources compare an argument with (`'$(arg robot_type)' == 'lite'`, `${dof == 6}`).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from lxml import etree

    from armtool.lint.context import UrdfContext

    # The linter's expansion of a xacro with exactly these arguments (None when it fails).
    LoadWith = Callable[[Path, dict[str, str]], UrdfContext | None]

OTHER_ROBOT_SHARE = 0.5  # unknown with no argument to explain it: written for another robot ...
OTHER_ROBOT_MIN = 5  # ... when that is also many names (two typos in a four-name SRDF are typos)
MAX_TRIES = 6  # expansions tried, at most
_ARG = re.compile(r"<xacro:arg\s+name=\"([\w-]+)\"")
_FLIPPED = {"true": "false", "false": "true", "1": "0", "0": "1"}


def _compared_values(text: str, name: str) -> Iterator[str]:
    """Literals an argument (or a property or parameter of the same name) is compared with."""
    arg = rf"(?:\$\(arg\s+{re.escape(name)}\)|\b{re.escape(name)}\b)"
    value = r"'?\"?([\w.-]+)'?\"?"
    for pattern in (rf"{arg}'?\s*==\s*{value}", rf"{value}\s*==\s*'?{arg}"):
        for match in re.finditer(pattern, text):
            yield match.group(1)


def candidates(arg_sets: Sequence[dict[str, str]], srdf: Path, urdf: UrdfContext) -> list[dict[str, str]]:
    """Argument changes to try, each as name -> value, nearest source first; `arg_sets` are the
    configuration's argument sets for the URDF."""
    from armtool.lint.pairing import read_setup_assistant

    current = urdf.xacro_args
    out: list[dict[str, str]] = []

    def add(change: dict[str, str]) -> None:
        change = {k: v for k, v in change.items() if current.get(k) != v}
        if change and change not in out:
            out.append(change)

    for args in arg_sets:
        add(args)
    setup = read_setup_assistant(srdf.parent)
    if setup is not None:
        try:
            siblings = sorted(p for p in setup.package_dir.parent.iterdir() if p.is_dir())
        except OSError:
            siblings = []
        for sibling in siblings:
            other = read_setup_assistant(sibling) if (sibling / ".setup_assistant").is_file() else None
            if other is not None and other.urdf_relative and urdf.path.as_posix().endswith(other.urdf_relative):
                add(other.urdf_xacro_args)
    for change in compared_arguments(urdf.path, urdf.source_files):
        add(change)
    return out


def compared_arguments(top: Path, sources: Sequence[Path] = ()) -> list[dict[str, str]]:
    """One-argument changes a xacro's sources write down: each flag `<xacro:arg>` of `top` (default
    true or false) the other way, and each argument with each literal it is compared with in `top`
    or the files it includes (`sources`)."""
    try:
        text = top.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return []
    names = list(dict.fromkeys(_ARG.findall(text)))
    texts = [text]
    for path in sources:
        if path != top:
            try:
                texts.append(path.read_text(encoding="utf-8", errors="replace"))
            except OSError:
                continue
    from armtool.moveit.substitutions import xacro_arg_defaults

    out: list[dict[str, str]] = []
    for name, default in xacro_arg_defaults(top).items():  # a flag (`<xacro:if value="$(arg hand)">`)
        flipped = _FLIPPED.get(default.lower())
        if flipped is not None:
            out.append({name: flipped})
    for name in names:
        for source in texts:
            for value in _compared_values(source, name):
                if {name: value} not in out:
                    out.append({name: value})
    return out


def variant_folder(srdf: Path) -> str | None:
    """The name of the folder an SRDF sits in when that folder is one of several variant folders
    (config/6dof/ beside config/7dof/, each with an SRDF), else None."""
    here = srdf.parent
    try:
        siblings = [p for p in here.parent.iterdir() if p.is_dir() and p != here and not p.name.startswith(".")]
    except OSError:
        return None
    for sibling in siblings:
        try:
            if any(f.name.lower().endswith((".srdf", ".srdf.xacro")) for f in sibling.iterdir()):
                return here.name
        except OSError:
            continue
    return None


def folder_arguments(folder: str, urdf: UrdfContext) -> list[dict[str, str]]:
    """Argument values a variant folder's name gives (`6dof` -> dof:=6, `lite6` -> robot_type:=lite):
    a value the xacro's sources write for an argument (compared with, or a number where the
    default is a number) that the folder name holds as a word or a number."""
    from armtool.moveit.substitutions import xacro_arg_defaults

    out: list[dict[str, str]] = []
    pairs = [next(iter(c.items())) for c in compared_arguments(urdf.path, urdf.source_files)]
    numbers = re.findall(r"\d+", folder)
    for name, default in xacro_arg_defaults(urdf.path).items():
        if re.fullmatch(r"\d+", default):
            pairs += [(name, n) for n in numbers if n != default]
    for name, value in pairs:
        if re.search(rf"(?<![A-Za-z0-9]){re.escape(value)}|{re.escape(value)}(?![A-Za-z0-9])", folder):
            if {name: value} not in out and urdf.xacro_args.get(name) != value:
                out.append({name: value})
    return out


def fit(
    arg_sets: Sequence[dict[str, str]], load_with: LoadWith, srdf: Path, root: etree._Element, urdf: UrdfContext
) -> tuple[UrdfContext | None, str | None]:
    """The URDF to check the SRDF against, and the S003 message when the SRDF was written for
    another argument set (or another robot), or could not be paired with its variant. The URDF
    unchanged and None when it fits. A variant folder's name (config/6dof/) is tried first; when
    it names a variant no argument value gives, names are not checked: they belong to a variant
    armtool could not expand."""
    from armtool.lint.pairing import srdf_names, unknown_names

    wanted = srdf_names(root)
    total = len(wanted[0]) + len(wanted[1])
    missing = unknown_names(wanted, urdf.joint_names, urdf.link_names)
    if missing == 0:
        return urdf, None
    unknown = sorted((wanted[0] - urdf.joint_names) | (wanted[1] - urdf.link_names))
    examples = ", ".join(unknown[:4]) + (", ..." if len(unknown) > 4 else "")
    folder = variant_folder(srdf) if urdf.from_xacro else None
    if folder is not None:
        best: tuple[int, UrdfContext] | None = None
        for change in folder_arguments(folder, urdf)[:MAX_TRIES]:
            other = load_with(urdf.path, {**urdf.xacro_args, **change})
            left = unknown_names(wanted, other.joint_names, other.link_names) if other is not None else missing
            if other is not None and left < missing and (best is None or left < best[0]):
                best = (left, other)
        if best is not None:
            return best[1], None  # the folder says which variant: checked against it (typos still per name)
    if urdf.from_xacro:
        for change in candidates(arg_sets, srdf, urdf)[:MAX_TRIES]:
            other = load_with(urdf.path, {**urdf.xacro_args, **change})
            if other is not None and unknown_names(wanted, other.joint_names, other.link_names) == 0:
                flags = " ".join(f"--xacro-arg {k}:={v}" for k, v in change.items())
                return other, (
                    f"the SRDF was written for another variant of {urdf.path.name}: {missing} of the {total} joint "
                    f"and link names it uses ({examples}) {'is' if missing == 1 else 'are'} not in the expansion "
                    f"armtool was given, and all are with {flags}; checked against that expansion"
                )
    if folder is not None:
        return None, (
            f"could not be checked: it sits in the variant folder '{folder}', and no argument value written for "
            f"{urdf.path.name} gives the {missing} joint and link names it uses that the expansion lacks ({examples}); "
            "pass --xacro-arg NAME:=VALUE for this variant (or --urdf for its URDF)"
        )
    if missing >= OTHER_ROBOT_MIN and missing >= OTHER_ROBOT_SHARE * total:
        return None, (
            f"the SRDF does not describe {urdf.path.name}: {missing} of the {total} joint and link names it uses "
            f"({examples}) are not in it, and no argument value written in its sources changes that; "
            "names and limits were not checked"
        )
    return urdf, None
