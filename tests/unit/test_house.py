"""The shape of the package (DESIGN.md, "Layout"): no import circles, core/ depends only on itself
and model/, no module past about 1,000 lines, and the old import paths users may have still work.

The import graph is read with the standard library's ``ast`` from the source (every ``import`` and
``from ... import`` anywhere in a module, function-level ones included), so a circle hidden in a
lazy import counts too.
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src"
PKG = SRC / "moorline"
#: "no module over about 1,000 lines" (DESIGN.md, "Style")
MAX_LINES = 1000


def _modules() -> dict[str, Path]:
    out = {}
    for p in PKG.rglob("*.py"):
        name = ".".join(p.relative_to(SRC).with_suffix("").parts)
        out[name.removesuffix(".__init__")] = p
    return out


def _runtime_nodes(tree: ast.AST):
    """Every node except those under ``if TYPE_CHECKING:`` (imports for type hints only, which
    never run: DESIGN.md lets views name the System that way)."""
    todo = [tree]
    while todo:
        node = todo.pop()
        yield node
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and isinstance(child.test, ast.Name) and child.test.id == "TYPE_CHECKING":
                todo.extend(child.orelse)
                continue
            todo.append(child)


def _import_graph() -> dict[str, set[str]]:
    mods = _modules()
    graph: dict[str, set[str]] = {m: set() for m in mods}
    for m, p in mods.items():
        pkg = m if p.name == "__init__.py" else m.rpartition(".")[0]
        for node in _runtime_nodes(ast.parse(p.read_text(), str(p))):
            if isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    parts = pkg.split(".")
                    parts = parts[: len(parts) - node.level + 1]
                    base = ".".join(parts + ([base] if base else []))
                names = [base] + [f"{base}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            else:
                continue
            for n in names:
                # 'from .x import y' imports module x (and y if it is a module); a package import
                # runs its __init__, which counts as importing that package module
                if n in mods and n != m:
                    graph[m].add(n)
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def _is_package_init_edge(a: str, b: str, mods: dict[str, Path]) -> bool:
    """A package's __init__ re-exporting its own submodules is not a circle of the design."""
    return mods[a].name == "__init__.py" and b.startswith(a + ".")


def test_cycle_finder_sees_a_circle():
    """The checker itself: a three-module circle is found, a chain is not."""
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []


def test_no_module_imports_one_that_imports_it_back():
    mods = _modules()
    graph = {m: {n for n in deps if not _is_package_init_edge(m, n, mods)} for m, deps in _import_graph().items()}
    assert _cycles(graph) == []


def test_core_depends_only_on_core_and_model():
    graph = _import_graph()
    bad = {m: sorted(n for n in deps if not n.startswith(("moorline.core", "moorline.model")))
           for m, deps in graph.items() if m.startswith("moorline.core")}
    assert {m: d for m, d in bad.items() if d} == {}


def test_lower_layers_do_not_import_upper_ones():
    """model -> nothing of moorline but errors; io -> model; post -> numpy/xarray only;
    quasistatic -> model and core kernels."""
    graph = _import_graph()
    allowed = {
        "moorline.model": ("moorline.model",),
        "moorline.io": ("moorline.io", "moorline.model", "moorline.errors"),
        "moorline.post": ("moorline.post",),
        "moorline.quasistatic": ("moorline.quasistatic", "moorline.model", "moorline.core"),
    }
    bad = {}
    for m, deps in graph.items():
        for layer, ok in allowed.items():
            if m == layer or m.startswith(layer + "."):
                wrong = sorted(n for n in deps if not n.startswith(ok))
                if wrong:
                    bad[m] = wrong
    assert bad == {}


def test_no_module_past_about_a_thousand_lines():
    long = {m: n for m, p in _modules().items() if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert long == {}


@pytest.mark.parametrize("path, names", [
    ("moorline", ["System", "simulate", "Model", "Trajectory", "DeckError", "SimulationError"]),
    ("moorline.coupling", ["System", "LineView", "PointView", "RodView", "BodyView"]),
    ("moorline.batch", ["Study", "run_sweep", "run_case", "register_parameter", "sea_waves", "PARAMETERS",
                        "StudyError", "SweepError", "SweepResult", "CaseSpec"]),
    ("moorline.cli", ["main"]),
])
def test_old_import_paths_keep_working(path, names):
    mod = importlib.import_module(path)
    missing = [n for n in names if not hasattr(mod, n)]
    assert missing == []


def test_old_paths_are_the_same_objects():
    import moorline
    import moorline.batch
    import moorline.coupling
    import moorline.studies
    import moorline.system

    assert moorline.coupling.System is moorline.system.System is moorline.System
    assert moorline.batch.run_sweep is moorline.studies.run_sweep
