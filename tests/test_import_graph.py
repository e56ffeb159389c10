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


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The nodes that reach one another, one sorted list per circle: the graph's strongly
    connected components of more than one node (SciPy's csgraph)."""
    import numpy as np
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components

    nodes = sorted(graph)
    at = {name: i for i, name in enumerate(nodes)}
    edges = np.array([(at[a], at[b]) for a in nodes for b in graph[a] if b in at], dtype=np.intp).reshape(-1, 2)
    adjacency = csr_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(len(nodes), len(nodes)))
    _count, labels = connected_components(adjacency, directed=True, connection="strong")
    groups: dict[int, list[str]] = {}
    for name, label in zip(nodes, labels):
        groups.setdefault(int(label), []).append(name)
    return sorted(members for members in groups.values() if len(members) > 1)


def import_circles(root: Path = ROOT) -> list[list[str]]:
    """The modules that reach one another through imports."""
    return circles(import_graph(root))


def stage_circles(package: str, root: Path = ROOT) -> list[list[str]]:
    """The subpackages (and modules) directly under `package` that reach one another through imports:
    each is one stage, and a stage may use the ones below it only."""
    depth = package.count(".") + 2

    def stage(module: str) -> str | None:
        return ".".join(module.split(".")[:depth]) if module.startswith(package + ".") else None

    graph: dict[str, set[str]] = {}
    for module, deps in import_graph(root).items():
        own = stage(module)
        if own is not None:
            graph.setdefault(own, set()).update(s for s in map(stage, deps) if s is not None and s != own)
    return circles(graph)


def test_no_module_reaches_itself_through_imports() -> None:
    assert import_circles() == []


def test_the_calibration_stages_import_one_way() -> None:
    # model < targets < inputs < fit < outputs < simulation < pipeline: a stage that needs a later
    # one's code has it in the wrong place (docs/development.md, "How `armtool calibrate` is built")
    assert stage_circles("armtool.calib") == []


def _package(tmp_path: Path, files: dict[str, str]) -> Path:
    pkg = tmp_path / "armtool"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("")
    for name, text in files.items():  # "fit/problems.py": in a subpackage
        (pkg / "sub" / name).parent.mkdir(exist_ok=True)
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


def test_the_stage_check_sees_two_stages_that_need_each_other(tmp_path: Path) -> None:
    # no module circle, but inputs needs fit and fit needs inputs
    root = _package(
        tmp_path,
        {
            "inputs/__init__.py": "",
            "inputs/files.py": "",
            "inputs/reader.py": "from armtool.sub.fit.problems import P\n",
            "fit/__init__.py": "",
            "fit/problems.py": "",
            "fit/reader.py": "from armtool.sub.inputs.files import F\n",
        },
    )
    assert import_circles(root) == []
    assert stage_circles("armtool.sub", root) == [["armtool.sub.fit", "armtool.sub.inputs"]]
