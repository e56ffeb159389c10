"""What rules see of a URDF: links, joints and the tree, plus `finding()` to report at the right place."""

from __future__ import annotations

import math
from collections import defaultdict
from pathlib import Path
from typing import Any, NamedTuple

from lxml import etree

from armtool.lint.finding import Finding
from armtool.lint.locate import Locator, display_path
from armtool.lint.numbers import all_plain, numeric_texts, numeric_values, parse_floats
from armtool.lint.rule import Rule, Target
from armtool.model.display import note_suffix
from armtool.model.packages import PackageResolver

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
_MOVING = frozenset(JOINT_TYPES) - {"fixed"}


_XPATHS: dict[str, etree.XPath] = {}


def _compiled_xpath(expr: str) -> etree.XPath:
    compiled = _XPATHS.get(expr)
    if compiled is None:
        compiled = _XPATHS[expr] = etree.XPath(expr, smart_strings=False)
    return compiled


class JointView(NamedTuple):
    el: etree._Element
    name: str | None
    type: str | None
    parent: str | None
    child: str | None
    # The first child element of each kind (what el.find(tag) returns), looked up once per file:
    # rules ask for them joint after joint, and each find() costs several times a dict lookup.
    parent_el: etree._Element | None = None
    child_el: etree._Element | None = None
    limit_el: etree._Element | None = None
    axis_el: etree._Element | None = None
    mimic_el: etree._Element | None = None
    # The <limit>'s attributes (one lxml call; several rules read them): limit_el.get(k) is limits.get(k).
    limits: dict[str, str] = {}  # noqa: RUF012 (read-only; every view with a <limit> gets its own)

    @property
    def moves(self) -> bool:
        return self.type in _MOVING

    def limit(self) -> etree._Element | None:
        return self.limit_el


class FileContext:
    """Shared by every file kind: the file, where elements are, and how to build a Finding."""

    target: Target

    def __init__(self, path: Path, locator: Locator) -> None:
        self.path = path
        self.locator = locator

    def finding(
        self,
        rule: Rule | type[Rule],
        el: etree._Element,
        message: str,
        *,
        attr: str | None = None,
        hint: str | None = None,
        fix_value: str | None = None,
    ) -> Finding:
        place = self.locator.place(el, attr)
        if place.note:
            message += note_suffix(place.note)
        edit = self.locator.edit(el, attr, fix_value) if (attr and fix_value is not None) else None
        shown = self.locator.display
        return Finding(
            shown(place.path),
            place.line,
            place.column,
            rule.code,
            rule.name,
            rule.severity,
            message,
            hint,
            edit,
            tuple((shown(s.path), s.line) for s in place.related) if place.related else (),
        )

    def finding_at(
        self, rule: Rule | type[Rule], line: int, column: int, message: str, *, hint: str | None = None
    ) -> Finding:
        """A finding at a known line and column of this file (for YAML, which has no elements)."""
        return Finding(
            path=display_path(self.path),
            line=line,
            column=column,
            code=rule.code,
            name=rule.name,
            severity=rule.severity,
            message=message,
            hint=hint,
        )


class UrdfContext(FileContext):
    target = Target.URDF

    def __init__(
        self,
        path: Path,
        root: etree._Element,
        locator: Locator,
        resolver: PackageResolver,
        *,
        from_xacro: bool = False,
        raw: bytes | None = None,
    ) -> None:
        super().__init__(path, locator)
        self.root = root
        self.raw = raw  # the file's bytes, for whole-text prechecks (None after xacro)
        self.resolver = resolver
        self.from_xacro = from_xacro
        self.xacro_args: dict[str, str] = {}  # what a xacro was expanded with
        self.source_files: tuple[Path, ...] = ()  # the files its expansion read
        self.links: list[etree._Element] = []
        self.joints: list[JointView] = []
        self.transmissions: list[etree._Element] = []
        # False when a <link> or <joint> is in an XML namespace: then `link/...` XPaths miss it.
        self.plain_tags = True
        # One pass over the top level and over each joint's children; every rule reads the result.
        links, joints = self.links, self.joints
        for el in root:
            tag = el.tag
            if tag.__class__ is not str:
                continue  # comment or processing instruction
            if tag[0] == "{":
                tag = tag.rsplit("}", 1)[-1]
                if tag in ("link", "joint"):
                    self.plain_tags = False
            if tag == "link":
                links.append(el)
            elif tag == "transmission":
                self.transmissions.append(el)
            elif tag == "joint":
                kids: dict[object, etree._Element] = {}
                for c in el:
                    if c.tag not in kids:
                        kids[c.tag] = c
                parent, child, limit = kids.get("parent"), kids.get("child"), kids.get("limit")
                attrib = el.attrib
                joints.append(
                    JointView(
                        el,
                        attrib.get("name"),
                        attrib.get("type"),
                        parent.get("link") if parent is not None else None,
                        child.get("link") if child is not None else None,
                        parent,
                        child,
                        limit,
                        kids.get("axis"),
                        kids.get("mimic"),
                        dict(limit.items()) if limit is not None else {},
                    )
                )
        self.link_name: dict[etree._Element, str | None] = {el: el.get("name") for el in links}  # link.get("name")
        self._link_by_name: dict[str, etree._Element] = {}
        for el, name in self.link_name.items():
            self._link_by_name.setdefault(name or "", el)
        self._joint_by_name: dict[str, JointView] = {}
        for j in self.joints:
            self._joint_by_name.setdefault(j.name or "", j)
        self.link_names = {n for n in self._link_by_name if n}
        self.joint_names = {n for n in self._joint_by_name if n}
        self._numbers: list[tuple[etree._Element, str, str, int, list[float] | None]] | None = None
        self._meshes: list[tuple[etree._Element, str, str | None, str | None]] | None = None
        self._inertias: (
            list[tuple[etree._Element, etree._Element, tuple[float, ...], tuple[float, float, float]]] | None
        ) = None
        self._inertial_of: dict[etree._Element, etree._Element] | None = None
        self._texts: dict[int, set[str]] | None = None
        self._plain: bool | None = None
        self.joints_by_child: dict[str, list[JointView]] = defaultdict(list)
        self.joints_by_parent: dict[str, list[JointView]] = defaultdict(list)
        for j in self.joints:
            if j.child is not None:
                self.joints_by_child[j.child].append(j)
            if j.parent is not None:
                self.joints_by_parent[j.parent].append(j)

    def xpath(self, expr: str, **variables: str) -> Any:
        """Run an XPath query on the file (compiled once per process; attribute values come back as str).

        Most files have no problem a given rule looks for: one query in libxml2 tells a rule that
        nothing needs a closer look, faster than visiting each element from Python.
        """
        return _compiled_xpath(expr)(self.root, **variables)

    def below_links(self, path: str) -> str:
        """An XPath for `path` below every link (`link/path`; namespaced links too when there are any)."""
        return ("link/" if self.plain_tags else "*[local-name()='link']/") + path

    def inertial_of(self, link: etree._Element) -> etree._Element | None:
        """The link's first <inertial> (what link.find("inertial") returns), indexed once per file."""
        index = self._inertial_of
        if index is None:
            index = self._inertial_of = {}
            for inertial in reversed(self.xpath(self.below_links("inertial"))):
                index[inertial.getparent()] = inertial
        return index.get(link)

    def numeric_values(self) -> list[tuple[etree._Element, str, str, int, list[float] | None]]:
        """(element, attribute, raw text, expected count, parsed values or None), read once per file."""
        if self._numbers is None:
            self._numbers = numeric_values(self.root)
        return self._numbers

    def numeric_texts(self) -> dict[int, set[str]]:
        """{expected count: distinct texts}, a superset of numeric_values()'s texts, once per file."""
        if self._texts is None:
            self._texts = numeric_texts(self.root)
        return self._texts

    def numbers_plain(self) -> bool:
        """True when every numeric text in the file is well formed and finite (most files)."""
        if self._plain is None:
            self._plain = all_plain(self.numeric_texts())
        return self._plain

    def meshes(self) -> list[tuple[etree._Element, str, str | None, str | None]]:
        """(<mesh>, filename, resolved path or None, package that was not found) per mesh of a link,
        once per file. The mesh's link is mesh_link(mesh)."""
        if self._meshes is None:
            base = self.base_dir
            resolve = self.resolver.resolve
            out = []
            seen: dict[str, tuple[str | None, str | None]] = {"": (None, None)}  # visual and collision share meshes
            for mesh in self.xpath("link/*/geometry/mesh"):  # one path search for the file, in libxml2
                uri = mesh.get("filename") or ""
                found = seen.get(uri)
                if found is None:
                    found = seen[uri] = resolve(uri, base)
                out.append((mesh, uri, *found))
            self._meshes = out
        return self._meshes

    @staticmethod
    def mesh_link(mesh: etree._Element) -> etree._Element:
        """The <link> of a mesh from meshes() (link/visual/geometry/mesh)."""
        return mesh.getparent().getparent().getparent()

    def inertias(self) -> list[tuple[etree._Element, etree._Element, tuple[float, ...], tuple[float, float, float]]]:
        """(link, <inertia>, (ixx, iyy, izz, ixy, ixz, iyz), principal moments ascending), once per file."""
        if self._inertias is None:
            from armtool.lint.inertia import principal_moments, read_inertia

            out = []
            seen: set[etree._Element] = set()
            for inertia in self.xpath("link/inertial/inertia"):
                link = inertia.getparent().getparent()
                if link in seen:
                    continue  # the first <inertial> of a link counts, as link.find() would
                seen.add(link)
                values = read_inertia(inertia)
                if values is not None:
                    out.append((link, inertia, values, principal_moments(*values)))
            self._inertias = out
        return self._inertias

    @property
    def base_dir(self) -> Path:
        return self.path.parent

    def link(self, name: str) -> etree._Element | None:
        """The first link of that name."""
        return self._link_by_name.get(name)

    def joint(self, name: str) -> JointView | None:
        """The first joint of that name."""
        return self._joint_by_name.get(name)

    def root_links(self) -> list[str]:
        """Links that are nobody's child, in file order."""
        roots: dict[str, None] = {}
        children = self.joints_by_child
        for name in self.link_name.values():
            if name is not None and name not in children:
                roots[name] = None
        return list(roots)

    def is_moved(self, link_name: str) -> bool:
        """True if a non-fixed joint moves this link relative to its parent."""
        return any(j.moves for j in self.joints_by_child.get(link_name, ()))

    def limits_of(self, joint_name: str) -> tuple[float, float] | None:
        """(lower, upper) in the joint's units, or None when unbounded or unknown."""
        j = self.joint(joint_name)
        if j is None:
            return None
        if j.type == "continuous":
            return None
        limit = j.limit()
        if limit is None:
            return None
        lo, hi = parse_floats(j.limits.get("lower", "0")), parse_floats(j.limits.get("upper", "0"))
        if not lo or not hi or len(lo) != 1 or len(hi) != 1:
            return None
        if not (math.isfinite(lo[0]) and math.isfinite(hi[0])):
            return None
        return lo[0], hi[0]

    def ancestors(self, link_name: str) -> list[str]:
        """Links from `link_name`'s parent up to the root (stops on loops)."""
        out: list[str] = []
        seen = {link_name}
        current = link_name
        while True:
            parents = self.joints_by_child.get(current)
            if not parents or parents[0].parent is None or parents[0].parent in seen:
                return out
            current = parents[0].parent
            seen.add(current)
            out.append(current)
