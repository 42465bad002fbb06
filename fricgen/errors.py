"""The one family of errors fricgen reports to users: the CLI turns each into one stderr line."""
from __future__ import annotations


class FricgenError(ValueError):
    """Base of every error fricgen reports; the message names the problem in one line."""


class DataError(FricgenError):
    """Unusable data: a sweep, a motion log or a value derived from them."""


class ModelError(FricgenError):
    """An invalid model or model.json; the message names the offending field."""


class UsageError(FricgenError):
    """Bad command-line input that is neither a data nor a model problem."""


class BuildError(FricgenError):
    """The emitted C could not be compiled (no working C compiler, or it refused the code)."""
