"""Find ROS packages without ROS: `package://name/...` and `$(find name)`.

A package is named by `<name>` in its package.xml, as ROS names it, not by its directory
(`moveit_resources/panda_description` is `moveit_resources_panda_description`).
Search order: --package-path entries, ROS_PACKAGE_PATH, AMENT_PREFIX_PATH/<prefix>/share,
then around the file itself: first the cheap lookups (the file's own package, an enclosing
install-space directory share/<name> as ament's index finds it, a sibling that is the package),
then a scan of the tree around the file (a repository usually holds its own packages and their
siblings). `armtool lint` runs in every pre-commit, so a scan never enters an installed tree
(site-packages, a colcon install/ space) and reads each directory at most once per run.
Relative entries are taken from the working directory, as a shell would.
"""

from __future__ import annotations

import contextlib
import os
import re
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import NamedTuple

from armtool.fileio import read_regular

_NAME_RE = re.compile(rb"<name>\s*([^<\s]+)\s*</name>")
# Never descended into: version control, environments, build products, and installed trees
# (a colcon install/ space, a Python site-packages): packages there are found by the cheap
# share/<name> lookup, as ament's index finds them, and scanning them costs thousands of reads.
_SKIP = {
    ".git",
    ".hg",
    ".svn",
    ".venv",
    "venv",
    "node_modules",
    "__pycache__",
    "build",
    "install",
    "log",
    "site-packages",
    "dist-packages",
}
# Files that mark a directory as an install or devel space (colcon, catkin): never scanned.
_INSTALL_MARKERS = {"local_setup.sh", "local_setup.bash", "_local_setup_util_sh.py", ".catkin", "setup.sh"}
_IGNORE_MARKERS = {"COLCON_IGNORE", "CATKIN_IGNORE", "AMENT_IGNORE"}
# How deep below a search root packages are looked for (colcon searches without limit; a
# workspace's src/ rarely nests packages deeper than this).
_SCAN_DEPTH = 6
# How many directories above a file's own package the tree around it is searched.
_NEAR_LEVELS = 3
_MAX_DIRS = 20_000  # directories one scan may visit: a search that climbed too high stays bounded


def package_name(directory: Path, limit: int = 8192) -> str | None:
    """The `<name>` in directory/package.xml (in its first `limit` bytes), or None when there is
    no readable package.xml."""
    try:
        data = read_regular(directory / "package.xml", limit)
    except OSError:
        return None
    m = _NAME_RE.search(data)
    return m.group(1).decode("utf-8", "replace") if m else None


def package_root(path: Path, levels: int | None = None) -> Path | None:
    """The nearest directory at or above `path` that holds a package.xml (looking at `levels`
    directories at most: `path` and its parents)."""
    for directory in [path, *path.parents][:levels]:
        if (directory / "package.xml").is_file():
            return directory
    return None


def installed(package: Path) -> bool:
    """Whether a package directory lies in an installed tree: a prefix's share/<name> (ament's and
    catkin's install layout) or a Python site-packages (pip wheels such as example-robot-data ship
    share/<name> there). Its siblings are found by directory name, never by a scan."""
    return package.parent.name == "share" or any(p in ("site-packages", "dist-packages") for p in package.parts)


def _env_paths(var: str) -> list[Path]:
    return [Path(p).absolute() for p in os.environ.get(var, "").split(os.pathsep) if p]


class _Listing(NamedTuple):
    package: str | None  # the <name> of its package.xml: packages do not nest, nothing below counts
    children: tuple[str, ...]  # subdirectories to descend into, sorted
    stop: bool  # an ignored tree or an install/devel space


class _TreeScan:
    """Packages below directories, each directory read (listed, its package.xml opened) at most
    once per run: a tree scanned for one file, or one level up from it, is not walked again for
    the next file; indexes of complete subtrees are remembered too."""

    def __init__(self) -> None:
        self._listings: dict[Path, _Listing] = {}
        self._complete: dict[Path, dict[str, Path]] = {}  # subtrees scanned to the bottom

    def index(self, directory: Path, depth: int = _SCAN_DEPTH) -> dict[str, Path]:
        return self._scan(directory, depth, [_MAX_DIRS])[0]

    def _listing(self, directory: Path) -> _Listing:
        known = self._listings.get(directory)
        if known is None:
            try:
                with os.scandir(directory) as entries:
                    listed = [(e.name, e.is_dir()) for e in entries]
            except OSError:
                listed = []
            names = {name for name, _ in listed}
            package = package_name(directory) if "package.xml" in names else None
            children = sorted(n for n, is_dir in listed if is_dir and n not in _SKIP and not n.startswith("."))
            stop = bool(names & _IGNORE_MARKERS or names & _INSTALL_MARKERS)
            known = self._listings[directory] = _Listing(package, tuple(children), stop)
        return known

    def _scan(self, directory: Path, depth: int, budget: list[int]) -> tuple[dict[str, Path], bool]:
        """The packages below `directory` within `depth` levels, and whether that is all of them."""
        done = self._complete.get(directory)
        if done is not None:
            return done, True
        budget[0] -= 1
        if budget[0] < 0:
            return {}, False
        listing = self._listing(directory)
        if listing.package is not None:
            index = {listing.package: directory}
        elif listing.stop or not listing.children:
            index = {}
        elif depth == 0:
            return {}, False  # more below: a deeper scan from higher up may still look there
        else:
            index = {}
            complete = True
            for child in listing.children:
                found, child_complete = self._scan(directory / child, depth - 1, budget)
                complete = complete and child_complete
                for name, path in found.items():
                    index.setdefault(name, path)
            if not complete:
                return index, False
        self._complete[directory] = index
        return index, True


class PackageResolver:
    def __init__(self, package_paths: Sequence[Path] = ()) -> None:
        # absolute(): a relative --package-path means "from here", not "from the including file"
        self._roots = [Path(p).absolute() for p in package_paths] + _env_paths("ROS_PACKAGE_PATH")
        self._ament = [p / "share" for p in _env_paths("AMENT_PREFIX_PATH")]
        self._index: dict[str, Path] | None = None
        self._trees = _TreeScan()
        self._cache: dict[tuple[str, Path | None], Path | None] = {}
        self._resolved: dict[tuple[str, Path], tuple[str | None, str | None]] = {}
        self._files: dict[str, bool] = {}

    def _build_index(self) -> dict[str, Path]:
        index: dict[str, Path] = {}
        for root in self._roots:
            if root.is_dir():
                for name, path in self._trees.index(root).items():
                    index.setdefault(name, path)
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

    def _levels(self, own: Path | None) -> list[Path]:
        """The directories above the file's own package whose trees are scanned: up to the
        repository root, never the home or root directory, never into an installed tree."""
        levels: list[Path] = []
        if own is None or installed(own):
            return levels
        home = Path.home()
        directory = own
        while len(levels) < _NEAR_LEVELS and directory.parent != directory:
            directory = directory.parent
            if directory == home or directory.parent == directory:
                break
            levels.append(directory)
            if (directory / ".git").exists():
                break
        return levels

    def _find_near(self, name: str, near: Path) -> Path | None:
        """The package among the file's own package, its siblings and cousins (a repository or a
        workspace's src/ seen from one of its files). Cheap lookups first: the file's own package,
        an enclosing directory of that name, a sibling directory that is that package; the scan of
        the tree around the file only when they fail."""
        own = package_root(near)
        if own is not None and package_name(own) == name:
            return own
        ancestors = [near, *near.parents]
        for ancestor in ancestors:
            # An enclosing directory named like the package that is it by package.xml, or that is an
            # install space's share/<name> (ament's index goes by the directory name).
            if ancestor.name == name and (ancestor.parent.name == "share" or package_name(ancestor) == name):
                return ancestor
            candidate = ancestor / name
            if package_name(candidate) == name:
                return candidate
        for directory in self._levels(own):
            found = self._trees.index(directory).get(name)
            if found is not None:
                return found
        # A directory named like the package: an install space's share/<name> (found by directory
        # name, as ament's index does, whatever its package.xml says) or a bare checkout of meshes.
        for ancestor in ancestors:
            if ancestor.name == name:
                return ancestor
            candidate = ancestor / name
            if candidate.is_dir():
                return candidate
        return None

    def suggest(self, name: str, near: Path) -> tuple[str, Path | None] | None:
        """The package most likely meant by a missing `name`, and where it lives: looked for from
        the file outwards, the packages below each enclosing directory of the file's own package up
        to its repository (the nearest level with a close name wins), then everything the resolver sees
        (--package-path, ROS_PACKAGE_PATH, ament prefixes). A package of an unrelated repository
        that happens to sit beside this one comes only after the file's own repository."""
        from armtool.suggest import closest

        near = near.absolute()
        own = package_root(near)
        tiers = [dict(self._trees.index(directory)) for directory in self._levels(own)] or [{}]
        if own is not None:
            tiers[0].setdefault(package_name(own) or own.name, own)
        for tier in tiers:
            match = closest(name, tier)
            if match is not None:
                return match, tier[match]
        match = closest(name, self.known_names(near))
        return (match, self.find(match, near)) if match is not None else None

    def known_names(self, near: Path | None = None) -> list[str]:
        """Every package name this resolver can see from `near`: for did-you-mean hints (an error
        path, so the scans it needs are paid only when something is missing)."""
        if self._index is None:
            self._index = self._build_index()
        names = set(self._index)
        for share in self._ament:
            with contextlib.suppress(OSError):
                names.update(e.name for e in os.scandir(share) if e.is_dir())
        if near is not None:
            near = near.absolute()
            own = package_root(near)
            if own is not None:
                names.add(package_name(own) or own.name)
                if installed(own):  # an install space: its share/ holds the other packages
                    with contextlib.suppress(OSError):
                        names.update(e.name for e in os.scandir(own.parent) if e.is_dir())
            for directory in self._levels(own):
                names.update(self._trees.index(directory))
        return sorted(names)

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
