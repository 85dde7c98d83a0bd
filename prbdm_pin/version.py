"""The package version, in one place (the package, its files and the truth's cache key read it)."""

__version__ = "0.1.0"
