"""Find ROS packages without ROS: `package://name/...` and `$(find name)`.

A package is named by `<name>` in its package.xml, as ROS names it, not by its directory
(`moveit_resources/panda_description` is `moveit_resources_panda_description`).
Search order: --package-path entries, ROS_PACKAGE_PATH, AMENT_PREFIX_PATH/<prefix>/share,
then the tree around the file itself (a repository usually holds its own packages and
their siblings). Relative entries are taken from the working directory, as a shell would.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Sequence
from pathlib import Path

from armtool.fileio import read_regular

_NAME_RE = re.compile(rb"<name>\s*([^<\s]+)\s*</name>")
_SKIP = {".git", ".hg", ".svn", ".venv", "venv", "node_modules", "__pycache__", "build", "install", "log"}
# How deep below a search root packages are looked for (colcon searches without limit; a
# workspace's src/ rarely nests packages deeper than this).
_SCAN_DEPTH = 6
# How many directories above a file's own package the tree around it is searched.
_NEAR_LEVELS = 3


def package_name(directory: Path) -> str | None:
    """The `<name>` in directory/package.xml, or None when there is no readable package.xml."""
    try:
        data = read_regular(directory / "package.xml", 8192)
    except OSError:
        return None
    m = _NAME_RE.search(data)
    return m.group(1).decode("utf-8", "replace") if m else None


def package_root(path: Path) -> Path | None:
    """The nearest directory at or above `path` that holds a package.xml."""
    for directory in [path, *path.parents]:
        if (directory / "package.xml").is_file():
            return directory
    return None


def _env_paths(var: str) -> list[Path]:
    return [Path(p).absolute() for p in os.environ.get(var, "").split(os.pathsep) if p]


_MAX_DIRS = 20_000  # directories one scan may visit: a search that climbed too high stays bounded


def _scan(directory: Path, depth: int, index: dict[str, Path], budget: list[int] | None = None) -> None:
    """Add every package below `directory` to `index` (packages do not nest: stop at a package.xml)."""
    budget = [_MAX_DIRS] if budget is None else budget
    budget[0] -= 1
    if budget[0] < 0:
        return
    name = package_name(directory)
    if name is not None:
        index.setdefault(name, directory)
        return
    if depth == 0:
        return
    try:
        with os.scandir(directory) as entries:
            children = sorted(
                e.name for e in entries if e.is_dir() and e.name not in _SKIP and not e.name.startswith(".")
            )
    except OSError:
        return
    names = set(children)
    if "COLCON_IGNORE" in names or "CATKIN_IGNORE" in names or "AMENT_IGNORE" in names:
        return
    for child in children:
        _scan(directory / child, depth - 1, index, budget)


class PackageResolver:
    def __init__(self, package_paths: Sequence[Path] = ()) -> None:
        # absolute(): a relative --package-path means "from here", not "from the including file"
        self._roots = [Path(p).absolute() for p in package_paths] + _env_paths("ROS_PACKAGE_PATH")
        self._ament = [p / "share" for p in _env_paths("AMENT_PREFIX_PATH")]
        self._index: dict[str, Path] | None = None
        self._near_index: dict[Path, dict[str, Path]] = {}
        self._cache: dict[tuple[str, Path | None], Path | None] = {}
        self._resolved: dict[tuple[str, Path], tuple[str | None, str | None]] = {}
        self._files: dict[str, bool] = {}

    def _build_index(self) -> dict[str, Path]:
        index: dict[str, Path] = {}
        for root in self._roots:
            if root.is_dir():
                _scan(root, _SCAN_DEPTH, index)
        return index

    def _tree_index(self, directory: Path) -> dict[str, Path]:
        index = self._near_index.get(directory)
        if index is None:
            index = self._near_index[directory] = {}
            _scan(directory, _SCAN_DEPTH, index)
        return index

    def find(self, name: str, near: Path | None = None) -> Path | None:
        """The directory of package `name`, or None."""
        key = (name, near)
        if key in self._cache:
            return self._cache[key]
        found = self._find(name, near)
        self._cache[key] = found
        return found

    def _find(self, name: str, near: Path | None) -> Path | None:
        if self._index is None:
            self._index = self._build_index()
        if name in self._index:
            return self._index[name]
        for root in self._roots:
            if root.name == name and root.is_dir() and package_name(root) in (None, name):
                return root
        for share in self._ament:
            if (share / name).is_dir():
                return share / name
        if near is not None:
            return self._find_near(name, near.absolute())
        return None

    def _find_near(self, name: str, near: Path) -> Path | None:
        """The package among the file's own package, its siblings and cousins (a repository or a
        workspace's src/ seen from one of its files)."""
        own = package_root(near)
        if own is not None and package_name(own) == name:
            return own
        levels: list[Path] = []
        if own is not None:
            # up from the package, to the repository's root at most; never the home or root directory
            home = Path.home()
            directory = own
            while len(levels) < _NEAR_LEVELS and directory.parent != directory:
                directory = directory.parent
                if directory == home or directory.parent == directory:
                    break
                levels.append(directory)
                if (directory / ".git").exists():
                    break
        for directory in levels:
            found = self._tree_index(directory).get(name)
            if found is not None:
                return found
        # A directory named like the package: an install space's share/<name> (found by directory
        # name, as ament's index does, whatever its package.xml says) or a bare checkout of meshes.
        for ancestor in [near, *near.parents]:
            if ancestor.name == name:
                return ancestor
            candidate = ancestor / name
            if candidate.is_dir():
                return candidate
        return None

    def resolve(self, uri: str, base_dir: Path) -> tuple[str | None, str | None]:
        """Resolve a mesh filename. Returns (path or None, name of a package that could not be found;
        "" when the URI names no package at all). Paths are strings: thousands of meshes are resolved
        per repository run, and pathlib objects cost several times more than os.path."""
        key = (uri, base_dir)
        found = self._resolved.get(key)
        if found is None:
            found = self._resolved[key] = self._resolve(uri, base_dir)
        return found

    def is_file(self, path: str) -> bool:
        """os.path.isfile, remembered: the same mesh is named by visual and collision, file after file."""
        known = self._files.get(path)
        if known is None:
            known = self._files[path] = os.path.isfile(path)
        return known

    def _resolve(self, uri: str, base_dir: Path) -> tuple[str | None, str | None]:
        if uri.startswith("package://"):
            rest = uri[len("package://") :]
            name, _, relative = rest.partition("/")
            if not name:
                return None, ""  # package:///x: no package name, ROS cannot resolve it
            pkg = self.find(name, base_dir)
            if pkg is None:
                return None, name
            return os.path.join(pkg, relative), None
        if uri.startswith("file://"):
            return uri[len("file://") :], None
        return os.path.join(base_dir, uri), None  # an absolute uri stays as it is

    @property
    def searched(self) -> Iterable[Path]:
        return [*self._roots, *self._ament]
