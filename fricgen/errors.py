"""The one family of errors fricgen reports to users: the CLI turns each into one stderr line."""
from __future__ import annotations


class FricgenError(ValueError):
    """Base of every error fricgen reports; the message names the problem in one line.

    A ``ValueError``, so that code catching bad values catches it too; the command line turns any
    of its subclasses into one stderr line and an exit status (2 for ``UsageError``, else 1).

    Examples
    --------
    >>> from fricgen import DataError, FricgenError
    >>> issubclass(DataError, FricgenError) and issubclass(FricgenError, ValueError)
    True
    """


class DataError(FricgenError):
    """Unusable data: a sweep, a motion log or a value derived from them.

    Examples
    --------
    >>> import fricgen
    >>> try:
    ...     fricgen.Sweep([0.0, 0.1], [1.0])
    ... except fricgen.DataError as exc:
    ...     print(type(exc).__name__)
    DataError
    """


class ModelError(FricgenError):
    """An invalid model or model.json; the message names the offending field.

    Examples
    --------
    >>> import fricgen
    >>> try:
    ...     fricgen.FrictionModel.from_dict({"format": "other"})
    ... except fricgen.ModelError:
    ...     print("refused")
    refused
    """


class UsageError(FricgenError):
    """Bad command-line input that is neither a data nor a model problem (exit status 2).

    Examples
    --------
    >>> from fricgen import UsageError
    >>> str(UsageError("--vs-max must be > 0, got -1"))
    '--vs-max must be > 0, got -1'
    """


class BuildError(FricgenError):
    """The emitted C could not be compiled (no working C compiler, or it refused the code).

    Examples
    --------
    >>> from fricgen.errors import BuildError, FricgenError
    >>> issubclass(BuildError, FricgenError)
    True
    """
