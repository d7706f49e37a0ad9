"""The static checks configured in pyproject.toml: ruff (pyflakes, pycodestyle, bugbear, naming, pyupgrade, import
order, unused noqa) and mypy (untyped bodies checked, no half-annotated functions); every noqa and type: ignore
says why."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.timeout(300)
def test_ruff_finds_nothing() -> None:
    ruff = shutil.which("ruff", path=str(Path(sys.executable).parent)) or shutil.which("ruff")
    if ruff is None:
        pytest.skip("ruff is in the test extra: pip install -e '.[test]'")
    out = subprocess.run([ruff, "check", "drivers", "analysis", "instrument", "benchmarks", "tests", "tools"],
                         cwd=ROOT, capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr


@pytest.mark.timeout(600)
def test_mypy_finds_nothing() -> None:
    pytest.importorskip("mypy", reason="mypy is in the test extra: pip install -e '.[test]'")
    out = subprocess.run([sys.executable, "-m", "mypy"], cwd=ROOT, capture_output=True, text=True)
    assert out.returncode == 0, out.stdout[-4000:] + out.stderr[-2000:]


def test_every_package_declares_its_types() -> None:
    for package in ("drivers", "analysis", "instrument"):
        assert (ROOT / package / "py.typed").exists(), package


def test_every_suppression_says_why() -> None:
    """A ``noqa`` or ``type: ignore`` names its rule and, after it, why the rule does not apply there."""
    import re

    bare = []
    for package in ("drivers", "analysis", "instrument", "benchmarks", "tests", "tools"):
        for f in sorted((ROOT / package).rglob("*.py")):
            if f == Path(__file__).resolve():
                continue  # this test's own patterns
            for n, line in enumerate(f.read_text(encoding="utf-8").splitlines(), 1):
                if "noqa" in line and not re.search(r"noqa: [A-Z0-9, ]+ +(-|—|#) *\w", line):
                    bare.append(f"{f.relative_to(ROOT)}:{n}")
                if "type: ignore" in line and not re.search(r"type: ignore\[[a-z,_-]+\] +# *\w", line):
                    bare.append(f"{f.relative_to(ROOT)}:{n}")
    assert bare == []
