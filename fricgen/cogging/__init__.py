"""Cogging: the position force of an axis identified from a slow move (``identify``) and held as
a sparse Fourier series that the firmware samples into a table (``map``). Loaded on first use:
``fricgen.model`` holds a map, and the identification reads logs through ``fricgen.data``."""
from .._lazy import lazy_names

_PUBLIC = {"CoggingFit": "identify", "identify_cogging": "identify", "CoggingMap": "map"}
__all__ = sorted(_PUBLIC)
__getattr__, __dir__ = lazy_names(globals(), _PUBLIC)
