"""Shared fixtures; hardware tests are opt-in with --device-url (never needed in CI)."""

from __future__ import annotations

import os

import pytest

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
# liblsl's warnings only (the instrument's own setting; tests that import pylsl first would get INFO lines)
os.environ.setdefault("LSLAPICFG", os.path.join(os.path.dirname(__file__), "..", "drivers", "lsl", "lsl_api.cfg"))


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption("--device-url", action="append", default=[],
                     help="URL of a real device for the *_with_device tests (repeatable)")


@pytest.fixture
def device_urls(request: pytest.FixtureRequest) -> list[str]:
    urls = request.config.getoption("--device-url")
    if not urls:
        pytest.skip("hardware test: pass --device-url to run it")
    return urls
