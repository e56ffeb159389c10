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


def fit(
    arg_sets: Sequence[dict[str, str]], load_with: LoadWith, srdf: Path, root: etree._Element, urdf: UrdfContext
) -> tuple[UrdfContext | None, str | None]:
    """The URDF to check the SRDF against, and the S003 message when the SRDF was written for
    another argument set (or another robot). The URDF unchanged and None when it fits."""
    from armtool.lint.pairing import srdf_names, unknown_names

    wanted = srdf_names(root)
    total = len(wanted[0]) + len(wanted[1])
    missing = unknown_names(wanted, urdf.joint_names, urdf.link_names)
    if missing == 0:
        return urdf, None
    unknown = sorted((wanted[0] - urdf.joint_names) | (wanted[1] - urdf.link_names))
    examples = ", ".join(unknown[:4]) + (", ..." if len(unknown) > 4 else "")
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
    if missing >= OTHER_ROBOT_MIN and missing >= OTHER_ROBOT_SHARE * total:
        return None, (
            f"the SRDF does not describe {urdf.path.name}: {missing} of the {total} joint and link names it uses "
            f"({examples}) are not in it, and no argument value written in its sources changes that; "
            "names and limits were not checked"
        )
    return urdf, None
