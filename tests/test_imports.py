"""The layout of src/walk3d: no import cycle between its modules nor between its packages, no
import of another package's private module or name, and no module over 400 lines.

The import graph is read from the source with :mod:`ast`, not by importing: every ``import`` and
``from ... import`` counts, also inside functions and ``if TYPE_CHECKING:`` blocks (an import
made lazy to dodge a cycle is still a cycle). Relative imports are resolved against the
importing module's package. ``from pkg import name`` is an edge to ``pkg.name`` when that is a
module, else to ``pkg``; only edges between modules under the scanned root are kept.

A package is the first level under the root (``walk3d.campaign``); a module at that level
(``walk3d.pipeline``, ``walk3d.api``) is a package of its own. Packages follow the data flow
(README, Layout), so no two of them may import each other, however indirectly.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src"
MAX_LINES = 400


def modules(root: Path) -> dict[str, Path]:
    """Dotted module name -> file, for every ``.py`` under ``root`` (packages by their name)."""
    out = {}
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def import_statements(mods: dict[str, Path]) -> Iterator[tuple[str, str, list[str]]]:
    """``(importer, module, names)`` of every import in ``mods``: ``import m`` gives ``m`` and
    no names, ``from m import a, b`` gives ``m`` (relative ones resolved) and ``[a, b]``."""
    for name, path in mods.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
            if isinstance(node, ast.Import):
                yield from ((name, a.name, []) for a in node.names)
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    anchor = package.split(".")
                    anchor = anchor[: len(anchor) - node.level + 1]
                    base = ".".join(anchor + ([base] if base else []))
                yield name, base, [a.name for a in node.names]


def import_graph(root: Path) -> dict[str, set[str]]:
    """Module -> the modules under ``root`` it imports (module doc)."""
    mods = modules(root)
    graph: dict[str, set[str]] = {name: set() for name in mods}
    for name, base, names in import_statements(mods):
        if not names and base in mods:
            graph[name].add(base)
        for alias in names:
            full = f"{base}.{alias}"
            if full in mods:
                graph[name].add(full)
            elif base in mods:
                graph[name].add(base)
    for name, targets in graph.items():
        # importing a.b.c runs a/__init__ and a/b/__init__ first, except those of the
        # importer's own packages, which are already running
        own = {name.rsplit(".", k)[0] for k in range(name.count(".") + 1)}
        for target in list(targets):
            parts = target.split(".")
            targets.update(p for p in (".".join(parts[:k]) for k in range(1, len(parts)))
                           if p in mods and p not in own)  # fmt: skip
    return graph


def import_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module, and modules importing themselves
    (Tarjan's algorithm, iterative), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            v, children = work[-1]
            w = next(children, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                elif w in on_stack:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                component = []
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    component.append(w)
                    if w == v:
                        break
                if len(component) > 1 or v in graph[v]:
                    cycles.append(sorted(component))
    return sorted(cycles)


def package_of(module: str) -> str:
    """The package ``module`` belongs to: its first two dotted parts (module doc)."""
    return ".".join(module.split(".")[:2])


def package_graph(graph: dict[str, set[str]]) -> dict[str, set[str]]:
    """Package -> the other packages its modules import, from a module graph."""
    out: dict[str, set[str]] = {}
    for module, targets in graph.items():
        source = package_of(module)
        out.setdefault(source, set()).update(package_of(t) for t in targets)
    for source, targets in out.items():
        targets.discard(source)
    return out


def private(name: str) -> bool:
    """Whether a module or name is private: one leading underscore (not a dunder)."""
    return name.startswith("_") and not name.startswith("__")


def private_imports(root: Path) -> list[str]:
    """``importer -> imported`` for every import of a private module or name (any dotted part
    after the root) from another package under ``root``, sorted."""
    mods = modules(root)
    found = set()
    for name, base, names in import_statements(mods):
        for target in [f"{base}.{a}" for a in names] or [base]:
            module = target if target in mods else target.rpartition(".")[0]
            if module in mods and package_of(module) != package_of(name):
                if any(private(part) for part in target.split(".")[1:]):
                    found.add(f"{name} -> {target}")
    return sorted(found)


def long_modules(root: Path, limit: int = MAX_LINES) -> dict[str, int]:
    """Files under ``root`` with more than ``limit`` lines -> their line count."""
    out = {}
    for path in sorted(root.rglob("*.py")):
        n = len(path.read_text(encoding="utf-8").splitlines())
        if n > limit:
            out[str(path.relative_to(root))] = n
    return out


def _write(root: Path, files: dict[str, str]) -> Path:
    for rel, text in files.items():
        path = root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    return root


def test_walk3d_has_no_import_cycle():
    graph = import_graph(SRC)
    assert "walk3d.results.prediction" in graph  # the scan found the package
    assert "walk3d.results.opensim" in graph["walk3d.results.prediction"]
    assert import_cycles(graph) == []


def test_walk3d_packages_import_each_other_in_one_direction():
    packages = package_graph(import_graph(SRC))
    assert {"walk3d.problem", "walk3d.campaign", "walk3d.pipeline", "walk3d.api"} <= set(packages)
    assert "walk3d.pipeline" in packages["walk3d.campaign"]  # a lazy import, read all the same
    assert import_cycles(packages) == []


def test_no_walk3d_package_imports_another_ones_private_names():
    assert private_imports(SRC) == []


def test_no_walk3d_module_is_longer_than_400_lines():
    assert len(modules(SRC)) > 50
    assert long_modules(SRC) == {}


def test_cycle_checker_finds_cycles(tmp_path):
    """Negative control: synthetic packages with cycles made every way the checker must see."""
    root = _write(
        tmp_path,
        {
            # pkg -> pkg.g (star import) -> pkg (from pkg import name that is not a module)
            "pkg/__init__.py": "from pkg.g import *\n",
            "pkg/g.py": "from pkg import VERSION\n",
            # a -> b (in a function) -> c (relative, type-checking only) -> a (from pkg import a)
            "pkg/a.py": "def f():\n    from pkg.b import g\n    return g\n",
            "pkg/b.py": "from typing import TYPE_CHECKING\n\nif TYPE_CHECKING:\n"
            "    from .c import h\n\ng = 1\n",
            "pkg/c.py": "from pkg import a\n\nh = a\n",
            # self-import, and an acyclic pair: d -> e
            "pkg/s.py": "import pkg.s\n",
            "pkg/d.py": "from . import e\n",
            "pkg/e.py": "import os\n",
            # sub -> sub.x -> sub (relative, two levels: ``sub`` is a module of ``pkg``)
            "pkg/sub/__init__.py": "from pkg.sub.x import X\n",
            "pkg/sub/x.py": "from .. import sub\n\nX = sub\n",
            # q.sub -> q.x -> q.sub.y, which runs q/sub/__init__ first: a cycle through a parent
            "q/__init__.py": "",
            "q/sub/__init__.py": "from q.x import X\n",
            "q/x.py": "from q.sub.y import Y\n\nX = Y\n",
            "q/sub/y.py": "Y = 1\n",
        },
    )
    graph = import_graph(root)
    assert graph["pkg.d"] == {"pkg.e"}
    assert ["q.sub", "q.x"] in import_cycles(graph)
    assert [c for c in import_cycles(graph) if c[0].startswith("pkg")] == [
        ["pkg", "pkg.g"],
        ["pkg.a", "pkg.b", "pkg.c"],
        ["pkg.s"],
        ["pkg.sub", "pkg.sub.x"],
    ]
    (root / "pkg/c.py").write_text("h = 1\n", encoding="utf-8")
    assert ["pkg.a", "pkg.b", "pkg.c"] not in import_cycles(import_graph(root))


def test_line_limit_finds_long_modules(tmp_path):
    """Negative control: a 401-line file is reported, a 400-line one is not."""
    root = _write(tmp_path, {"pkg/long.py": "x = 1\n" * 401, "pkg/ok.py": "x = 1\n" * 400})
    assert long_modules(root) == {"pkg/long.py": 401}


def test_package_cycle_checker_finds_cycles_that_no_module_cycle_makes(tmp_path):
    """Negative control: a -> b (module level), b -> c (lazy, c a top-level module), c -> a
    (type checking only) close a loop of packages while every module graph edge points onward;
    d -> a is no loop."""
    root = _write(
        tmp_path,
        {
            "pkg/__init__.py": "",
            "pkg/a/__init__.py": "",
            "pkg/a/x.py": "from pkg.b.y import Y\n\nX = Y\n",
            "pkg/a/w.py": "W = 1\n",
            "pkg/b/__init__.py": "",
            "pkg/b/y.py": "Y = 1\n",
            "pkg/b/z.py": "def f():\n    from pkg.c import C\n\n    return C\n",
            "pkg/c.py": "from typing import TYPE_CHECKING\n\nif TYPE_CHECKING:\n"
            "    from pkg.a import w\n\nC = 1\n",
            "pkg/d/__init__.py": "",
            "pkg/d/m.py": "from ..a.x import X\n",
        },
    )
    graph = import_graph(root)
    assert import_cycles(graph) == []
    packages = package_graph(graph)
    assert packages["pkg.d"] == {"pkg.a"}
    assert import_cycles(packages) == [["pkg.a", "pkg.b", "pkg.c"]]
    (root / "pkg/b/z.py").write_text("Z = 1\n", encoding="utf-8")
    assert import_cycles(package_graph(import_graph(root))) == []


def test_private_import_checker_finds_them_across_packages_only(tmp_path):
    """Negative control: private modules and names imported from another package every way
    (absolute, relative, lazy, ``from package import _module``) are reported; from the same
    package, and dunder names, are not."""
    root = _write(
        tmp_path,
        {
            "pkg/__init__.py": "",
            "pkg/_top.py": "T = 1\n",
            "pkg/a/__init__.py": "",
            "pkg/a/_hidden.py": "H = 1\n",
            "pkg/a/mod.py": "def _f():\n    return 1\n\n\nY = 1\n",
            "pkg/a/inner.py": "from pkg.a._hidden import H\nfrom .mod import _f\n",
            "pkg/b/__init__.py": "",
            "pkg/b/uses.py": "import pkg.a._hidden\nfrom pkg.a import _hidden, mod\n"
            "from pkg.a.mod import Y, __doc__\n\n\ndef g():\n    from ..a.mod import _f\n\n"
            "    return _f\n",
            "pkg/b/top.py": "from pkg._top import T\n",
        },
    )
    assert private_imports(root) == [
        "pkg.b.top -> pkg._top.T",
        "pkg.b.uses -> pkg.a._hidden",
        "pkg.b.uses -> pkg.a.mod._f",
    ]
    (root / "pkg/b/uses.py").write_text("from pkg.a.mod import Y\n", encoding="utf-8")
    (root / "pkg/b/top.py").write_text("T = 1\n", encoding="utf-8")
    assert private_imports(root) == []
