"""Problem files: the schema (every key, its type, range, default and
documentation), the value checks with their one-line errors, and the reader
that turns a TOML file into bodies, a contact pair, options and load steps."""

from .reader import Problem, ProblemFile, load_problem

__all__ = ["ProblemFile", "Problem", "load_problem"]
