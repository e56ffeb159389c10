"""Lint configuration: `[tool.armtool.lint]` in pyproject.toml, or `[lint]` in armtool.toml (for
repositories without a pyproject.toml; armtool.toml wins when a directory has both).

Keys: select, ignore, per-file-ignores, severity, fail-on; and for real ROS repositories
package-paths (relative to the config file), xacro-args (glob = {name = value}), urdf
(SRDF glob = URDF path) and srdf (kinematics.yaml glob = SRDF path).
"""

from __future__ import annotations

import fnmatch
import os
import re
import sys
from pathlib import Path
from typing import Any

from armtool.errors import ArmtoolError
from armtool.lint.finding import Finding, Severity
from armtool.lint.registry import CODES, NAMES

MAX_VARIANTS = 16  # argument sets one file is linted with, at most

_KEYS = {"select", "ignore", "per-file-ignores", "severity", "fail-on", "package-paths", "xacro-args", "urdf", "srdf"}
CONFIG_NAMES = ("armtool.toml", "pyproject.toml")


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
        self.package_paths: list[Path] = []
        # glob -> argument sets; more than one set: each is a variant of the file, linted in turn
        self.xacro_args: dict[str, list[dict[str, str]]] = {}
        self.urdf: dict[str, Path] = {}
        self.srdf: dict[str, Path] = {}

    def _matches(self, pattern: str, path: Path) -> bool:
        rel = _relative(path, self.root)
        return fnmatch.fnmatch(rel, pattern) or fnmatch.fnmatch(path.name, pattern)

    def xacro_args_for(self, path: Path) -> dict[str, str]:
        """xacro arguments of every glob that matches the file, in the order written (of a glob
        with several argument sets, the first: what commands other than lint expand)."""
        out: dict[str, str] = {}
        for pattern, sets in self.xacro_args.items():
            if self._matches(pattern, path):
                out.update(sets[0])
        return out

    def xacro_arg_sets(self, path: Path) -> list[dict[str, str]]:
        """Every argument set the file is linted with: one per combination of the sets of the
        globs that match it (a single set when no glob lists several)."""
        combos: list[dict[str, str]] = [{}]
        for pattern, sets in self.xacro_args.items():
            if self._matches(pattern, path):
                combos = [{**done, **more} for done in combos for more in sets][:MAX_VARIANTS]
        return combos

    def urdf_for(self, srdf: Path) -> Path | None:
        """The URDF the config pairs with this SRDF (the first matching glob)."""
        return next((urdf for pattern, urdf in self.urdf.items() if self._matches(pattern, srdf)), None)

    def srdf_for(self, kinematics: Path) -> Path | None:
        return next((srdf for pattern, srdf in self.srdf.items() if self._matches(pattern, kinematics)), None)

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
    """The nearest armtool.toml or pyproject.toml at or above `start`."""
    for directory in [start, *start.parents]:
        for name in CONFIG_NAMES:
            candidate = directory / name
            if candidate.is_file():
                return candidate
    return None


class _Place:
    """Where a setting of one configuration file is written: `at(key, ...)` is `file:line` of
    that key inside the armtool section (found in the text only when an error needs it)."""

    def __init__(self, path: Path, text: str, section: tuple[str, ...]) -> None:
        self.path, self.text, self.section = path, text, section
        self._lines: dict[tuple[str, ...], int] | None = None

    def at(self, *keys: str, inside: bool = True) -> str:
        from armtool.toml_lines import key_lines, line_of

        if self._lines is None:
            self._lines = key_lines(self.text)
        line = line_of(self._lines, (*self.section, *keys) if inside else keys)
        return f"{self.path}:{line}" if line is not None else str(self.path)


def _paths_table(value: Any, key: str, place: _Place, root: Path) -> dict[str, Path]:
    hint = f'e.g. {key} = {{ "config/*.srdf" = "urdf/arm.urdf.xacro" }}'
    if not isinstance(value, dict):
        raise ArmtoolError(f"'{key}' must be a table of glob = \"path\", not {_kind(value)}", place.at(key), hint)
    for glob, target in value.items():
        if not isinstance(target, str):
            raise ArmtoolError(
                f"'{key}.{glob}' must be a path (a string), not {_kind(target)}", place.at(key, glob), hint
            )
    return {str(k): root / v for k, v in value.items()}


def _xacro_args(value: Any, place: _Place) -> dict[str, list[dict[str, str]]]:
    hint = (
        'e.g. xacro-args = { "urdf/ur.urdf.xacro" = { name = "ur", ur_type = "ur5e" } }, or a list of such '
        'tables for variants: "robots/gen3.xacro" = [{ dof = "6" }, { dof = "7" }]'
    )
    if not isinstance(value, dict):
        raise ArmtoolError(
            f"'xacro-args' must be a table of glob = {{ name = value }}, not {_kind(value)}",
            place.at("xacro-args"),
            hint,
        )
    out: dict[str, list[dict[str, str]]] = {}
    for pattern, args in value.items():
        if isinstance(args, list) and all(isinstance(a, str) and ":=" in a for a in args):
            args = dict(a.split(":=", 1) for a in args)
        sets = args if isinstance(args, list) and args and all(isinstance(a, dict) for a in args) else [args]
        for one in sets:
            if not isinstance(one, dict) or not all(isinstance(v, (str, int, float, bool)) for v in one.values()):
                raise ArmtoolError(
                    f"'xacro-args.{pattern}' must be a table of name = value", place.at("xacro-args", pattern), hint
                )
        out[str(pattern)] = [
            {str(k): (str(v).lower() if isinstance(v, bool) else str(v)) for k, v in one.items()} for one in sets
        ]
    return out


def _kind(value: Any) -> str:
    """What a TOML value is, for messages: "a string", "a list", "a table"."""
    kinds: list[tuple[type, str]] = [(bool, "a boolean"), (str, "a string"), (int, "a number"), (float, "a number")]
    kinds += [(list, "a list"), (dict, "a table")]
    return next((name for kind, name in kinds if isinstance(value, kind)), "a date or time")


def check_selector(sel: str, key: str, where: str | None = None) -> str:
    """`sel` if it names a rule, a code prefix or ALL; else an error with the closest code or name.
    A selector that matches nothing would silently check nothing (a CI that can never fail)."""
    if sel.strip() and _valid_selector(sel):
        return sel
    from armtool.suggest import did_you_mean

    hint = did_you_mean(sel.upper(), list(CODES)) or did_you_mean(sel.lower(), list(NAMES))
    raise ArmtoolError(
        f"unknown rule '{sel}' in {key}{hint}",
        where,
        "use a code (U301), a prefix (U3, S) or a name (rpy-out-of-range); `armtool rules` lists them",
    )


def parse_selectors(text: str, flag: str) -> list[str]:
    """`--select U3,S101` as a list of checked selectors; an empty list is an error (nothing would run)."""
    items = [s.strip() for s in text.split(",") if s.strip()]
    if not items:
        raise ArmtoolError(f"{flag} names no rule", hint=f"e.g. {flag} U3,S101; `armtool rules` lists the codes")
    return [check_selector(s, flag) for s in items]


def _selectors(value: Any, key: tuple[str, ...], place: _Place, allow_empty: bool = True) -> list[str]:
    name = ".".join(key)
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        what = (
            _kind(value)
            if not isinstance(value, list)
            else "a list holding " + _kind(next(v for v in value if not isinstance(v, str)))
        )
        raise ArmtoolError(
            f"'{name}' must be a list of rule codes, not {what}", place.at(*key), 'a list such as ["U", "S101"]'
        )
    if not value and not allow_empty:
        raise ArmtoolError(
            f"'{name}' is empty: no rule would run",
            place.at(*key),
            'list codes or prefixes (select = ["U", "S101"]), or remove the key for all rules',
        )
    return [check_selector(sel, f"'{name}'", place.at(*key)) for sel in value]


def _severity(value: Any, key: tuple[str, ...], place: _Place) -> Severity:
    if not isinstance(value, str):
        raise ArmtoolError(
            f"'{'.'.join(key)}' must be a severity (a string), not {_kind(value)}",
            place.at(*key),
            'use "error", "warning" or "info"',
        )
    try:
        return Severity(value.lower())
    except ValueError:
        raise ArmtoolError(f"unknown severity '{value}'", place.at(*key), "use error, warning or info") from None


def _table(value: Any, name: str, where: str, hint: str) -> dict[str, Any]:
    """`value` if it is a table; a string, a list (`[[...]]`) or a number where armtool's settings
    table belongs is an error, never a configuration read as empty."""
    if not isinstance(value, dict):
        raise ArmtoolError(f"{name} must be a table, not {_kind(value)}", where, hint)
    return value


def load_config(path: Path | None = None) -> LintConfig:
    """Read the config from `path`, or from the nearest armtool.toml / pyproject.toml above the working directory."""
    if path is None:
        path = find_pyproject(Path.cwd())
        if path is None:
            return LintConfig()
    try:
        text = path.read_bytes().decode("utf-8")
    except OSError as exc:
        raise ArmtoolError(f"cannot read config: {exc.strerror}", str(path)) from None
    except UnicodeDecodeError as exc:
        line = exc.object[: exc.start].count(b"\n") + 1
        raise ArmtoolError(
            "config is not UTF-8 text (TOML files are UTF-8)", f"{path}:{line}", "save it as UTF-8"
        ) from None
    own_file = path.name == "armtool.toml"
    if not own_file and "armtool" not in text:
        return LintConfig(root=path.parent, source=path)  # not ours: skip the TOML parser's start-up cost
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # Python 3.10 (Ubuntu 22.04, ROS 2 Humble): the same parser, from PyPI
        import tomli as tomllib

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        # tomllib says where in its message: "... (at line 2, column 3)", or "(at end of document)"
        found = re.search(r"\(at line (\d+), column (\d+)\)$", str(exc))
        end = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
        where = f"{path}:{found.group(1)}:{found.group(2)}" if found else f"{path}:{max(end, 1)}"
        message = re.sub(r"\s*\(at (line \d+, column \d+|end of document)\)$", "", str(exc))
        raise ArmtoolError(f"invalid TOML: {message}", where, "fix the TOML syntax there") from None
    except RecursionError:  # the parser recurses per nested array or inline table
        raise ArmtoolError(
            "TOML nested too deeply to read", str(path), "no armtool setting nests more than a few levels"
        ) from None
    name = "[lint]" if own_file else "[tool.armtool.lint]"
    place = _Place(path, text, ("lint",) if own_file else ("tool", "armtool", "lint"))
    if own_file:
        tool = data.get("tool")
        if isinstance(tool, dict) and "armtool" in tool:  # pyproject.toml's layout in armtool's own file: never read
            raise ArmtoolError(
                "armtool.toml holds [tool.armtool], which only a pyproject.toml has",
                place.at("tool", "armtool", inside=False),
                "in armtool.toml the settings go under [lint] ([lint.xacro-args], ...)",
            )
        top = data
        unknown_top = sorted(set(top) - {"lint"})
        section = top.get("lint")
    else:
        # pyproject.toml's [tool] holds one table per tool (PEP 518); armtool's is [tool.armtool],
        # and its settings are [tool.armtool.lint]. `tool = "armtool"`, `tool.armtool = "lint"`,
        # `[[tool.armtool]]`: not a table where one is needed, refused at its line.
        hint = "write [tool.armtool.lint] with its keys below it"
        if "tool" not in data:
            return LintConfig(root=path.parent, source=path)
        tool = _table(data["tool"], "[tool]", place.at("tool", inside=False), hint)
        if "armtool" not in tool:
            return LintConfig(root=path.parent, source=path)
        top = _table(tool["armtool"], "[tool.armtool]", place.at("tool", "armtool", inside=False), hint)
        unknown_top = sorted(set(top) - {"lint"})
        section = top.get("lint")
    if unknown_top:  # lint's keys one level too high (`[tool.armtool]` then `select = ...`): never ignored
        container = "armtool.toml" if own_file else "[tool.armtool]"
        keys = (unknown_top[0],) if own_file else ("tool", "armtool", unknown_top[0])
        raise ArmtoolError(
            f"unknown key(s) in {container}: {', '.join(unknown_top)}",
            place.at(*keys, inside=False),
            f"put {unknown_top[0]} = ... under {name}"
            if unknown_top[0] in _KEYS
            else f"the only table armtool reads here is {name}",
        )
    if section is None:
        return LintConfig(root=path.parent, source=path)
    section = _table(section, name, place.at(), f"write {name} with its keys below it")
    unknown = sorted(set(section) - _KEYS)
    if unknown:
        raise ArmtoolError(
            f"unknown key(s) in {name}: {', '.join(unknown)}",
            place.at(unknown[0]),
            "known keys: " + ", ".join(sorted(_KEYS)),
        )
    cfg = LintConfig(root=path.parent, source=path)
    if "select" in section:
        cfg.select = _selectors(section["select"], ("select",), place, allow_empty=False)
    if "ignore" in section:
        cfg.ignore = _selectors(section["ignore"], ("ignore",), place)
    pfi = section.get("per-file-ignores", {})
    if not isinstance(pfi, dict):
        raise ArmtoolError(
            f"'per-file-ignores' must be a table of glob = [codes], not {_kind(pfi)}",
            place.at("per-file-ignores"),
            'e.g. per-file-ignores = { "urdf/legacy_*.urdf" = ["U401"] }',
        )
    cfg.per_file_ignores = {str(k): _selectors(v, ("per-file-ignores", k), place) for k, v in pfi.items()}
    sev = section.get("severity", {})
    if not isinstance(sev, dict):
        raise ArmtoolError(
            f"'severity' must be a table of code = \"error|warning|info\", not {_kind(sev)}",
            place.at("severity"),
            'e.g. severity = { U401 = "error" }',
        )
    for sel, value in sev.items():
        _selectors([sel], ("severity", sel), place)
        cfg.severity[sel] = _severity(value, ("severity", sel), place)
    if "fail-on" in section:
        cfg.fail_on = _severity(section["fail-on"], ("fail-on",), place)
    paths = section.get("package-paths", [])
    if isinstance(paths, str):
        paths = [paths]
    if not isinstance(paths, list) or not all(isinstance(p, str) for p in paths):
        raise ArmtoolError(
            "'package-paths' must be a list of directories (strings)",
            place.at("package-paths"),
            'e.g. package-paths = ["src"]',
        )
    cfg.package_paths = [path.parent / p for p in paths]
    cfg.xacro_args = _xacro_args(section.get("xacro-args", {}), place)
    cfg.urdf = _paths_table(section.get("urdf", {}), "urdf", place, path.parent)
    cfg.srdf = _paths_table(section.get("srdf", {}), "srdf", place, path.parent)
    return cfg


__all__ = ["LintConfig", "load_config"]
