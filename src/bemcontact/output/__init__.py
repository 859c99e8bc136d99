"""Output: result files (JSON, VTU/PVD, CSV) in an output directory that
always holds one complete run, reading them back, and figures."""

from .read import read_csv
from .rundir import RunDirectory
from .write import OutputOptions, write_json, write_results, write_summary

__all__ = ["OutputOptions", "RunDirectory", "write_results", "write_summary", "write_json",
           "read_csv"]
