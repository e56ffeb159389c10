"""`[tool.armtool.lint]` in pyproject.toml: select, ignore, per-file-ignores, severity, fail-on."""

from __future__ import annotations

import fnmatch
import os
import sys
from pathlib import Path
from typing import Any

from armtool.errors import ArmtoolError
from armtool.lint.finding import Finding, Severity
from armtool.lint.registry import CODES, NAMES

_KEYS = {"select", "ignore", "per-file-ignores", "severity", "fail-on"}


def _valid_selector(sel: str) -> bool:
    if sel.upper() == "ALL" or sel.lower() in NAMES:
        return True
    return any(code.startswith(sel.upper()) for code in CODES)


def selector_matches(sel: str, finding: Finding) -> bool:
    if sel.upper() == "ALL":
        return True
    return finding.code.startswith(sel.upper()) or finding.name == sel.lower()


class LintConfig:
    def __init__(self, root: Path | None = None, source: Path | None = None) -> None:
        self.select: list[str] = ["ALL"]
        self.ignore: list[str] = []
        self.per_file_ignores: dict[str, list[str]] = {}
        self.severity: dict[str, Severity] = {}
        self.fail_on = Severity.ERROR
        self.root = root if root is not None else Path.cwd()
        self.source = source

    def keeps(self, finding: Finding) -> bool:
        if not any(selector_matches(s, finding) for s in self.select):
            return False
        if any(selector_matches(s, finding) for s in self.ignore):
            return False
        if not self.per_file_ignores:
            return True
        rel = _relative(Path(finding.path), self.root)
        for pattern, selectors in self.per_file_ignores.items():
            if fnmatch.fnmatch(rel, pattern) or fnmatch.fnmatch(Path(rel).name, pattern):
                if any(selector_matches(s, finding) for s in selectors):
                    return False
        return True

    def adjust(self, finding: Finding) -> Finding:
        for sel, severity in self.severity.items():
            if selector_matches(sel, finding):
                return finding.with_severity(severity)
        return finding


def _relative(path: Path, root: Path) -> str:
    try:
        return os.path.relpath(path.resolve(), root.resolve()).replace(os.sep, "/")
    except ValueError:
        return str(path)


def find_pyproject(start: Path) -> Path | None:
    for directory in [start, *start.parents]:
        candidate = directory / "pyproject.toml"
        if candidate.is_file():
            return candidate
    return None


def _selectors(value: Any, key: str, where: str) -> list[str]:
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ArmtoolError(f"'{key}' must be a list of rule codes", where, 'e.g. select = ["U", "S101"]')
    for sel in value:
        if not _valid_selector(sel):
            raise ArmtoolError(f"unknown rule '{sel}' in '{key}'", where, "run `armtool rules` for the list of codes")
    return list(value)


def _severity(value: Any, where: str) -> Severity:
    try:
        return Severity(str(value).lower())
    except ValueError:
        raise ArmtoolError(f"unknown severity '{value}'", where, "use error, warning or info") from None


def load_config(path: Path | None = None) -> LintConfig:
    """Read the config from `path`, or from the nearest pyproject.toml above the working directory."""
    if path is None:
        path = find_pyproject(Path.cwd())
        if path is None:
            return LintConfig()
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ArmtoolError(f"cannot read config: {exc.strerror}", str(path)) from None
    if "armtool" not in text:
        return LintConfig(root=path.parent, source=path)  # not ours: skip the TOML parser's start-up cost
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # Python 3.10 (Ubuntu 22.04, ROS 2 Humble): the same parser, from PyPI
        import tomli as tomllib

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ArmtoolError(f"invalid TOML: {exc}", str(path)) from None
    section = data.get("tool", {}).get("armtool", {}).get("lint")
    if section is None:
        return LintConfig(root=path.parent, source=path)
    where = f"{path} [tool.armtool.lint]"
    if not isinstance(section, dict):
        raise ArmtoolError("[tool.armtool.lint] must be a table", where)
    unknown = set(section) - _KEYS
    if unknown:
        raise ArmtoolError(f"unknown key(s): {', '.join(sorted(unknown))}", where, "known keys: " + ", ".join(sorted(_KEYS)))
    cfg = LintConfig(root=path.parent, source=path)
    if "select" in section:
        cfg.select = _selectors(section["select"], "select", where)
    if "ignore" in section:
        cfg.ignore = _selectors(section["ignore"], "ignore", where)
    pfi = section.get("per-file-ignores", {})
    if not isinstance(pfi, dict):
        raise ArmtoolError("'per-file-ignores' must be a table of glob = [codes]", where)
    cfg.per_file_ignores = {str(k): _selectors(v, f"per-file-ignores.{k}", where) for k, v in pfi.items()}
    sev = section.get("severity", {})
    if not isinstance(sev, dict):
        raise ArmtoolError("'severity' must be a table of code = \"error|warning|info\"", where)
    for sel, value in sev.items():
        _selectors([sel], "severity", where)
        cfg.severity[sel] = _severity(value, where)
    if "fail-on" in section:
        cfg.fail_on = _severity(section["fail-on"], where)
    return cfg


__all__ = ["LintConfig", "load_config"]
