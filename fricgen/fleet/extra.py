"""The optional extra ``fricgen[fleet]`` (Dask ``distributed`` and pyarrow), imported only when a
fleet runs."""
from __future__ import annotations

from ..errors import UsageError

MISSING_EXTRA = "fricgen fleet needs Dask and pyarrow: pip install 'fricgen[fleet]'"


def need(module: str):
    """Import an optional module of the ``fleet`` extra, or one ``UsageError`` line."""
    try:
        return __import__(module, fromlist=["_"])
    except ImportError:
        raise UsageError(f"{MISSING_EXTRA} ({module} is missing)") from None
