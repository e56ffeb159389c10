"""No module of armtool imports, directly or through others, a module that imports it: every
dependency runs one way.

Modules that import each other, two of them or round a longer circle (a → b → c → a), can only be
loaded in one order, hide which is the lower layer, and cannot be understood apart. Every import
counts, at module level, inside a function (lazy) and under TYPE_CHECKING alike: each is a
dependency of one file on the other.
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


def import_graph(root: Path = ROOT) -> dict[str, set[str]]:
    """Every armtool module -> the armtool modules it imports."""
    modules = module_names(root)
    return {name: imported(name, path, modules) for name, path in modules.items()}


def import_circles(root: Path = ROOT) -> list[list[str]]:
    """The modules that reach one another through imports, one sorted list per circle
    (the graph's strongly connected components of more than one module, by Tarjan's algorithm)."""
    graph = import_graph(root)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    circles: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        for dep in sorted(graph[node]):
            if dep not in index:
                visit(dep)
                low[node] = min(low[node], low[dep])
            elif dep in stack:
                low[node] = min(low[node], index[dep])
        if low[node] == index[node]:
            members = [stack.pop()]
            while members[-1] != node:
                members.append(stack.pop())
            if len(members) > 1:
                circles.append(sorted(members))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return sorted(circles)


def test_no_module_reaches_itself_through_imports() -> None:
    assert import_circles() == []


def _package(tmp_path: Path, files: dict[str, str]) -> Path:
    pkg = tmp_path / "armtool"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("")
    for name, text in files.items():
        (pkg / "sub" / name).write_text(text)
    return tmp_path


def test_the_check_sees_lazy_and_type_checking_imports(tmp_path: Path) -> None:
    root = _package(
        tmp_path,
        {
            "a.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from armtool.sub.b import B\n",
            "b.py": "def f():\n    from . import a\n    return a\n",
            "c.py": "import armtool.sub.a\n",
        },
    )
    assert import_circles(root) == [["armtool.sub.a", "armtool.sub.b"]]


def test_the_check_sees_a_circle_through_several_modules(tmp_path: Path) -> None:
    # dataset -> measured -> problems -> dataset: no two of them import each other
    root = _package(
        tmp_path,
        {
            "dataset.py": "from armtool.sub.measured import parse\n",
            "measured.py": "def f():\n    from armtool.sub import problems\n",
            "problems.py": "from armtool.sub.dataset import Sample\n",
            "lower.py": "",
            "upper.py": "from armtool.sub import dataset, lower\n",
        },
    )
    assert import_circles(root) == [["armtool.sub.dataset", "armtool.sub.measured", "armtool.sub.problems"]]
