"""Bin means of a force over one period of the position, per direction of motion, and their
Fourier coefficients: the screening of ``fit.cogging`` (a bin a direction left unvisited, where
the axis stalled for a moment, is interpolated from the bins beside it)."""
from __future__ import annotations

import numpy as np

from ..errors import DataError

#: Fewest position bins per period.
MIN_BINS = 32
#: The share of the bins a direction may leave unvisited (an axis that stalls for a moment at a
#: cogging peak): their means are interpolated from the bins beside them.
MAX_EMPTY = 0.01


def bin_index(x, period, bins):
    """The bin (of ``bins`` per period) each position falls in."""
    return np.floor((x % period) / period * bins).astype(int) % bins


def bin_cap(most) -> int:
    """The largest power of two from MIN_BINS up to ``most``: the finest position bins a pass
    can fill (``most`` half its samples or counts per period)."""
    bins = MIN_BINS
    while 2 * bins <= most:
        bins *= 2
    return bins


def filled_bins(x, sign, period, most) -> int:
    """The most position bins per period (``bin_cap`` of ``most`` down) that each direction
    visits all but MAX_EMPTY of (the encoder's steps and the sample rate leave finer bins
    empty); DataError if the move does not cover the period each way."""
    bins = bin_cap(most)
    while True:
        empty = [(label, np.bincount(bin_index(x[sign == d], period, bins), minlength=bins) == 0)
                 for d, label in ((1, "+"), (-1, "-"))]
        if all(e.mean() <= MAX_EMPTY for _, e in empty):
            return bins
        if bins == MIN_BINS:
            label, e = next((label, e) for label, e in empty if e.mean() > MAX_EMPTY)
            raise DataError(f"the move covers {1 - e.mean():.0%} of one period ({period:.6g}) in the "
                            f"{label} direction; a cogging map needs the whole period each way")
        bins //= 2


def bin_coefficients(x, r, sign, period, bins, harmonics):
    """Per direction (+, -), the sine and cosine coefficients of the bin means of r over one
    period (each divided by the bin's sinc attenuation); ``bins`` as ``filled_bins`` gives them,
    a bin a direction left unvisited interpolated from its neighbours."""
    idx = bin_index(x, period, bins)
    arg = np.outer(harmonics, (np.arange(bins) + 0.5) / bins * 2 * np.pi)
    sine, cosine = (2 / bins * w(arg) / np.sinc(harmonics / bins)[:, None] for w in (np.sin, np.cos))
    centre, out = np.arange(bins), []
    for d in (1, -1):
        rows = sign == d
        counts = np.bincount(idx[rows], minlength=bins)
        seen = counts > 0
        means = np.bincount(idx[rows], weights=r[rows], minlength=bins)[seen] / counts[seen]
        means = np.interp(centre, centre[seen], means, period=bins)
        out.append((sine @ means, cosine @ means))
    return out
