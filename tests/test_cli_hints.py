"""Every option a command's messages name is an option that command has.

A hint such as "pass --xacro-arg NAME:=VALUE" is only useful when the command that printed it
takes --xacro-arg (`traj` said so, and had no such option). For each command this test collects
the modules it can reach (its own module and everything they import, at module level or inside
functions, within armtool), takes every string those modules can print (messages and hints, not
docstrings and not option declarations), and checks each `--option` in them against the
command's real options. An option that follows `armtool SUBCOMMAND` in the same string is checked
against that subcommand instead ("run `armtool lint --fix`").
"""

from __future__ import annotations

import ast
import re
from functools import cache
from pathlib import Path
from typing import Any

import typer.main

from armtool.cli.typer_app import build_app

ROOT = Path(__file__).resolve().parents[1] / "armtool"
RULES_DIR = ROOT / "lint" / "rules"
OPTION = re.compile(r"(?<![\w-])--[a-z][a-z0-9]*(?:-[a-z0-9]+)*")
MENTION = re.compile(r"armtool\s+([a-z][a-z-]*(?:\s+[a-z][a-z-]*)?)")
# Options of programs other than armtool that messages quote (pip, xacro, ros2, git).
FOREIGN = {"--inorder", "--symlink-install", "--packages-select", "--user", "--upgrade"}


def _module_path(name: str) -> Path | None:
    parts = name.split(".")
    if parts[0] != "armtool":
        return None
    base = ROOT.joinpath(*parts[1:])
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


@cache
def _parsed(path: Path) -> ast.Module:
    return ast.parse(path.read_text(encoding="utf-8"))


class _Module:
    """A module's top-level names: imports (module or module.attr), definitions, constants."""

    def __init__(self, name: str) -> None:
        path = _module_path(name)
        assert path is not None
        self.name = name
        self.package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
        self.tree = _parsed(path)
        self.names: dict[str, tuple[str, object]] = {}
        for node in self.tree.body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                self.names[node.name] = ("def", node)
            elif isinstance(node, (ast.Assign, ast.AnnAssign)):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                for target in targets:
                    if isinstance(target, ast.Name):
                        self.names[target.id] = ("value", node)
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                self.names.update(_bindings(node, self.package))
            elif isinstance(node, ast.If):  # `if TYPE_CHECKING:` imports name types only
                continue


def _bindings(node: ast.Import | ast.ImportFrom, package: str) -> dict[str, tuple[str, object]]:
    out: dict[str, tuple[str, object]] = {}
    if isinstance(node, ast.Import):
        for alias in node.names:
            if alias.asname:
                out[alias.asname] = ("module", alias.name)
            else:
                out[alias.name.split(".")[0]] = ("module", alias.name.split(".")[0])
        return out
    base = node.module or ""
    if node.level:
        parts = package.split(".")
        anchor = parts[: len(parts) - node.level + 1]
        base = ".".join([*anchor, base] if base else anchor)
    for alias in node.names:
        full = f"{base}.{alias.name}"
        kind = ("module", full) if _module_path(full) is not None else ("symbol", (base, alias.name))
        out[alias.asname or alias.name] = kind
    return out


@cache
def _module(name: str) -> _Module | None:
    return _Module(name) if _module_path(name) is not None else None


def _reachable_strings(module: str, function: str) -> tuple[list[tuple[str, str]], set[str]]:
    """(module, text) of every string the function can print, following what it calls: armtool's
    functions and classes by name, and methods by attribute name on the classes it uses (a
    method is followed when some reached code names it: `limits.require_acceleration()`);
    annotations are not calls. Also the modules it reaches."""
    start = _module(module)
    assert start is not None and function in start.names
    todo: list[tuple[str, str]] = [(module, function)]
    seen: set[tuple[str, str]] = set()
    texts: list[tuple[str, str]] = []
    modules: set[str] = set()
    classes: list[tuple[str, ast.ClassDef]] = []
    attributes: set[str] = set()
    visited_methods: set[int] = set()

    def lookup(mod: _Module, local: dict[str, tuple[str, object]], name: str) -> tuple[str, object]:
        return local.get(name) or mod.names.get(name, ("", None))

    def visit(mod: _Module, node: ast.AST) -> None:
        texts.extend((mod.name, t) for t in _printed_strings(node))
        local: dict[str, tuple[str, object]] = {}
        annotations: set[int] = set()
        for sub in ast.walk(node):
            if isinstance(sub, (ast.Import, ast.ImportFrom)):
                local.update(_bindings(sub, mod.package))
            for ann in _annotations(sub):
                annotations.update(id(a) for a in ast.walk(ann))
        for sub in ast.walk(node):
            if id(sub) in annotations:
                continue
            if isinstance(sub, ast.Name):
                kind, target = lookup(mod, local, sub.id)
                if kind in ("def", "value"):
                    todo.append((mod.name, sub.id))
                elif kind == "symbol":
                    todo.append(target)  # type: ignore[arg-type]
            elif isinstance(sub, ast.Attribute):
                attributes.add(sub.attr)
                if isinstance(sub.value, ast.Name):
                    kind, target = lookup(mod, local, sub.value.id)
                    if kind == "module" and _module(str(target)) is not None:
                        todo.append((str(target), sub.attr))

    while True:
        while todo:
            mod_name, name = todo.pop()
            if (mod_name, name) in seen:
                continue
            seen.add((mod_name, name))
            mod = _module(mod_name)
            if mod is None or name not in mod.names:
                continue
            kind, target = mod.names[name]
            if kind == "symbol":  # a re-export: follow it
                todo.append(target)  # type: ignore[arg-type]
                continue
            if kind not in ("def", "value"):
                continue
            modules.add(mod_name)
            if isinstance(target, ast.ClassDef):
                classes.append((mod_name, target))
                body = target.body
                if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                    body = body[1:]  # the docstring
                for item in body:  # the class body itself, without its methods
                    if not isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)):
                        visit(mod, item)
            else:
                visit(mod, target)  # type: ignore[arg-type]
        pending = [
            (mod_name, item)
            for mod_name, cls in classes
            for item in cls.body
            if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef))
            and id(item) not in visited_methods
            and (item.name in attributes or (item.name.startswith("__") and item.name.endswith("__")))
        ]
        if not pending:
            return texts, modules
        for mod_name, item in pending:
            visited_methods.add(id(item))
            mod = _module(mod_name)
            assert mod is not None
            visit(mod, item)


def _annotations(node: ast.AST) -> list[ast.AST]:
    """The annotation expressions a node carries (types, not calls)."""
    out: list[ast.AST] = []
    if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
        args = node.args
        for arg in [*args.posonlyargs, *args.args, *args.kwonlyargs, args.vararg, args.kwarg]:
            if arg is not None and arg.annotation is not None:
                out.append(arg.annotation)
        if node.returns is not None:
            out.append(node.returns)
    elif isinstance(node, ast.AnnAssign):
        out.append(node.annotation)
    return out


def _is_declaration(node: ast.Call) -> bool:
    func = node.func
    name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
    return name in ("Option", "Argument")


def _printed_strings(tree: ast.AST) -> list[str]:
    """String literals in a definition that can end up in a message: docstrings and the arguments
    of typer.Option/Argument (declarations and their help texts) are left out."""
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                skip.add(id(first.value))
        if isinstance(node, ast.Call) and _is_declaration(node):
            skip.update(id(sub) for sub in ast.walk(node))
    texts: list[str] = []
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.JoinedStr):
            texts.append(
                "".join(v.value for v in node.values if isinstance(v, ast.Constant) and isinstance(v.value, str))
            )
            skip.update(id(v) for v in node.values)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            texts.append(node.value)
    return texts


def _commands() -> dict[str, tuple[Any, str]]:
    """'traj time' -> (click command, module of its callback)."""
    root = typer.main.get_command(build_app())
    out: dict[str, tuple[Any, str]] = {}

    def walk(group: Any, prefix: str) -> None:
        if hasattr(group, "commands"):
            for name, sub in group.commands.items():
                walk(sub, f"{prefix} {name}".strip())
        else:
            callback = group.callback
            module = getattr(getattr(callback, "__wrapped__", callback), "__module__", "")
            out[prefix] = (group, f"{module}:{getattr(callback, '__wrapped__', callback).__name__}")

    walk(root, "")
    return out


def _options(command: Any) -> set[str]:
    return {opt for param in command.params for opt in (*param.opts, *param.secondary_opts)} | {"--help"}


def _named_command(text: str, at: int, name: str, commands: dict[str, set[str]]) -> set[str] | None:
    """The options of the command a text names before position `at` on the same command line
    (`armtool traj time PATH --urdf`); None when it names none (the option is then the printing
    command's own)."""
    best: tuple[int, set[str]] | None = None
    for match in MENTION.finditer(text, 0, at):
        if re.search(r"[`);,]|\bor\b|\band\b", text[match.end() : at]):
            continue  # the command line it named ended before the option
        said = match.group(1)
        target = said if said in commands else said.split()[0]
        options = commands.get(target) or set().union(*(o for n, o in commands.items() if n.startswith(target + " ")))
        best = (match.start(), options)
    return None if best is None else best[1]


# Options a reached message names only when that option's value was given, which only the
# commands that have it can do (found by following calls, not values).
GIVEN_ONLY = {
    ("armtool.traj.check", "--max-step"): "the absolute jump rule reports --max-step only when CheckOptions.max_step "
    "is set, which only `traj check` does",
    ("armtool.traj.check", "--vel-limit"): "T304's hint, a warning: the commands that write a trajectory print "
    "only check's errors (pipeline.checked_text), so only `traj check` (which has --vel-limit) shows it",
    ("armtool.calib.model.terms.compliance", "--params"): "`calibrate apply` builds the terms through "
    "calib.apply.apply, which re-raises their errors with its own hint (--dataset); only `calibrate fit`, "
    "which has --params, shows them as they are",
    ("armtool.servo.lut.table", "--clip"): "only angles outside the table are refused with it: `servo-lut check` draws "
    "its angles inside the table, fit/export reach the method only through a field of the same name (command_ticks)",
}


def test_every_hint_names_an_option_of_its_command() -> None:
    commands = _commands()
    options = {name: _options(cmd) for name, (cmd, _) in commands.items()}
    problems: list[str] = []
    for name, (command, where) in sorted(commands.items()):
        own = _options(command)
        module, function = where.split(":")
        texts, _ = _reachable_strings(module, function)
        if name in ("lint", "lint-urdf"):  # rules are imported by name from the registry: walk each
            for rule in sorted(RULES_DIR.glob("[a-z][0-9][0-9][0-9]_*.py")):
                rule_module = f"armtool.lint.rules.{rule.stem}"
                texts += [(rule_module, t) for t in _printed_strings(_parsed(rule))]
        for reached, text in texts:
            if OPTION.fullmatch(text.strip()):
                continue  # a bare flag is a label passed along with the value it gave, not a hint
            for match in OPTION.finditer(text):
                option = match.group(0)
                if option in FOREIGN or (reached, option) in GIVEN_ONLY:
                    continue
                named = _named_command(text, match.start(), name, options)
                if option not in (own if named is None else named):
                    problems.append(f"`armtool {name}` can print {option!r} ({reached}: {text[:90]!r})")
    assert not problems, "\n".join(dict.fromkeys(problems))


def test_the_walk_sees_every_robot_command() -> None:
    """The walk is not vacuous: it finds the commands, and their xacro hint among their strings."""
    commands = _commands()
    for name in ("lint", "expand", "tree", "ik-bench", "calibrate simulate", "traj time", "traj cartesian"):
        assert name in commands
        module, function = commands[name][1].split(":")
        _, reached = _reachable_strings(module, function)
        assert "armtool.model.xacro_source" in reached, name
