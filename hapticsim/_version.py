"""The package version, in a module that imports nothing (lower layers read it without
importing the package root)."""

__version__ = "0.1.0"
