"""The instrument application: acquisition, recording, session store, trial protocols, GUI, command line."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("afo-gait-instrument")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"
