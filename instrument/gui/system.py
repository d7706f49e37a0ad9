"""The system libraries Qt's X11 platform plugin (xcb) loads, checked before the window opens.

Qt names only the first library it misses ("could not load the Qt platform plugin xcb"); a Debian 12
machine lacked three of them at once. This check names every missing one, with its package per
distribution, in one line. Headless runs (``QT_QPA_PLATFORM=offscreen``), Wayland and other platforms
need none of them.
"""

from __future__ import annotations

import ctypes.util
import os

from ..errors import InstrumentError

#: library (as ``ctypes.util.find_library`` names it) → (Debian/Ubuntu package, Fedora package)
XCB_LIBRARIES: dict[str, tuple[str, str]] = {
    "xcb-cursor": ("libxcb-cursor0", "xcb-util-cursor"),
    "xcb-icccm": ("libxcb-icccm4", "xcb-util-wm"),
    "xcb-keysyms": ("libxcb-keysyms1", "xcb-util-keysyms"),
    "xcb-image": ("libxcb-image0", "xcb-util-image"),
    "xcb-render-util": ("libxcb-render-util0", "xcb-util-renderutil"),
    "xcb-xkb": ("libxcb-xkb1", "libxcb"),
    "xkbcommon-x11": ("libxkbcommon-x11-0", "libxkbcommon-x11"),
    "xcb-shape": ("libxcb-shape0", "libxcb"),
    "xcb-randr": ("libxcb-randr0", "libxcb"),
    "xcb-xinerama": ("libxcb-xinerama0", "libxcb"),
    "EGL": ("libegl1", "mesa-libEGL"),
    "fontconfig": ("libfontconfig1", "fontconfig"),
}


class GuiSystemError(InstrumentError):
    """System libraries the operator window needs are missing (names them and their packages)."""


def missing_libraries(find: object = ctypes.util.find_library) -> list[str]:
    """The libraries of :data:`XCB_LIBRARIES` this machine does not have (``find`` for tests)."""
    return [lib for lib in XCB_LIBRARIES if not find(lib)]  # type: ignore[operator]  # a find_library-like callable


def check_gui_system(environ: dict[str, str] | None = None, find: object = ctypes.util.find_library) -> None:
    """Raise :class:`GuiSystemError` naming the missing libraries, when the window would open on X11.

    :raises GuiSystemError: one line: the libraries, the apt and dnf commands that install them.
    """
    env = os.environ if environ is None else environ
    platform = env.get("QT_QPA_PLATFORM", "")
    if platform and not platform.startswith("xcb"):
        return  # offscreen, wayland, vnc, ...: not the xcb plugin
    if not platform and env.get("WAYLAND_DISPLAY") and not env.get("DISPLAY"):
        return
    missing = missing_libraries(find)
    if missing:
        debian = sorted({XCB_LIBRARIES[m][0] for m in missing})
        fedora = sorted({XCB_LIBRARIES[m][1] for m in missing})
        raise GuiSystemError(f"the operator window needs system libraries this machine lacks ({', '.join(missing)}): "
                             f"Debian/Ubuntu: sudo apt install {' '.join(debian)}; Fedora: sudo dnf install "
                             f"{' '.join(fedora)} (or QT_QPA_PLATFORM=offscreen for a run without a screen)")
