"""The package version (one place; ``bemcontact.__version__``)."""

__version__ = "0.1.0"
