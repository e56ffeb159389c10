from __future__ import annotations

import os
from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target
from armtool.model.packages import package_root


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

    Example:
    <mesh filename="package://arm_description/meshes/Forearm.STL"/>   (file is forearm.stl)

    Use instead:
    <mesh filename="package://arm_description/meshes/forearm.stl"/>
    """

    code, name, severity, target = "U501", "unresolved-mesh", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        home: str | None = None
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
                if home is None:  # the package (or directory) that holds the file
                    file_dir = ctx.path.resolve().parent
                    home = str(package_root(file_dir) or file_dir)
                # Both sides with symlinks resolved: a colcon --symlink-install tree links into src/.
                outside = os.path.commonpath([os.path.realpath(path), home]) != home
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
            yield ctx.finding(
                self,
                mesh,
                f"link '{link.get('name')}': mesh '{uri}' not found (looked for {path})",
                attr="filename",
                hint="fix the path; file names are case-sensitive",
            )
