"""The package version, written in this one place: ``bemcontact.__version__``,
and the distribution's metadata (pyproject.toml reads it from here with
scikit-build-core's regex provider)."""

__version__ = "0.1.0"
