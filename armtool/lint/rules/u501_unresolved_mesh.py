from __future__ import annotations

import os
import re
from collections.abc import Iterator
from pathlib import Path

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target
from armtool.model.packages import package_root

# How far below the deepest existing folder of a missing mesh the closest file is looked for.
_SUGGEST_DEPTH = 4
_SUGGEST_MAX_FILES = 5000


class UnresolvedMesh(Rule):
    """
    What it does:
    Reports a <mesh filename> that points to no file: a relative or absolute path that
    does not exist, or a `package://pkg/...` path whose package was found but whose file
    was not. Packages are looked up in --package-path, ROS_PACKAGE_PATH,
    AMENT_PREFIX_PATH and the directories around the file.

    An absolute path (`file:///usr/...` or `/opt/...`) outside the package that holds the file
    names a file on one machine, not in the package: when it is missing here, that says as much
    about this machine as about the model, so it is a warning (the model loads its meshes only
    where that path exists).

    Why is this bad?
    RViz shows nothing, collision checking uses no geometry for the link (so the planner
    happily drives through it), and Gazebo refuses to spawn the model.

    When the file is missing, the existing file with the closest path is suggested: a misspelt or
    differently cased name, a renamed folder (looked for below the deepest folder of the path that
    exists, inside the package).

    Example:
    <mesh filename="package://arm_description/meshes/Forearm.STL"/>   (file is forearm.stl)

    Use instead:
    <mesh filename="package://arm_description/meshes/forearm.stl"/>
    """

    code, name, severity, target = "U501", "unresolved-mesh", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        home: Path | None = None  # the package (or directory) that holds the file, when first needed
        suggested: dict[str, list[str]] = {}  # folder -> files below it, listed once per file linted
        for mesh, uri, path, missing_package in ctx.meshes():
            if (
                uri
                and missing_package != ""
                and (path is None or missing_package is not None or ctx.resolver.is_file(path))
            ):
                continue  # found, or its package is U502's (most meshes): nothing to say
            link = ctx.mesh_link(mesh)
            if not uri:
                yield ctx.finding(
                    self,
                    mesh,
                    f"link '{link.get('name')}': <mesh> has no filename",
                    hint='add filename="package://..."',
                )
                continue
            if missing_package == "":
                # Pinocchio joins its package directories with the rest and finds such files; ROS's
                # resource_retriever looks up the package "" and fails.
                two_slashes = "package://" + uri[len("package:///") :].lstrip("/")
                found, missing = ctx.resolver.resolve(two_slashes, ctx.base_dir)
                if found is not None and missing is None and ctx.resolver.is_file(found):
                    hint = f'write filename="{two_slashes}" (two slashes; that file exists)'
                else:
                    hint = "write package://PACKAGE/path; ROS's resource_retriever cannot resolve package:///"
                yield ctx.finding(
                    self,
                    mesh,
                    f"link '{link.get('name')}': mesh '{uri}' names no package (three slashes after package:); "
                    "ROS's resource_retriever cannot resolve it",
                    attr="filename",
                    hint=hint,
                )
                continue
            if path is None or missing_package is not None or ctx.resolver.is_file(path):
                continue
            if uri.startswith("file://") or os.path.isabs(uri):
                home = home or _home(ctx)
                # Both sides with symlinks resolved: a colcon --symlink-install tree links into src/.
                outside = os.path.commonpath([os.path.realpath(path), str(home)]) != str(home)
            else:
                outside = False
            if outside:
                yield ctx.finding(
                    self,
                    mesh,
                    f"link '{link.get('name')}': mesh '{uri}' is an absolute path outside the package, "
                    f"and not on this machine",
                    attr="filename",
                    hint="ship the mesh in the package and name it package://PACKAGE/path",
                ).with_severity(Severity.WARNING)
                continue
            if not uri.startswith("package://"):
                home = home or _home(ctx)
            suggestion = self._closest(ctx, uri, path, suggested, home)
            if suggestion is not None:
                yield ctx.finding(
                    self,
                    mesh,
                    f"link '{link.get('name')}': mesh '{uri}' not found (looked for {path}; "
                    f"did you mean '{suggestion}'?)",
                    attr="filename",
                    hint=f'write filename="{suggestion}" (that file exists; file names are case-sensitive)',
                )
                continue
            yield ctx.finding(
                self,
                mesh,
                f"link '{link.get('name')}': mesh '{uri}' not found (looked for {path})",
                attr="filename",
                hint="fix the path; file names are case-sensitive",
            )

    @staticmethod
    def _closest(
        ctx: UrdfContext, uri: str, path: str, listings: dict[str, list[str]], home: Path | None
    ) -> str | None:
        """The existing file whose path is closest to the missing `path`, written the way `uri` is
        (package://, relative or absolute), or None. Looked for below the deepest existing folder
        of `path` that lies inside the package (a package:// URI's, else `home`, the linted file's)."""
        if uri.startswith("package://"):
            name = uri[len("package://") :].partition("/")[0]
            boundary = ctx.resolver.find(name, ctx.base_dir)
        else:
            boundary = home
        if boundary is None:
            return None
        bound = os.path.realpath(boundary)
        anchor = os.path.dirname(os.path.realpath(path))
        while not os.path.isdir(anchor):
            parent = os.path.dirname(anchor)
            if parent == anchor:
                return None
            anchor = parent
        if os.path.commonpath([anchor, bound]) != bound:
            return None  # the path leaves the package: nothing of ours to suggest
        files = listings.get(anchor)
        if files is None:
            files = listings[anchor] = _files_below(anchor)
        wanted = os.path.relpath(os.path.realpath(path), anchor)
        match = closest_path(wanted, files)
        if match is None:
            return None
        found = os.path.join(anchor, match)
        if uri.startswith("package://"):
            return f"package://{name}/" + os.path.relpath(found, bound).replace(os.sep, "/")
        if uri.startswith("file://"):
            return "file://" + found
        if os.path.isabs(uri):
            return found
        return os.path.relpath(found, os.path.realpath(ctx.base_dir)).replace(os.sep, "/")


def _home(ctx: UrdfContext) -> Path:
    """The package that holds the linted file (or, in none, its directory): where a mesh named
    by a relative or absolute path belongs."""
    file_dir = ctx.path.resolve().parent
    return package_root(file_dir) or file_dir


def _similar_names(a: str, b: str) -> float:
    """How alike two file names are (0..1), for a misspelling: the same but for case or separators
    is 1; otherwise difflib's ratio of the stems when their numbers agree (link1 is not link2) and
    their extensions match, else 0."""
    import difflib

    def squeeze(name: str) -> str:
        return re.sub(r"[\s_.-]", "", name.lower())

    (stem_a, ext_a), (stem_b, ext_b) = os.path.splitext(a), os.path.splitext(b)
    if squeeze(stem_a) == squeeze(stem_b):
        return 1.0 if ext_a.lower() == ext_b.lower() else 0.9  # forearm.stl for forearm.dae: converted
    if ext_a.lower() != ext_b.lower() or re.findall(r"\d+", stem_a) != re.findall(r"\d+", stem_b):
        return 0.0
    return difflib.SequenceMatcher(None, stem_a.lower(), stem_b.lower()).ratio()


def closest_path(wanted: str, files: list[str]) -> str | None:
    """The file among `files` (paths relative to one folder) that `wanted` most likely meant: the
    same file name in a folder of another name (a renamed folder: the closest folder name wins), or
    in the same folder a name that differs by case or a small misspelling. None when nothing is
    that close: a hint must not send the user to an unrelated mesh."""
    import difflib

    folder, name = os.path.split(wanted)
    best: tuple[float, str] | None = None
    for candidate in files:
        cand_folder, cand_name = os.path.split(candidate)
        if cand_name.lower() == name.lower():
            score = 1.0 + difflib.SequenceMatcher(None, folder.lower(), cand_folder.lower()).ratio()
        elif cand_folder.lower() == folder.lower():
            score = _similar_names(name, cand_name)
            if score < 0.8:
                continue
        else:
            continue
        if best is None or score > best[0]:
            best = (score, candidate)
    return best[1] if best else None


def _files_below(directory: str) -> list[str]:
    """Paths (relative to `directory`) of the files below it, a few levels deep and bounded in number."""
    out: list[str] = []
    stack = [("", 0)]
    while stack and len(out) < _SUGGEST_MAX_FILES:
        relative, depth = stack.pop()
        try:
            with os.scandir(os.path.join(directory, relative)) as entries:
                for entry in entries:
                    if entry.name.startswith("."):
                        continue
                    child = os.path.join(relative, entry.name) if relative else entry.name
                    if entry.is_file():
                        out.append(child)
                    elif entry.is_dir() and depth < _SUGGEST_DEPTH:
                        stack.append((child, depth + 1))
        except OSError:
            continue
    return out
