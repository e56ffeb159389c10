"""Include-only xacro fragments: files that another file of the package pulls in with
`<xacro:include>` and that do not stand alone (an end effector attached to a wrist link only the
includer defines; an SRDF fragment using an argument only the including SRDF declares). Linted on
its own such a file gives xacro errors, unknown links and false loops; its findings are those of
the file that includes it, expanded as a robot.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from armtool.fileio import read_regular

_INCLUDE = re.compile(rb"<xacro:include\s[^>]*?filename\s*=\s*[\"']([^\"']+)[\"']")
_SUFFIXES = (".xacro", ".urdf", ".srdf")
MAX_FILES = 400  # files of a package looked at for includes
MAX_DEPTH = 4  # includers of includers followed to the top
# A xacro that gives these on its own may be a fragment: a joint names a link it does not define,
# several roots or a loop; xacro failed on a name the includer defines (an argument, a property, a
# macro), not on a missing package or file, which fails through the includer too.
_GRAPH_CODES = frozenset({"U101", "U103"})
_UNDEFINED = ("undefined substitution argument", "is not defined", "unknown macro", "undefined")


def needs_includer(code: str, message: str) -> bool:
    """Whether a finding of a xacro linted alone may come from names only its includer defines."""
    if code in _GRAPH_CODES:
        return True
    return code == "X001" and any(word in message for word in _UNDEFINED)


def _scope(path: Path) -> Path:
    """Where includers are looked for: the ROS package that holds `path`, else its directory's parent."""
    from armtool.model.packages import package_root

    return package_root(path.parent, MAX_DEPTH) or path.parent.parent


def _names(filename: str, path: Path, includer: Path) -> bool:
    """Whether an include's filename (as written) is `path`."""
    filename = filename.replace("\\", "/")
    if filename.rsplit("/", 1)[-1] != path.name:
        return False
    if "$(" not in filename and "${" not in filename:
        return (includer.parent / filename).resolve() == path.resolve()
    tail = re.split(r"\$\([^)]*\)|\$\{[^}]*\}", filename)[-1].lstrip("/")  # after $(find pkg)/
    return path.resolve().as_posix().endswith("/" + tail) if tail else True


def _package_files(scope: Path) -> list[Path]:
    out: list[Path] = []
    for directory, dirs, files in os.walk(scope):
        dirs[:] = sorted(d for d in dirs if not d.startswith(".") and d not in ("build", "install", "log"))
        out += [Path(directory) / f for f in sorted(files) if f.lower().endswith(_SUFFIXES)]
        if len(out) >= MAX_FILES:
            break
    return out[:MAX_FILES]


def direct_includers(path: Path) -> list[Path]:
    """The package's files whose `<xacro:include>` names `path`."""
    out = []
    target = path.resolve()
    for cand in _package_files(_scope(path)):
        if cand.resolve() == target:
            continue
        try:
            data = read_regular(cand, 4 << 20)
        except OSError:
            continue
        if any(_names(m.group(1).decode("utf-8", "replace"), path, cand) for m in _INCLUDE.finditer(data)):
            out.append(cand)
    return out


def top_includer(path: Path) -> Path | None:
    """The file at the top of `path`'s include chain (one that no file of the package includes),
    or None when nothing includes `path`."""
    seen = {path.resolve()}
    current: Path | None = None
    frontier = path
    for _ in range(MAX_DEPTH):
        found = [p for p in direct_includers(frontier) if p.resolve() not in seen]
        if not found:
            break
        current = frontier = found[0]
        seen.add(current.resolve())
    return current
