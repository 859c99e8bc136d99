"""Output: result files (JSON, VTU/PVD, CSV), reading them back, figures,
and progress reports."""

from .read import read_csv
from .write import OutputOptions, write_json, write_results, write_summary

__all__ = ["OutputOptions", "write_results", "write_summary", "write_json", "read_csv"]
