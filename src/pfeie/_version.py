"""The package version, the single place it is set."""

__version__ = "0.3.25"
