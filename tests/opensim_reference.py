"""OpenSim as an independent reference, run in a subprocess.

OpenSim's Python wheel bundles its own CasADi (for Moco), which cannot share a process with the
``casadi`` wheel the estimator uses; every OpenSim evaluation therefore runs in a child
interpreter that prints JSON.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
import textwrap
from typing import Any

import pytest


def have_opensim() -> bool:
    return importlib.util.find_spec("opensim") is not None


def run_opensim(script: str, timeout_s: float = 120.0) -> Any:
    """Run ``script`` (which prints one JSON document last) with OpenSim imported as ``osim``."""
    if not have_opensim():
        pytest.skip("OpenSim (pip install opensim, in the test extra) is the independent reference")
    code = "import json, opensim as osim\n" + textwrap.dedent(script)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout_s)
    if out.returncode != 0:
        raise RuntimeError(f"OpenSim reference failed:\n{out.stderr[-2000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])
