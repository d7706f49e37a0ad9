"""Import rules between the layers and inside the application, and no import circles.

* ``analysis`` imports nothing from ``drivers``/``instrument`` and no Qt; ``drivers`` no Qt, no
  ``instrument`` and no ``analysis`` (the simulated world keeps its own constants; gravity comes in
  as a parameter).
* Inside ``instrument``: Qt only in ``gui/``; ``live/`` (what runs during a trial) never imports
  ``offline/`` (what runs after it), ``sim/`` or ``gui/``; the kinds never import ``offline/``,
  ``sim/``, ``gui/`` or the command line; the store never imports a kind or what runs after a trial.
* No module imports, directly or around a circle, a module that imports it back: every import
  counts, including those inside functions (an import under ``TYPE_CHECKING`` does not run).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
QT = {"PySide6", "pyqtgraph", "shiboken6"}
RULES = {
    "analysis": {"drivers", "instrument"} | QT,
    "drivers": {"instrument", "analysis"} | QT,
}
#: inside instrument/: sub-package → the sub-packages (and modules) it must not import
INSIDE = {
    "live": {"offline", "sim", "gui", "cli"},
    "kinds": {"offline", "sim", "gui", "cli"},
    "store": {"offline", "sim", "gui", "cli", "kinds"},
    "offline": {"sim", "gui", "cli"},
    "sim": {"cli"},  # the demo saves the operator window's screens through gui/ (Qt stays there)
}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _type_checking_only(node: ast.AST) -> bool:
    return isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING"


def imports_of(path: Path) -> set[str]:
    """Every module ``path`` imports when it runs (absolute names; inside functions too; not under ``TYPE_CHECKING``)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    inside = ROOT in path.resolve().parents
    name = module_name(path) if inside else path.stem
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    skip = {id(n) for top in ast.walk(tree) if _type_checking_only(top) for n in ast.walk(top)}
    out: set[str] = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            out.add(mod)
            out |= {f"{mod}.{a.name}" for a in node.names}  # ``from pkg import module``
    return out


def imported_roots(path: Path) -> set[str]:
    return {m.split(".")[0] for m in imports_of(path) if m}


def project_modules() -> dict[str, Path]:
    return {module_name(f): f for pkg in ("analysis", "drivers", "instrument") for f in (ROOT / pkg).rglob("*.py")}


def import_graph() -> dict[str, set[str]]:
    """Module → the project modules it imports (a registry that finds its modules at run time,
    ``instrument.kinds``, imports every module of its package)."""
    mods = project_modules()
    graph = {m: {i for i in imports_of(p) if i in mods and i != m} for m, p in mods.items()}
    graph["instrument.kinds"] |= {m for m in mods if m.startswith("instrument.kinds.")}
    return graph


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
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


@pytest.mark.parametrize("package", sorted(RULES))
def test_package_respects_import_rules(package: str) -> None:
    files = sorted((ROOT / package).rglob("*.py"))
    assert files, f"{package}/ has no modules"
    bad = {str(f.relative_to(ROOT)): sorted(imported_roots(f) & RULES[package]) for f in files}
    assert not {k: v for k, v in bad.items() if v}


def test_qt_only_in_the_gui() -> None:
    files = [f for f in (ROOT / "instrument").rglob("*.py") if "gui" not in f.relative_to(ROOT).parts]
    assert {str(f.relative_to(ROOT)): sorted(imported_roots(f) & QT) for f in files if imported_roots(f) & QT} == {}


@pytest.mark.parametrize("sub", sorted(INSIDE))
def test_instrument_sub_packages_respect_their_floors(sub: str) -> None:
    files = sorted((ROOT / "instrument" / sub).rglob("*.py"))
    assert files, f"instrument/{sub}/ has no modules"
    forbidden = {f"instrument.{s}" for s in INSIDE[sub]}
    bad = {str(f.relative_to(ROOT)): sorted(m for m in imports_of(f) if any(m == x or m.startswith(x + ".")
                                                                          for x in forbidden)) for f in files}
    assert {k: v for k, v in bad.items() if v} == {}


def test_no_import_circles() -> None:
    assert circles(import_graph()) == []


def test_rule_checker_sees_violations_and_circles(tmp_path: Path) -> None:
    f = tmp_path / "m.py"
    f.write_text("import os\nfrom PySide6.QtCore import QTimer\nfrom .local import x\n"
                 "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import numpy\n"
                 "def later():\n    import scipy\n")
    assert imported_roots(f) - {""} == {"os", "PySide6", "typing", "scipy"}  # not numpy: TYPE_CHECKING
    assert circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert circles({"a": {"b"}, "b": set()}) == []
