"""Find the files, load each kind, run the rules for it, apply config and inline ignores."""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator, Sequence
from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

from armtool.errors import ArmtoolError
from armtool.fileio import read_regular
from armtool.lint.config import LintConfig
from armtool.lint.context import FileContext, UrdfContext
from armtool.lint.file_findings import LOADER_CODE, invalid_yaml, xacro_finding
from armtool.lint.file_findings import file_finding as _file_finding
from armtool.lint.finding import Finding
from armtool.lint.locate import Locator, display_path, local_tag
from armtool.lint.rule import Rule, Target
from armtool.model.packages import PackageResolver
from armtool.model.xmlsource import XmlSyntaxProblem, declares_entities, parse_xml

if TYPE_CHECKING:  # imported on use (xacro costs start-up time; SRDF support is not always needed)
    from lxml import etree

    from armtool.lint.checked import PackageChecked
    from armtool.lint.srdf_context import SrdfContext
    from armtool.model.xacro_source import Expansion

SKIP_DIRS = {".git", ".hg", ".svn", ".venv", "venv", "node_modules", "__pycache__", "build", "install", "log"}
MAX_BYTES = 256 * 1024 * 1024


STDIN = Path("-")  # `armtool lint -`: a robot description (URDF or SRDF) read from standard input


class FileKind(str, Enum):
    URDF = "urdf"
    XACRO = "xacro"
    SRDF = "srdf"
    KINEMATICS = "kinematics"
    JOINT_LIMITS = "joint_limits"
    PILZ = "pilz"
    CONTROLLERS = "controllers"
    SETUP_ASSISTANT = "setup_assistant"


def file_kind(path: Path) -> FileKind | None:
    """The kind a file's name says; for MoveIt's YAML files its content decides later whether it
    is MoveIt's (UR's default_kinematics.yaml, Franka's joint_limits.yaml are not)."""
    name = path.name.lower()
    if name == ".setup_assistant":
        return FileKind.SETUP_ASSISTANT
    if name.endswith(".srdf") or name.endswith(".srdf.xacro"):
        return FileKind.SRDF
    if name.endswith(".urdf"):
        return FileKind.URDF
    if name.endswith(".xacro"):
        return FileKind.XACRO
    if not name.endswith((".yaml", ".yml")):
        return None
    stem = name.rsplit(".", 1)[0]
    if stem.endswith("kinematics"):
        return FileKind.KINEMATICS
    if "joint_limits" in stem:
        return FileKind.JOINT_LIMITS
    if stem.endswith("cartesian_limits"):
        return FileKind.PILZ
    if "controller" in stem:
        return FileKind.CONTROLLERS
    return None


def collect_files(paths: Sequence[Path]) -> list[Path]:
    """Files named on the command line (any extension is taken as asked) and robot files below directories."""
    out: list[Path] = []
    for path in paths:
        if path == STDIN:
            out.append(path)
        elif path.is_dir():
            found = sorted(_walk(path))
            if not found:
                raise ArmtoolError(
                    "no robot description files (.urdf, .xacro, .srdf, MoveIt's YAML files) found",
                    str(path),
                    "pass the files themselves, or a directory that holds them",
                )
            out.extend(found)
        elif path.is_file():
            out.append(path)
        elif path.exists():
            raise ArmtoolError(
                "not a regular file (a FIFO, socket or device)",
                str(path),
                "pass a file; to lint a stream, pipe it to `armtool lint -`",
            )
        else:
            raise ArmtoolError("no such file or directory", str(path), "check the path")
    unique: dict[Path, None] = {}
    for p in out:
        unique.setdefault(p, None)
    return list(unique)


def _walk(directory: Path, seen: set[tuple[int, int]] | None = None) -> Iterator[Path]:
    """Robot files below a directory; each directory once, so symlink loops end. Only regular
    files (or links to them): a FIFO or device named `*.urdf` would block the read or never end."""
    seen = set() if seen is None else seen
    try:
        st = directory.stat()
        entries = sorted(directory.iterdir())
    except OSError:
        return
    if (st.st_dev, st.st_ino) in seen:
        return
    seen.add((st.st_dev, st.st_ino))
    for entry in entries:
        if entry.is_dir():
            if entry.name not in SKIP_DIRS and not entry.name.startswith("."):
                yield from _walk(entry, seen)
        elif file_kind(entry) is not None and entry.is_file():
            yield entry


class LintOptions:
    def __init__(
        self,
        xacro_args: dict[str, str] | None = None,
        package_paths: Sequence[Path] = (),
        urdf: Path | None = None,
        srdf: Path | None = None,
        config: LintConfig | None = None,
        stdin: bytes | None = None,
        moveit_config: Path | None = None,
    ) -> None:
        self.stdin = stdin  # the bytes of `-`
        self.moveit_config = moveit_config  # a MoveIt config package checked as a whole
        self.file_args: dict[Path, dict[str, str]] = {}  # xacro arguments of one file (resolved path)
        self.xacro_args = dict(xacro_args or {})
        self.package_paths = list(package_paths)
        self.urdf = urdf
        self.srdf = srdf
        self.config = config if config is not None else LintConfig()


class LintResult(NamedTuple):
    findings: list[Finding]
    files: list[Path]
    checked: list[PackageChecked] = []  # noqa: RUF012 (read-only; per package, what its files were checked against)


def rules_for(target: Target) -> list[Rule]:
    """One instance of each rule that checks files of this kind (loader-reported ones excluded)."""
    from armtool.lint.registry import checks_for

    return [rule() for rule in checks_for(target)]


def _cause(path: Path, findings: list[Finding]) -> tuple[str, str]:
    """Why a counterpart file that was found could not be used, from the findings its loading
    produced; and what fixes it: its own error's hint (xacro's names the missing argument or
    package), said of that file ("" when its error has none)."""
    error = next((f for f in findings if f.severity.value == "error"), None)
    first = error if error is not None else (findings[0] if findings else None)
    shown = display_path(path)
    why = (
        f"{shown} is not a robot description with links"
        if first is None
        else f"{shown} could not be loaded: {first.code} {first.message}"
    )
    hint = f"{shown} was found but cannot be used; {error.hint}" if error is not None and error.hint else ""
    return why, hint


_XACRO_HINTS = re.compile(rb"<xacro:|\$\{|\$\((?:arg|find|eval|env|optenv|dirname)\b")
_XACRO_NAMESPACES = ("http://www.ros.org/wiki/xacro", "http://ros.org/wiki/xacro", "http://wiki.ros.org/xacro")


def _is_xacro(root: etree._Element) -> bool:
    """A document that only xacro can make into a URDF: an element in xacro's namespace, or an
    attribute with a `${...}` or `$(...)` expression (comments do not count)."""
    from lxml import etree

    for el in root.iter(etree.Element):
        tag = el.tag
        if isinstance(tag, str) and tag.startswith("{") and tag[1:].split("}", 1)[0] in _XACRO_NAMESPACES:
            return True
        if any("${" in v or "$(" in v for v in el.attrib.values()):
            return True
    return False


_SRDF_TAGS = re.compile(rb"<(group|virtual_joint|disable_collisions|group_state|end_effector|passive_joint)[\s/>]")
_LINK_TAG = re.compile(rb"<link[\s/>]")


def sniff_kind(data: bytes) -> FileKind:
    """The kind of a file whose name does not say (PR2's srdf/robot.xml, a robot_description on
    stdin): an SRDF has groups, states or collision pairs and no links; anything else is a URDF."""
    if _SRDF_TAGS.search(data) and not _LINK_TAG.search(data):
        return FileKind.SRDF
    return FileKind.URDF


def _names_srdf(srdf: Path) -> bool:
    """True when the package's .setup_assistant names this SRDF (its URDF is then this SRDF's
    by MoveIt's own record, not only the package's)."""
    from armtool.lint.pairing import read_setup_assistant

    setup = read_setup_assistant(srdf.parent)
    if setup is None or not setup.srdf_relative:
        return False
    return (setup.package_dir / setup.srdf_relative).resolve() == srdf.resolve()


def _sniff_yaml(data: bytes) -> FileKind:
    """The MoveIt file a YAML file named on the command line looks like (the rules then decide
    from its content whether it is MoveIt's at all)."""
    if re.search(rb"^\s*joint_limits\s*:", data, re.MULTILINE):
        return FileKind.JOINT_LIMITS
    if re.search(rb"^\s*cartesian_limits\s*:", data, re.MULTILINE):
        return FileKind.PILZ
    if re.search(rb"^\s*(controller_names|controller_list|controller_manager)\s*:", data, re.MULTILINE):
        return FileKind.CONTROLLERS
    return FileKind.KINEMATICS


def _read(path: Path) -> bytes:
    """A regular file's bytes (never a FIFO or device: see read_regular), at most MAX_BYTES."""
    try:
        data = read_regular(path, MAX_BYTES + 1)
    except OSError as exc:
        raise ArmtoolError(f"cannot read file: {exc.strerror}", str(path)) from None
    if len(data) > MAX_BYTES:
        raise ArmtoolError(f"file is over armtool's limit of {MAX_BYTES // (1024 * 1024)} MB", str(path))
    return data


class Linter:
    def __init__(self, options: LintOptions) -> None:
        from armtool.lint.suppress import SuppressionIndex

        self.options = options
        self.resolver = PackageResolver([*options.package_paths, *options.config.package_paths])
        self._urdf_cache: dict[tuple[Path, tuple[tuple[str, str], ...]], tuple[UrdfContext | None, list[Finding]]] = {}
        self._rules: dict[Target, list[Rule]] = {}
        self.suppressions = SuppressionIndex()
        # (resolved path, path as findings show it, paired with its URDF) -> the SRDF: loaded once per run
        self._srdf_cache: dict[tuple[Path, str, bool], tuple[SrdfContext | None, list[Finding]]] = {}
        self._urdf_hint: dict[Path, str] = {}  # SRDF -> what fixes the URDF that was found but failed
        self._variant: dict[Path, dict[str, str]] = {}  # a file being linted with one of its argument sets
        self._exact_cache: dict[tuple[Path, tuple[tuple[str, str], ...]], UrdfContext | None] = {}
        self.package_cache: dict[Path, Any] = {}  # MoveIt config package root -> its controllers (moveit_files)
        self.yaml_documents: dict[Path, Any] = {}  # resolved path -> its YAML nodes or parse error (moveit_files)
        self.run_files: set[Path] = set()  # every file of this run, resolved (a fragment's includer among them?)
        # file linted (resolved) -> (URDF, SRDF) it was checked against (display paths, None: none) and its kind
        self.counterparts: dict[str, tuple[str | None, str | None, str]] = {}

    def _read(self, path: Path) -> bytes:
        """The file's bytes; inline ignore comments are read from them too, not from a second read."""
        if path == STDIN:
            data = self.options.stdin or b""
            if b"<xacro:" in data:
                raise ArmtoolError(
                    "standard input holds a xacro document; xacro needs its file for includes",
                    "-",
                    "pass the .xacro file itself, or pipe xacro's output: xacro FILE | armtool lint -",
                )
        else:
            data = _read(path)
        self.suppressions.prime(display_path(path), data)
        return data

    def read_text(self, path: Path) -> str:
        """A YAML file's text (UTF-8; undecodable bytes replaced), read once for ignore comments too."""
        return self._read(path).decode("utf-8", "replace")

    # ---- per-file settings ------------------------------------------------
    def xacro_args_for(self, path: Path, extra: dict[str, str] | None = None) -> dict[str, str]:
        """xacro arguments for one file: the config's for its glob, then `extra` (.setup_assistant),
        then --xacro-arg (the command line wins)."""
        variant = self._variant.get(path.resolve())
        args = dict(variant if variant is not None else self.options.config.xacro_args_for(path))
        args.update(self.options.file_args.get(path.resolve(), {}))
        args.update(extra or {})
        args.update(self.options.xacro_args)
        return args

    # ---- URDF and xacro -------------------------------------------------
    def load_urdf(
        self, path: Path, extra_args: dict[str, str] | None = None
    ) -> tuple[UrdfContext | None, list[Finding]]:
        """Parse a URDF or expand a xacro. Returns the context (None if unusable) and loader findings."""
        if path.name.lower().endswith(".xacro"):
            return self._load_xacro(path, extra_args)
        data = self._read(path)
        try:
            root = parse_xml(data, keep_blank_text=False)
        except XmlSyntaxProblem as exc:
            return None, [_file_finding("U001", path, exc.line, exc.column, f"not well-formed XML: {exc.message}")]
        findings = []
        if declares_entities(root):
            findings.append(
                _file_finding(
                    "U003",
                    path,
                    1,
                    1,
                    "DOCTYPE declares entities; armtool does not expand them",
                    "remove the DOCTYPE; use xacro properties instead",
                )
            )
        if local_tag(root) != "robot":
            findings.append(
                _file_finding(
                    "U002",
                    path,
                    root.sourceline or 1,
                    1,
                    f"root element is <{local_tag(root)}>, not <robot>",
                    'a URDF file holds one <robot name="..."> element',
                )
            )
            return None, findings
        if path != STDIN and _XACRO_HINTS.search(data) and _is_xacro(root):  # stdin: xacro needs the file
            ctx, found = self._load_xacro(path, extra_args)
            note = _file_finding(
                "X002",
                path,
                1,
                1,
                f"{path.name} is a xacro (xacro elements or ${{...}}/$(...) expressions): expanded as one",
                f"rename it {path.stem}.urdf.xacro; other tools read a .urdf as plain URDF",
            )
            return ctx, [note, *findings, *found]
        return UrdfContext(path, root, Locator(path, data=data), self.resolver, raw=data), findings

    def _expand(
        self, path: Path, extra_args: dict[str, str] | None = None, exact: dict[str, str] | None = None
    ) -> Expansion | Finding:
        """xacro's expansion of `path` (with `exact` arguments, else the file's: xacro_args_for),
        or the X001 finding that says why it failed."""
        from armtool.model.xacro_source import XacroFailure, expand

        self._read(path)
        try:
            return expand(path, exact if exact is not None else self.xacro_args_for(path, extra_args), self.resolver)
        except XacroFailure as exc:
            return xacro_finding(exc)

    def load_urdf_with(self, path: Path, args: dict[str, str]) -> UrdfContext | None:
        """A xacro expanded with exactly these arguments (another variant), or None when it fails."""
        key = (path.resolve(), tuple(sorted(args.items())))
        if key not in self._exact_cache:
            self._exact_cache[key] = self._load_xacro(path, exact=args)[0]
        return self._exact_cache[key]

    def _load_xacro(
        self, path: Path, extra_args: dict[str, str] | None = None, exact: dict[str, str] | None = None
    ) -> tuple[UrdfContext | None, list[Finding]]:
        args = exact if exact is not None else self.xacro_args_for(path, extra_args)
        expansion = self._expand(path, exact=args)
        if isinstance(expansion, Finding):
            return None, [expansion]
        root = expansion.root
        if local_tag(root) != "robot":
            if not any(isinstance(el.tag, str) for el in root):
                return None, []  # macros or arguments only, under another root (<gripper>): an include file
            return None, [
                _file_finding("U002", path, 1, 1, f"expanded root element is <{local_tag(root)}>, not <robot>")
            ]
        ctx = UrdfContext(
            path.resolve(), root, Locator(path.resolve(), expansion.origins), self.resolver, from_xacro=True
        )
        ctx.xacro_args = dict(args)
        ctx.source_files = tuple(expansion.files)
        return ctx, []

    def lint_urdf(self, path: Path) -> list[Finding]:
        sets = self.options.config.xacro_arg_sets(path) if path != STDIN else [{}]
        if len(sets) < 2:
            return self._lint_urdf_once(path)
        return self._lint_variants(path, sets)

    def _lint_urdf_once(self, path: Path) -> list[Finding]:
        ctx, findings = self.load_urdf(path)
        if ctx is None:
            return findings
        if ctx.from_xacro and not ctx.links and not ctx.joints:
            return findings  # a macro library: nothing to check until a robot uses it
        self.note_counterparts(path, path, None, "urdf")
        return findings + list(self._run(ctx, Target.URDF))

    def _lint_variants(self, path: Path, sets: list[dict[str, str]]) -> list[Finding]:
        """The file linted once per argument set of the configuration. A finding every set gives
        is reported once; the others say which set gave them ("[xacro args dof:=6]")."""
        key = path.resolve()
        differing = sorted({k for s in sets for k in s if len({s.get(k) for s in sets}) > 1})
        per_set: list[tuple[str, list[Finding]]] = []
        try:
            for args in sets:
                self._variant[key] = args
                label = " ".join(f"{k}:={args.get(k, '')}" for k in differing) or "(no arguments)"
                per_set.append((label, self._lint_urdf_once(path)))
        finally:
            self._variant.pop(key, None)
        counts: dict[tuple[str, int, int, str, str], int] = {}
        for _, found in per_set:
            for f in dict.fromkeys(found):
                counts[(f.path, f.line, f.column, f.code, f.message)] = (
                    counts.get((f.path, f.line, f.column, f.code, f.message), 0) + 1
                )
        out: list[Finding] = []
        seen: set[tuple[str, int, int, str, str]] = set()
        for label, found in per_set:
            for f in found:
                k = (f.path, f.line, f.column, f.code, f.message)
                if counts[k] == len(per_set):
                    if k not in seen:
                        seen.add(k)
                        out.append(f)
                else:
                    out.append(f._replace(message=f"{f.message} [xacro args {label}]"))
        return out

    # ---- SRDF --------------------------------------------------------------
    def _urdf_model(
        self, path: Path, extra_args: dict[str, str] | None = None
    ) -> tuple[UrdfContext | None, list[Finding]]:
        key = (path.resolve(), tuple(sorted((extra_args or {}).items())))
        if key not in self._urdf_cache:
            self._urdf_cache[key] = self.load_urdf(path, extra_args)
        return self._urdf_cache[key]

    def _urdf_for_srdf(self, srdf: Path, srdf_root: etree._Element) -> tuple[UrdfContext | None, str | None, bool]:
        """The URDF an SRDF describes, or None and why not; and whether the pairing is the user's
        or MoveIt's own (--urdf, the configuration, .setup_assistant) rather than a guess from the
        files beside it. The first usable candidate, unless it lacks names the SRDF uses and a
        later candidate found beside it lacks fewer."""
        from armtool.lint.pairing import srdf_names, unknown_names, urdf_candidates

        given = self.options.urdf or self.options.config.urdf_for(srdf)
        if given is not None:
            ctx, findings = self._urdf_model(given)
            if ctx is not None:
                return ctx, None, True
            why, self._urdf_hint[srdf] = _cause(given, findings)
            return None, why, True
        first_failure: str | None = None
        best: tuple[int, UrdfContext] | None = None
        wanted: tuple[set[str], set[str]] | None = None  # the SRDF's names, read once when first needed
        for cand in urdf_candidates(srdf, srdf_root.get("name"), self.resolver):
            if not cand.path.is_file():
                first_failure = first_failure or f"{display_path(cand.path)} ({cand.why}) does not exist"
                continue
            ctx, findings = self._urdf_model(cand.path, cand.xacro_args)
            if ctx is not None and ctx.links:
                if cand.why == "named by .setup_assistant":
                    return ctx, None, _names_srdf(srdf)  # MoveIt's own record of the pairing
                wanted = wanted or srdf_names(srdf_root)
                missing = unknown_names(wanted, ctx.joint_names, ctx.link_names)
                if best is None or missing < best[0]:
                    best = (missing, ctx)
                if missing == 0:
                    break
            if ctx is None and findings and first_failure is None:
                why, self._urdf_hint[srdf] = _cause(cand.path, findings)
                first_failure = f"{why} ({cand.why})"
        if best is not None:
            return best[1], None, False
        return None, first_failure or "no URDF found beside it", False

    def load_srdf(self, path: Path, *, pair: bool = True) -> tuple[SrdfContext | None, list[Finding]]:
        """The SRDF (a .srdf.xacro expanded like URDF xacros), paired with its URDF. None with no
        findings for an SRDF xacro that only defines macros: nothing to check on its own.

        Loaded once per run for each way of asking: every MoveIt YAML file of a package looks for
        its SRDF (pair=False), and the SRDF's own lint and the files checked against its URDF ask
        for it paired. The key holds the path as findings show it as well as the file: a symlink,
        or a path outside the working directory written another way, is loaded as it is written."""
        key = (path.resolve(), display_path(path), pair)
        cached = self._srdf_cache.get(key)
        if cached is None:
            cached = self._srdf_cache[key] = self._load_srdf(path, pair)
        ctx, findings = cached
        return ctx, list(findings)

    def _load_srdf(self, path: Path, pair: bool) -> tuple[SrdfContext | None, list[Finding]]:
        from armtool.lint.srdf_context import SrdfContext

        if path.name.lower().endswith(".xacro"):
            expansion = self._expand(path)
            if isinstance(expansion, Finding):
                return None, [expansion]
            root = expansion.root
            if local_tag(root) == "robot" and not any(isinstance(el.tag, str) for el in root):
                return None, []
            locator = Locator(path.resolve(), expansion.origins)
            path = path.resolve()
        else:
            data = self._read(path)
            try:
                root = parse_xml(data)
            except XmlSyntaxProblem as exc:
                return None, [_file_finding("S001", path, exc.line, exc.column, f"not well-formed XML: {exc.message}")]
            locator = Locator(path, data=data)
        if local_tag(root) != "robot":
            return None, [
                _file_finding(
                    "S001", path, root.sourceline or 1, 1, f"root element is <{local_tag(root)}>, not <robot>"
                )
            ]
        findings: list[Finding] = []
        urdf: UrdfContext | None = None
        authoritative = False
        if pair:
            urdf, why, authoritative = self._urdf_for_srdf(path, root)
            if urdf is None:
                findings.append(
                    _file_finding(
                        "S002",
                        path,
                        root.sourceline or 1,
                        1,
                        f"cannot check names and limits against the robot: {why}",
                        self._urdf_hint.get(path)
                        or "pass --urdf PATH (a .urdf or .urdf.xacro), or set it for this file in "
                        "[tool.armtool.lint.urdf]",
                    )
                )
        if urdf is not None:
            from armtool.lint.srdf_variant import fit

            sets = self.options.config.xacro_arg_sets(urdf.path)
            urdf, mismatch = fit(sets, self.load_urdf_with, path, root, urdf)
            if mismatch is not None:
                findings.append(_file_finding("S003", path, root.sourceline or 1, 1, mismatch))
        ctx = SrdfContext(path, root, locator, urdf)
        ctx.urdf_given = urdf is not None and authoritative
        return ctx, findings

    def lint_srdf(self, path: Path) -> list[Finding]:
        ctx, findings = self.load_srdf(path)
        if ctx is None:
            return findings
        self.note_counterparts(path, ctx.urdf.path if ctx.urdf is not None else None, path, "srdf")
        return findings + list(self._run(ctx, Target.SRDF))

    # ---- kinematics.yaml -----------------------------------------------------
    def _find_srdf(self, path: Path, groups: list[str]) -> tuple[SrdfContext | None, str, str]:
        """The SRDF of a MoveIt YAML file, or None, why not, and what to do about it: an SRDF that
        was found but could not be loaded gets its own error's hint (a xacro argument it needs,
        a package path), not "pass --srdf"."""
        from armtool.lint.pairing import srdf_candidates

        pass_srdf = "pass --srdf PATH, or set it for this file in [tool.armtool.lint.srdf]"
        given = self.options.srdf or self.options.config.srdf_for(path)
        if given is not None:
            ctx, findings = self.load_srdf(given, pair=False)
            if ctx is not None:
                return ctx, "", ""
            why, hint = _cause(given, findings)
            return None, why, hint or pass_srdf
        failure, hint = "", ""
        for tier in srdf_candidates(path):
            usable: dict[Path, SrdfContext] = {}
            for cand in tier:
                if not cand.path.is_file():
                    continue
                ctx, findings = self.load_srdf(cand.path, pair=False)
                if ctx is not None:
                    usable.setdefault(ctx.path, ctx)
                elif findings and not failure:
                    failure, hint = _cause(cand.path, findings)
            if len(usable) == 1:
                return next(iter(usable.values())), "", ""
            covering = [c for c in usable.values() if set(groups) <= set(c.groups)]
            if len(covering) == 1 or (groups and covering):
                return covering[0], "", ""  # every one of them defines the file's groups: each check holds
            if len({frozenset(c.groups) for c in usable.values()}) == 1:
                return next(iter(usable.values())), "", ""  # the same groups (an SRDF and its exported copy)
            if usable:
                return None, "several SRDFs beside it: " + ", ".join(sorted(p.name for p in usable)), pass_srdf
        return None, failure or "no SRDF found beside it", hint or pass_srdf

    def lint_kinematics(self, path: Path) -> list[Finding]:
        import yaml

        from armtool.lint.kinematics_context import (
            KinematicsContext,
            NotAMapping,
            is_moveit_kinematics,
            may_be_unusable_moveit,
            read_groups,
        )
        from armtool.moveit.substitutions import launch_values

        text = self.read_text(path)
        try:
            groups = read_groups(text, launch_values(path) if "$(" in text else None)
        except yaml.YAMLError as exc:
            return [invalid_yaml("K001", path, exc)]
        except NotAMapping as exc:
            if self._find_srdf(path, [])[0] is None:
                return []  # a list of something else (DH rows?) with no MoveIt config around it: not MoveIt's
            return [
                _file_finding(
                    "K001",
                    path,
                    exc.line,
                    exc.column,
                    f"the file is {exc.what}, not a mapping of group names to solver settings",
                    "write `GROUP:` then its settings (kinematics_solver: ...), one group per SRDF group",
                )
            ]
        except RecursionError:
            return [_file_finding("K001", path, 1, 1, "YAML nested too deeply to read", "flatten it")]
        names = [g.name for g in groups]
        if not is_moveit_kinematics(groups):
            if not may_be_unusable_moveit(groups):
                return []  # named *kinematics.yaml, but not MoveIt's (UR's calibration, Franka's parameters)
            srdf_ctx = self._find_srdf(path, names)[0]
            if srdf_ctx is None or not set(names) & set(srdf_ctx.groups):
                return []  # `a1: 0.025`: no planning group of that name, so not MoveIt's
            return list(self._run(KinematicsContext(path, groups, srdf_ctx), Target.KINEMATICS))
        findings: list[Finding] = []
        srdf_ctx, why, hint = self._find_srdf(path, names)
        if srdf_ctx is None:
            findings.append(_file_finding("K002", path, 1, 1, f"cannot check group names: {why}", hint))
        ctx = KinematicsContext(path, groups, srdf_ctx)
        self.note_counterparts(path, None, srdf_ctx.path if srdf_ctx is not None else None, "kinematics")
        if srdf_ctx is not None and not set(names) <= set(srdf_ctx.groups):
            ctx.variant_groups = self.srdf_variant_groups(srdf_ctx.path)
        return findings + list(self._run(ctx, Target.KINEMATICS))

    def srdf_variant_groups(self, srdf: Path) -> set[str]:
        """The groups an SRDF xacro defines with the other argument values its sources write down
        (`hand:=true` of a `<xacro:if value="$(arg hand)">`): a kinematics.yaml written for every
        variant configures groups the default expansion lacks."""
        from armtool.lint.srdf_context import SrdfContext
        from armtool.lint.srdf_variant import MAX_TRIES, compared_arguments

        if not srdf.name.lower().endswith(".xacro"):
            return set()
        base = self._expand(srdf)
        if isinstance(base, Finding):
            return set()
        args = self.xacro_args_for(srdf)
        out: set[str] = set()
        for change in compared_arguments(srdf, base.files)[:MAX_TRIES]:
            expansion = self._expand(srdf, exact={**args, **change})
            if not isinstance(expansion, Finding):
                out.update(SrdfContext(srdf, expansion.root, Locator(srdf), None).groups)
        return out

    # ---- a MoveIt config package's other YAML files ----------------------------------
    def srdf_for_package_file(self, path: Path) -> SrdfContext | None:
        """The SRDF a package YAML file (joint_limits.yaml, controllers) belongs to: as for kinematics.yaml."""
        return self._find_srdf(path, [])[0]

    def given_urdf(self, path: Path) -> Path | None:
        """The URDF the user gave for this file: --urdf, or the configuration's `urdf` table."""
        return self.options.urdf or self.options.config.urdf_for(path)

    def urdf_model(self, path: Path) -> UrdfContext | None:
        """A URDF or xacro loaded once per run (None when it does not load)."""
        return self._urdf_model(path)[0]

    def paired_srdf(self, path: Path) -> SrdfContext | None:
        """The SRDF with its URDF (loaded once per run; its own findings are reported when it is linted)."""
        return self.load_srdf(path)[0]

    def run_rules(self, ctx: FileContext, target: Target) -> Iterator[Finding]:
        return self._run(ctx, target)

    # ---- common -----------------------------------------------------------------
    def _run(self, ctx: FileContext, target: Target) -> Iterator[Finding]:
        rules = self._rules.get(target)
        if rules is None:
            rules = self._rules[target] = rules_for(target)
        for rule in rules:
            yield from rule.check(ctx)

    def lint_file(self, path: Path) -> list[Finding]:
        kind = file_kind(path) if path != STDIN else sniff_kind(self._read(path))
        if kind is None and path.suffix.lower() in (".yaml", ".yml"):
            kind = _sniff_yaml(self._read(path))  # named on the command line: its content decides
        elif kind is None and path.is_file():
            kind = sniff_kind(self._read(path))
        if kind is FileKind.SRDF:
            return self._through_includer(path, self.lint_srdf(path))
        if kind is FileKind.KINEMATICS:
            return self.lint_kinematics(path)
        if kind in (FileKind.JOINT_LIMITS, FileKind.PILZ, FileKind.CONTROLLERS, FileKind.SETUP_ASSISTANT):
            from armtool.lint import moveit_files

            lint = {
                FileKind.JOINT_LIMITS: moveit_files.lint_joint_limits,
                FileKind.PILZ: moveit_files.lint_pilz,
                FileKind.CONTROLLERS: moveit_files.lint_controllers,
                FileKind.SETUP_ASSISTANT: moveit_files.lint_setup_assistant,
            }[kind]
            return lint(self, path)
        return self._through_includer(path, self.lint_urdf(path))

    def note_counterparts(self, path: Path, urdf: Path | None, srdf: Path | None, kind: str) -> None:
        """Record what a file of this kind (a FileKind value) was checked against (the run's
        "checked:" summary, armtool.lint.checked)."""
        if path != STDIN:
            self.counterparts[str(path.resolve())] = (
                display_path(urdf) if urdf is not None else None,
                display_path(srdf) if srdf is not None else None,
                kind,
            )

    def _through_includer(self, path: Path, found: list[Finding]) -> list[Finding]:
        """A xacro that does not stand alone (armtool.lint.fragments) and that a file of its
        package includes: checked through that file (its findings that point into this one),
        or, when that file is linted in the same run, left to it; an X003 note says so."""
        from armtool.lint.fragments import needs_includer, top_includer

        if path == STDIN or not path.name.lower().endswith(".xacro"):
            return found
        if not any(needs_includer(f.code, f.message) and f.severity.value == "error" for f in found):
            return found
        top = top_includer(path)
        if top is None:
            return found
        mine, shown = path.resolve(), display_path(top)
        expansion = self._expand(top)
        if isinstance(expansion, Finding) or mine not in {p.resolve() for p in expansion.files}:
            return [
                _file_finding(
                    "X003",
                    path,
                    1,
                    1,
                    f"included by {shown} (with other xacro arguments than the ones given: its expansion does not "
                    "include it); not checked as a robot on its own, nor through it",
                    f"lint {shown} with the --xacro-arg values that include this file",
                )
            ]
        note = _file_finding(
            "X003",
            path,
            1,
            1,
            f"included by {shown}, which defines what it needs: checked through its expansion, not as a robot "
            "on its own",
            f"lint {shown} to check the robot this file is part of",
        )
        if top.resolve() in self.run_files:
            return [note]
        return [note, *(f for f in self.lint_file(top) if Path(f.path).resolve() == mine)]

    def lint(self, path: Path) -> list[Finding]:
        """lint_file() without the findings that inline ignore comments silence.

        A file too deep or too big for the checks (RecursionError, MemoryError) is that file's
        loader finding; any other unexpected exception is re-raised naming the file, so one bad
        file among many (a parallel run) says which it was."""
        try:
            found = self.lint_file(path)
        except ArmtoolError:
            raise
        except (RecursionError, MemoryError) as exc:
            what = "nested too deeply" if isinstance(exc, RecursionError) else "too large"
            kind = file_kind(path) if path != STDIN else None
            code = LOADER_CODE[kind.value] if kind is not None else "U001"
            found = [
                _file_finding(
                    code,
                    path,
                    1,
                    1,
                    f"file is {what} for armtool to check",
                    "simplify the file (fewer nesting levels, fewer elements)",
                )
            ]
        except Exception as exc:
            raise RuntimeError(f"while linting {display_path(path)}: {type(exc).__name__}: {exc}") from exc
        silenced = self.suppressions.silenced
        return [f for f in found if not silenced(f)]


# Many files are linted by worker processes (forked, so they share the imported rules): a
# repository-wide pre-commit run or `armtool lint src/` then uses every core, as ruff does.
# Plain os.fork and pipes, not multiprocessing: its import and Pool cost ~35 ms, a fifth of
# linting all 69 example-robot-data URDFs; here the parent lints too and one fork costs ~2 ms.
PARALLEL_MIN_FILES = 16
_TARGET_OF_KIND: dict[FileKind | None, Target] = {
    FileKind.SRDF: Target.SRDF,
    FileKind.KINEMATICS: Target.KINEMATICS,
    FileKind.JOINT_LIMITS: Target.JOINT_LIMITS,
    FileKind.PILZ: Target.PILZ,
    FileKind.CONTROLLERS: Target.CONTROLLERS,
    FileKind.SETUP_ASSISTANT: Target.SETUP_ASSISTANT,
}
MAX_WORKERS = 8


def _cpus() -> int:
    import os

    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def _lint_all(files: list[Path], linter: Linter) -> Iterator[list[Finding]]:
    """Findings per file, in the order of `files` (inline ignores applied); what each file was
    checked against lands in linter.counterparts, the workers' too."""
    import os

    linter.run_files = {p.resolve() for p in files if p != STDIN}
    workers = min(_cpus(), MAX_WORKERS)
    if len(files) < PARALLEL_MIN_FILES or workers < 2 or not hasattr(os, "fork"):
        for path in files:
            yield linter.lint(path)
        return
    yield from _lint_forked(linter, files, workers)


def _lint_forked(linter: Linter, files: list[Path], workers: int) -> Iterator[list[Finding]]:
    """Task indices travel through one pipe, written before forking: each process reads the next
    index when it is free (reads of 4 bytes from a pipe are atomic), so a process slowed by other
    load on the machine takes fewer files. Findings come back in file order, as in a serial run."""
    import marshal
    import os

    kinds = {file_kind(path) for path in files}
    targets = {_TARGET_OF_KIND.get(kind, Target.URDF) for kind in kinds}
    if targets - {Target.URDF}:
        targets |= {Target.URDF, Target.SRDF}  # an SRDF's URDF, a MoveIt YAML file's SRDF
    for target in targets:
        linter._rules.setdefault(target, rules_for(target))  # imported once, before forking
    # Largest files first: a few big robots (Talos, Romeo) dominate the work.
    sizes = []
    for i, path in enumerate(files):
        try:
            sizes.append((-os.stat(path).st_size, i))
        except OSError:
            sizes.append((0, i))
    order = [i for _, i in sorted(sizes)]
    tasks_r, tasks_w = os.pipe()
    queue = b"".join(i.to_bytes(4, "little") for i in order)
    os.set_blocking(tasks_w, False)
    try:
        queued = os.write(tasks_w, queue) // 4
    except BlockingIOError:
        queued = 0
    os.close(tasks_w)
    left = order[queued:]  # when the system gives pipes less room: the parent lints these itself
    children: list[tuple[int, int]] = []
    import gc

    try:
        gc.freeze()  # objects made so far are not collected: the children's pages stay shared
        for _ in range(workers - 1):
            results_r, results_w = os.pipe()
            pid = os.fork()
            if pid == 0:  # child: lint from the queue, send findings back, never return
                os.close(results_r)
                code = 0
                try:
                    _worker(linter, files, tasks_r, results_w)
                except BaseException:
                    code = 1
                finally:
                    os._exit(code)
            os.close(results_w)
            children.append((pid, results_r))
        mine = _take_tasks(linter, files, tasks_r)
        for index in left:
            try:
                mine.append((index, linter.lint(files[index])))
            except Exception as exc:
                mine.append((index, exc))
        results: dict[int, list[Finding]] = {}
        errors: dict[int, BaseException] = {}
        for index, outcome in mine:
            if isinstance(outcome, BaseException):
                errors[index] = outcome
            else:
                results[index] = outcome
        while children:
            pid, results_r = children[0]
            blob = _read_all(results_r)
            children.pop(0)  # read to the end: the child has finished (or died)
            os.close(results_r)
            os.waitpid(pid, 0)
            if not blob:
                raise RuntimeError("a lint worker process ended without reporting (killed?)")
            sent, failures, counterparts = marshal.loads(blob)
            linter.counterparts.update(counterparts)
            for index, rows in sent:
                results[index] = [_finding_from_row(row) for row in rows]
            for index, pickled in failures:
                import pickle

                errors[index] = pickle.loads(pickled)
        if errors:
            raise errors[min(errors)]  # the first failing file, as a serial run would report
    finally:
        gc.unfreeze()  # back to normal collection (lint_paths may run in a long-lived process)
        os.close(tasks_r)
        for pid, results_r in children:  # only left on an exception in the parent
            os.close(results_r)
            try:
                import signal

                os.kill(pid, signal.SIGTERM)
                os.waitpid(pid, 0)
            except OSError:
                pass
    for i in range(len(files)):
        yield results[i]


def _take_tasks(linter: Linter, files: list[Path], tasks_r: int) -> list[tuple[int, list[Finding] | BaseException]]:
    """Lint files from the queue until it is empty (a file that raises is kept as its exception)."""
    import os

    out: list[tuple[int, list[Finding] | BaseException]] = []
    while True:
        raw = os.read(tasks_r, 4)
        if len(raw) < 4:
            return out
        index = int.from_bytes(raw, "little")
        try:
            out.append((index, linter.lint(files[index])))
        except Exception as exc:
            out.append((index, exc))


def _worker(linter: Linter, files: list[Path], tasks_r: int, results_w: int) -> None:
    import marshal
    import os

    sent = []
    failures = []
    for index, outcome in _take_tasks(linter, files, tasks_r):
        if isinstance(outcome, BaseException):
            import pickle

            try:
                failures.append((index, pickle.dumps(outcome)))
            except Exception:
                failures.append((index, pickle.dumps(RuntimeError(f"{type(outcome).__name__}: {outcome}"))))
        else:
            sent.append((index, [_finding_to_row(f) for f in outcome]))
    blob = marshal.dumps((sent, failures, linter.counterparts))
    view = memoryview(blob)
    while view:
        view = view[os.write(results_w, view) :]
    os.close(results_w)


def _read_all(fd: int) -> bytes:
    import os

    chunks: list[bytes] = []
    while True:
        chunk = os.read(fd, 1 << 20)
        if not chunk:
            return b"".join(chunks)
        chunks.append(chunk)


# Findings cross the pipe as tuples of str/int/None (marshal: built in, no import, fast).
def _finding_to_row(f: Finding) -> tuple[object, ...]:
    edit = None if f.edit is None else (str(f.edit.path), f.edit.start, f.edit.end, f.edit.replacement)
    return (f.path, f.line, f.column, f.code, f.name, f.severity.value, f.message, f.hint, edit, f.related)


def _finding_from_row(row: tuple[object, ...]) -> Finding:
    from armtool.lint.finding import Edit, Severity

    fields: tuple[Any, ...] = row  # the rows _finding_to_row wrote: the types are Finding's
    path, line, column, code, name, severity, message, hint, edit, related = fields
    return Finding(
        path,
        line,
        column,
        code,
        name,
        Severity(severity),
        message,
        hint,
        None if edit is None else Edit(Path(edit[0]), *edit[1:]),
        related,
    )


def _package_files(options: LintOptions) -> tuple[list[Path], list[Finding]]:
    """--moveit-config: the package's files as its launch files load them (its URDF, with the
    .setup_assistant's xacro arguments, is also what its SRDF is checked against), and an M102
    finding for a URDF or SRDF not found (nor given with --urdf / --srdf)."""
    from armtool.moveit.package import read_package

    assert options.moveit_config is not None
    resolver = PackageResolver([*options.package_paths, *options.config.package_paths])
    pkg = read_package(options.moveit_config, resolver)
    files = pkg.files()
    missing: list[Finding] = []
    marker = pkg.root / ".setup_assistant"
    where = marker if marker.is_file() else pkg.root / "package.xml"
    for what, found, given, flag in (
        ("URDF", pkg.urdf, options.urdf, "--urdf"),
        ("SRDF", pkg.srdf, options.srdf, "--srdf"),
    ):
        if given is not None and (found is None or not found.is_file()):
            files.insert(0, given)
        elif found is None:
            why = next((p for p in pkg.problems if "was not found" in p), "") if what == "URDF" else ""
            missing.append(
                _file_finding(
                    "M102",
                    where,
                    1,
                    1,
                    f"no {what} found for the MoveIt config ({why or _NOT_FOUND[what]}): it was not checked, nor were "
                    "the package's files against it",
                    f"pass {flag} PATH",
                )
            )
    if pkg.urdf is not None and pkg.urdf.is_file():
        options.file_args[pkg.urdf.resolve()] = dict(pkg.urdf_xacro_args)
        if options.urdf is None:
            options.urdf = pkg.urdf
        files.insert(0, pkg.urdf)
    if pkg.srdf is not None and options.srdf is None and pkg.srdf.is_file():
        options.srdf = pkg.srdf
    if marker.is_file():
        files.append(marker)
    return files, missing


_NOT_FOUND = {
    "URDF": ".setup_assistant names none and config/ has no <robot>.urdf.xacro or <robot>.urdf",
    "SRDF": ".setup_assistant names none and config/ has no <robot>.srdf and no single SRDF",
}


def lint_paths(paths: Iterable[Path], options: LintOptions) -> LintResult:
    paths = list(paths)
    findings: list[Finding] = []
    if options.moveit_config is not None:
        package_files, findings = _package_files(options)
        paths += package_files
    files = collect_files(paths)
    config = options.config
    findings = [config.adjust(f) for f in findings if config.keeps(f)]
    linter = Linter(options)
    for file_findings in _lint_all(files, linter):
        for finding in file_findings:
            if config.keeps(finding):
                findings.append(config.adjust(finding))
    if len(files) > 1:
        from armtool.lint.shared_defects import merge_shared_defects

        findings = merge_shared_defects(findings)
    unique = {(f.path, f.line, f.column, f.code, f.message): f for f in findings}
    from armtool.lint.checked import by_package

    checked = by_package(files, linter.counterparts)
    return LintResult(sorted(unique.values(), key=lambda f: f.sort_key), files, checked)
