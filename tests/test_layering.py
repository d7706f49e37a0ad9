"""Import rules: analysis imports nothing from drivers/instrument and no Qt; drivers no Qt, no instrument."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
RULES = {
    "analysis": {"drivers", "instrument", "PySide6", "pyqtgraph", "shiboken6"},
    "drivers": {"instrument", "PySide6", "pyqtgraph", "shiboken6"},
}


def imported_roots(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(), filename=str(path))
    roots: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            roots |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            roots.add(node.module.split(".")[0])
    return roots


@pytest.mark.parametrize("package", sorted(RULES))
def test_package_respects_import_rules(package: str) -> None:
    files = sorted((ROOT / package).rglob("*.py"))
    assert files, f"{package}/ has no modules"
    bad = {str(f.relative_to(ROOT)): sorted(imported_roots(f) & RULES[package]) for f in files}
    assert not {k: v for k, v in bad.items() if v}


def test_rule_checker_sees_violations(tmp_path: Path) -> None:
    f = tmp_path / "m.py"
    f.write_text("import os\nfrom PySide6.QtCore import QTimer\nfrom .local import x\n")
    assert imported_roots(f) == {"os", "PySide6"}
