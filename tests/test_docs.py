"""The documentation: built with MkDocs in strict mode (every link and image found), the command reference
generated from the parser and current, the README short."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_the_command_reference_is_the_parser_s() -> None:
    from instrument.cli_reference import cli_reference

    assert (ROOT / "docs" / "cli.md").read_text(encoding="utf-8") == cli_reference(), \
        "docs/cli.md is stale: python -m instrument.cli_reference > docs/cli.md"


def test_the_site_builds_with_every_link_found(tmp_path: Path) -> None:
    pytest.importorskip("mkdocs")
    out = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
                         cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-3000:]
    assert (tmp_path / "site" / "operator" / "index.html").is_file()


def test_the_readme_is_short_and_starts_with_the_two_commands() -> None:
    lines = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    assert len(lines) <= 150
    blocks = [ln for ln in lines[:15] if ln.startswith("python3 -m venv")]
    assert len(blocks) == 2 and "instrument demo" in blocks[0] and "pytest" in blocks[1]
    # CI runs exactly the README's test command
    assert blocks[1] in (ROOT / ".ci" / "run").read_text(encoding="utf-8")
