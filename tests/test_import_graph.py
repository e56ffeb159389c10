"""No module of armtool imports from a module that imports it: every dependency runs one way.

Two modules that import each other can only be loaded in one order, hide which is the lower layer,
and cannot be understood apart. Every import counts, at module level, inside a function (lazy) and
under TYPE_CHECKING alike: each is a dependency of one file on the other.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def module_names(root: Path = ROOT) -> dict[str, Path]:
    """Dotted name -> file, for every module of the armtool package (a package is its __init__)."""
    out: dict[str, Path] = {}
    for path in sorted((root / "armtool").rglob("*.py")):
        parts = path.relative_to(root).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def imported(module: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The armtool modules that `module` imports anywhere in its file."""
    found: set[str] = set()
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base_parts = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                base = ".".join(base_parts + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            for alias in node.names:  # `from armtool.cli import options`: the submodule, if it is one
                found.add(f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base)
    return {name for name in found if name in modules and name != module}


def mutual_imports(root: Path = ROOT) -> list[tuple[str, str]]:
    modules = module_names(root)
    graph = {name: imported(name, path, modules) for name, path in modules.items()}
    return sorted({(a, b) for a, deps in graph.items() for b in deps if a < b and a in graph[b]})


def test_no_module_imports_a_module_that_imports_it() -> None:
    assert mutual_imports() == []


def test_the_check_sees_lazy_and_type_checking_imports(tmp_path: Path) -> None:
    pkg = tmp_path / "armtool"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "a.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from armtool.sub.b import B\n"
    )
    (pkg / "sub" / "b.py").write_text("def f():\n    from . import a\n    return a\n")
    (pkg / "sub" / "c.py").write_text("import armtool.sub.a\n")
    assert mutual_imports(tmp_path) == [("armtool.sub.a", "armtool.sub.b")]
