"""The operator window's system libraries: every missing one named with its package, in one line."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from instrument.cli import main
from instrument.gui import system
from instrument.gui.system import GuiSystemError, check_gui_system


def _lacking(*names: str) -> Callable[[str], str | None]:
    """A ``find_library`` stand-in that finds every library but ``names``."""
    return lambda lib: None if lib in names else f"lib{lib}.so"


def test_every_missing_library_is_named_with_its_packages() -> None:
    with pytest.raises(GuiSystemError) as info:
        check_gui_system({"DISPLAY": ":0"}, _lacking("xcb-cursor", "xcb-icccm", "xcb-keysyms"))
    text = str(info.value)
    assert "\n" not in text
    assert "sudo apt install libxcb-cursor0 libxcb-icccm4 libxcb-keysyms1" in text
    assert "xcb-util-cursor" in text and "xcb-util-wm" in text


def test_nothing_is_asked_of_a_headless_or_complete_machine() -> None:
    check_gui_system({"QT_QPA_PLATFORM": "offscreen"}, _lacking(*system.XCB_LIBRARIES))
    check_gui_system({"WAYLAND_DISPLAY": "wayland-0"}, _lacking(*system.XCB_LIBRARIES))
    check_gui_system({"DISPLAY": ":0"}, _lacking())


def test_gui_refuses_in_one_line_when_libraries_are_missing(monkeypatch: pytest.MonkeyPatch,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    from instrument.gui import app

    monkeypatch.setenv("QT_QPA_PLATFORM", "xcb")
    monkeypatch.setattr(app, "check_gui_system", lambda: check_gui_system(None, _lacking("xcb-cursor")))
    assert main(["gui", "--simulate"]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: the operator window needs system libraries") and "libxcb-cursor0" in err
    assert len(err.splitlines()) == 1
