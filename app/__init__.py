"""trikecert: lateral stability certification of keke, tadpole trikes and quadricycles."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("trikecert")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"
