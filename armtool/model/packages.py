"""Find ROS packages without ROS: `package://name/...` and `$(find name)`.

Search order: --package-path entries, ROS_PACKAGE_PATH, AMENT_PREFIX_PATH/<prefix>/share,
then the directories around the file itself (a repository usually holds its own package).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Sequence
from pathlib import Path

_NAME_RE = re.compile(rb"<name>\s*([^<\s]+)\s*</name>")
_SCAN_DEPTH = 3


def _package_name(directory: Path) -> str | None:
    try:
        data = (directory / "package.xml").read_bytes()[:4096]
    except OSError:
        return None
    m = _NAME_RE.search(data)
    return m.group(1).decode("utf-8", "replace") if m else None


def _env_paths(var: str) -> list[Path]:
    return [Path(p) for p in os.environ.get(var, "").split(os.pathsep) if p]


class PackageResolver:
    def __init__(self, package_paths: Sequence[Path] = ()) -> None:
        self._roots = list(package_paths) + _env_paths("ROS_PACKAGE_PATH")
        self._ament = [p / "share" for p in _env_paths("AMENT_PREFIX_PATH")]
        self._index: dict[str, Path] | None = None
        self._cache: dict[tuple[str, Path | None], Path | None] = {}
        self._resolved: dict[tuple[str, Path], tuple[str | None, str | None]] = {}
        self._files: dict[str, bool] = {}

    def _build_index(self) -> dict[str, Path]:
        index: dict[str, Path] = {}

        def scan(directory: Path, depth: int) -> None:
            name = _package_name(directory)
            if name is not None:
                index.setdefault(name, directory)
                return
            if depth == 0:
                return
            try:
                children = sorted(p for p in directory.iterdir() if p.is_dir() and not p.name.startswith("."))
            except OSError:
                return
            for child in children:
                scan(child, depth - 1)

        for root in self._roots:
            if root.is_dir():
                scan(root, _SCAN_DEPTH)
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
            if root.name == name and root.is_dir():
                return root
        for share in self._ament:
            if (share / name).is_dir():
                return share / name
        if near is not None:
            for ancestor in [near, *near.parents]:
                if ancestor.name == name or _package_name(ancestor) == name:
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
