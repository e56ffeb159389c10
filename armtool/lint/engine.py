"""Find the files, load each kind, run the rules for it, apply config and inline ignores."""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator, Sequence
from enum import Enum
from pathlib import Path
from typing import NamedTuple

from armtool.errors import ArmtoolError
from armtool.lint.config import LintConfig
from armtool.lint.context import FileContext, UrdfContext
from armtool.lint.finding import Finding
from armtool.lint.locate import Locator, display_path, local_tag
from armtool.lint.registry import rule_class
from armtool.lint.rule import Rule, Target
from armtool.model.packages import PackageResolver
from armtool.model.xmlsource import XmlSyntaxProblem, declares_entities, parse_xml

SKIP_DIRS = {".git", ".hg", ".svn", ".venv", "venv", "node_modules", "__pycache__", "build", "install", "log"}
MAX_BYTES = 256 * 1024 * 1024


class FileKind(str, Enum):
    URDF = "urdf"
    XACRO = "xacro"
    SRDF = "srdf"
    KINEMATICS = "kinematics"


def file_kind(path: Path) -> FileKind | None:
    name = path.name.lower()
    if name.endswith(".srdf") or name.endswith(".srdf.xacro"):
        return FileKind.SRDF
    if name.endswith(".urdf"):
        return FileKind.URDF
    if name.endswith(".xacro"):
        return FileKind.XACRO
    if name.endswith(("kinematics.yaml", "kinematics.yml")):
        return FileKind.KINEMATICS
    return None


def collect_files(paths: Sequence[Path]) -> list[Path]:
    """Files named on the command line (any extension is taken as asked) and robot files below directories."""
    out: list[Path] = []
    for path in paths:
        if path.is_dir():
            found = sorted(_walk(path))
            if not found:
                raise ArmtoolError(
                    "no robot description files (.urdf, .xacro, .srdf, kinematics.yaml) found",
                    str(path),
                    "pass the files themselves, or a directory that holds them",
                )
            out.extend(found)
        elif path.is_file():
            out.append(path)
        elif path.exists():
            raise ArmtoolError("not a regular file", str(path))
        else:
            raise ArmtoolError("no such file or directory", str(path), "check the path")
    unique: dict[Path, None] = {}
    for p in out:
        unique.setdefault(p, None)
    return list(unique)


def _walk(directory: Path, seen: set[tuple[int, int]] | None = None) -> Iterator[Path]:
    """Robot files below a directory; each directory once, so symlink loops end."""
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
        elif file_kind(entry) is not None:
            yield entry


class LintOptions:
    def __init__(
        self,
        xacro_args: dict[str, str] | None = None,
        package_paths: Sequence[Path] = (),
        urdf: Path | None = None,
        srdf: Path | None = None,
        config: LintConfig | None = None,
    ) -> None:
        self.xacro_args = dict(xacro_args or {})
        self.package_paths = list(package_paths)
        self.urdf = urdf
        self.srdf = srdf
        self.config = config if config is not None else LintConfig()


class LintResult(NamedTuple):
    findings: list[Finding]
    files: list[Path]


def rules_for(target: Target) -> list[Rule]:
    from armtool.lint.registry import rules_for as registered

    return [rule() for rule in registered(target)]


def _file_finding(code: str, path: Path, line: int, column: int, message: str, hint: str | None = None) -> Finding:
    rule = rule_class(code)
    return Finding(display_path(path), line, column, rule.code, rule.name, rule.severity, message, hint)


def _read(path: Path) -> bytes:
    try:
        size = path.stat().st_size
        if size > MAX_BYTES:
            raise ArmtoolError(f"file is {size // (1024 * 1024)} MB, above armtool's limit of {MAX_BYTES // (1024 * 1024)} MB", str(path))
        return path.read_bytes()
    except OSError as exc:
        raise ArmtoolError(f"cannot read file: {exc.strerror}", str(path)) from None


class Linter:
    def __init__(self, options: LintOptions) -> None:
        self.options = options
        self.resolver = PackageResolver(options.package_paths)
        self._urdf_cache: dict[Path, UrdfContext | None] = {}

    # ---- URDF and xacro -------------------------------------------------
    def load_urdf(self, path: Path) -> tuple[UrdfContext | None, list[Finding]]:
        """Parse a URDF or expand a xacro. Returns the context (None if unusable) and loader findings."""
        kind = file_kind(path)
        if kind is FileKind.XACRO or path.name.lower().endswith(".xacro"):
            return self._load_xacro(path)
        data = _read(path)
        try:
            root = parse_xml(data)
        except XmlSyntaxProblem as exc:
            return None, [_file_finding("U001", path, exc.line, exc.column, f"not well-formed XML: {exc.message}")]
        findings = []
        if declares_entities(root):
            findings.append(
                _file_finding("U003", path, 1, 1, "DOCTYPE declares entities; armtool does not expand them",
                              "remove the DOCTYPE; use xacro properties instead")
            )
        if local_tag(root) != "robot":
            findings.append(
                _file_finding("U002", path, root.sourceline or 1, 1, f"root element is <{local_tag(root)}>, not <robot>",
                              "a URDF file holds one <robot name=\"...\"> element")
            )
            return None, findings
        return UrdfContext(path, root, Locator(path, data=data), self.resolver, raw=data), findings

    def _load_xacro(self, path: Path) -> tuple[UrdfContext | None, list[Finding]]:
        from armtool.model.xacro_source import XacroFailure, expand

        _read(path)
        try:
            expansion = expand(path, self.options.xacro_args, self.resolver)
        except XacroFailure as exc:
            return None, [_file_finding("X001", exc.path, exc.line, 1, f"xacro failed: {exc.message}",
                                        "fix the xacro, or pass --xacro-arg NAME:=VALUE / --package-path DIR")]
        root = expansion.root
        if local_tag(root) != "robot":
            return None, [_file_finding("U002", path, 1, 1, f"expanded root element is <{local_tag(root)}>, not <robot>")]
        ctx = UrdfContext(path.resolve(), root, Locator(path.resolve(), expansion.origins), self.resolver, from_xacro=True)
        return ctx, []

    def lint_urdf(self, path: Path) -> list[Finding]:
        ctx, findings = self.load_urdf(path)
        if ctx is None:
            return findings
        if ctx.from_xacro and not ctx.links and not ctx.joints:
            return findings  # a macro library: nothing to check until a robot uses it
        return findings + list(self._run(ctx, Target.URDF))

    # ---- SRDF --------------------------------------------------------------
    def _urdf_for_srdf(self, srdf: Path, robot_name: str | None) -> Path | None:
        if self.options.urdf is not None:
            return self.options.urdf
        here = srdf.parent
        places = [here, here.parent]
        try:
            places += sorted(p for p in here.parent.iterdir() if p.is_dir() and p != here)
        except OSError:
            pass
        candidates: list[Path] = []
        for place in places:
            try:
                candidates += sorted(p for p in place.iterdir() if p.is_file() and file_kind(p) in (FileKind.URDF, FileKind.XACRO))
            except OSError:
                continue
        # The SRDF's own file name is the strongest hint (anymal-kinova.srdf says robot "anymal"),
        # then a file named like its robot, then a URDF that declares that robot name.
        for stem in (srdf.name.split(".")[0], robot_name):
            for cand in candidates:
                if stem and cand.name.split(".")[0] == stem:
                    return cand
        if robot_name:
            pattern = re.compile(rb"<robot[^>]*\sname\s*=\s*[\"']" + re.escape(robot_name.encode()) + rb"[\"']")
            for cand in candidates:
                try:
                    head = cand.read_bytes()[:4096]
                except OSError:
                    continue
                if pattern.search(head):
                    return cand
        same_dir = [c for c in candidates if c.parent == here and file_kind(c) is FileKind.URDF]
        return same_dir[0] if len(same_dir) == 1 else None

    def _urdf_model(self, path: Path) -> UrdfContext | None:
        key = path.resolve()
        if key not in self._urdf_cache:
            self._urdf_cache[key] = self.load_urdf(path)[0]
        return self._urdf_cache[key]

    def load_srdf(self, path: Path) -> tuple[FileContext | None, list[Finding]]:
        from armtool.lint.srdf_context import SrdfContext

        data = _read(path)
        try:
            root = parse_xml(data)
        except XmlSyntaxProblem as exc:
            return None, [_file_finding("S001", path, exc.line, exc.column, f"not well-formed XML: {exc.message}")]
        if local_tag(root) != "robot":
            return None, [_file_finding("S001", path, root.sourceline or 1, 1, f"root element is <{local_tag(root)}>, not <robot>")]
        findings: list[Finding] = []
        urdf_path = self._urdf_for_srdf(path, root.get("name"))
        urdf = self._urdf_model(urdf_path) if urdf_path is not None else None
        if urdf is None:
            why = "no URDF found beside it" if urdf_path is None else f"its URDF {display_path(urdf_path)} could not be loaded"
            findings.append(_file_finding("S002", path, root.sourceline or 1, 1,
                                          f"cannot check names and limits against the robot: {why}",
                                          "pass --urdf PATH (a .urdf or .urdf.xacro)"))
        return SrdfContext(path, root, Locator(path, data=data), urdf), findings

    def lint_srdf(self, path: Path) -> list[Finding]:
        ctx, findings = self.load_srdf(path)
        if ctx is None:
            return findings
        return findings + list(self._run(ctx, Target.SRDF))

    # ---- kinematics.yaml -----------------------------------------------------
    def _srdf_for_kinematics(self, path: Path) -> Path | None:
        if self.options.srdf is not None:
            return self.options.srdf
        candidates = sorted(p for p in path.parent.glob("*.srdf"))
        return candidates[0] if len(candidates) == 1 else None

    def lint_kinematics(self, path: Path) -> list[Finding]:
        import yaml

        from armtool.lint.kinematics_context import KinematicsContext, read_groups
        from armtool.lint.srdf_context import SrdfContext

        text = _read(path).decode("utf-8", "replace")
        try:
            groups = read_groups(text)
        except yaml.YAMLError as exc:
            mark = getattr(exc, "problem_mark", None)
            line, col = (mark.line + 1, mark.column + 1) if mark else (1, 1)
            problem = getattr(exc, "problem", None) or str(exc)
            return [_file_finding("K001", path, line, col, f"invalid YAML: {problem}")]
        findings: list[Finding] = []
        srdf_path = self._srdf_for_kinematics(path)
        srdf_ctx = None
        if srdf_path is not None:
            loaded, _ = self.load_srdf(srdf_path)
            srdf_ctx = loaded if isinstance(loaded, SrdfContext) else None
        if srdf_ctx is None:
            findings.append(_file_finding("K002", path, 1, 1, "cannot check group names: no SRDF found beside it",
                                          "pass --srdf PATH"))
        ctx = KinematicsContext(path, groups, srdf_ctx)
        return findings + list(self._run(ctx, Target.KINEMATICS))

    # ---- common -----------------------------------------------------------------
    def _run(self, ctx: FileContext, target: Target) -> Iterator[Finding]:
        for rule in rules_for(target):
            yield from rule.check(ctx)

    def lint_file(self, path: Path) -> list[Finding]:
        kind = file_kind(path)
        if kind is FileKind.SRDF:
            return self.lint_srdf(path)
        if kind is FileKind.KINEMATICS:
            return self.lint_kinematics(path)
        return self.lint_urdf(path)


# Many files are linted by worker processes (forked, so they share the imported rules): a
# repository-wide pre-commit run or `armtool lint src/` then uses every core, as ruff does.
PARALLEL_MIN_FILES = 16
_worker_linter: Linter | None = None


def _lint_in_worker(path: Path) -> list[Finding]:
    assert _worker_linter is not None
    return _worker_linter.lint_file(path)


def _lint_all(files: list[Path], options: LintOptions) -> Iterator[list[Finding]]:
    global _worker_linter
    import os

    workers = min(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1), 8)
    linter = Linter(options)
    if len(files) < PARALLEL_MIN_FILES or workers < 2:
        for path in files:
            yield linter.lint_file(path)
        return
    import multiprocessing  # only now: its import costs a few ms of start-up

    if "fork" not in multiprocessing.get_all_start_methods():
        for path in files:
            yield linter.lint_file(path)
        return
    for target in Target:
        rules_for(target)  # import every rule before forking, not once per worker
    _worker_linter = linter
    # Largest files first, one at a time: a few big robots (Talos, Romeo) dominate the work.
    by_size = sorted(files, key=lambda p: -p.stat().st_size if p.exists() else 0)
    try:
        with multiprocessing.get_context("fork").Pool(workers) as pool:
            yield from pool.imap_unordered(_lint_in_worker, by_size, chunksize=1)
    finally:
        _worker_linter = None


def lint_paths(paths: Iterable[Path], options: LintOptions) -> LintResult:
    from armtool.lint.suppress import SuppressionIndex

    files = collect_files(list(paths))
    suppressions = SuppressionIndex()
    config = options.config
    findings: list[Finding] = []
    for file_findings in _lint_all(files, options):
        for finding in file_findings:
            if not config.keeps(finding) or suppressions.silenced(finding):
                continue
            findings.append(config.adjust(finding))
    unique = {(f.path, f.line, f.column, f.code, f.message): f for f in findings}
    return LintResult(sorted(unique.values(), key=lambda f: f.sort_key), files)
