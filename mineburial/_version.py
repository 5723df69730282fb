"""The package version, in a leaf module that imports nothing of mineburial (so that any
module can record the version without importing the package's ``__init__``)."""

from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as _version

try:
    __version__ = _version("mineburial")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"
