"""Cogging: the position force of an axis identified from a slow move (``identify``) and held as
a sparse Fourier series that the firmware samples into a table (``map``)."""
from .identify import CoggingFit, identify_cogging
from .map import CoggingMap

__all__ = ["CoggingFit", "CoggingMap", "identify_cogging"]
