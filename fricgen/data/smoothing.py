"""The zero-phase Savitzky-Golay smoothing of a log (cubic, centred window) that gives v, dv/dt
and the force between which inverse dynamics [C1] holds, and the choice of its window.

``smooth`` is ``scipy.signal.savgol_filter`` in time linear in the log (by FFT from
FFT_WINDOW samples on); ``choose_window`` takes the window that minimizes the generalized
cross-validation score of the smoothed force plus the variance the velocity noise leaves in
m dv/dt (``VelocityNoise``: white on v, or on the position v was differentiated from);
``steady_rows`` the rows whose whole window moves one way; ``between_edges`` a position logged
in encoder counts as the line through its count edges, for its derivatives.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Callable, List, Optional

import numpy as np
from numpy.polynomial import Polynomial
from scipy.ndimage import maximum_filter1d, minimum_filter1d
from scipy.signal import oaconvolve, savgol_coeffs, savgol_filter

from .._progress import Progress

#: Degree of the Savitzky-Golay polynomial (cubic: its derivative equals the quadratic's).
POLYORDER = 3
#: Smallest window (samples) and the ratio of consecutive windows tried.
MIN_WINDOW, WINDOW_RATIO = 7, 1.25
#: The largest window, as a fraction of the log.
MAX_WINDOW_FRACTION = 0.05
#: The search stops at a window whose score exceeds the best so far by this factor: beyond the
#: optimum the smoothing's bias only grows, and the largest windows of a long log cost the most.
STOP_FACTOR = 2.0
#: Windows (samples) from which ``smooth`` convolves by FFT: the direct sum costs O(window)
#: per sample, the FFT O(log window).
FFT_WINDOW = 64


def between_edges(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """A position in encoder counts read between its count edges: each change of x placed half
    a sample before the row that first shows it, at the middle of the two levels, and x linear
    between those points (flat before the first and after the last). The staircase's steps,
    seen through a second derivative, are a noise that the sample rate aliases down to the
    frequencies of a slow move's ripple; the edges' times hold the motion to a fraction of a
    count. A position that changes at every row is only lightly smoothed, (x[k-1] + 2 x[k] +
    x[k+1]) / 4 (the midpoints lie on the motion)."""
    changed = np.flatnonzero(np.diff(x) != 0) + 1
    if changed.size < 2:
        return x
    edge_t = t[changed] - 0.5 * (t[changed] - t[changed - 1])
    return np.interp(t, edge_t, 0.5 * (x[changed] + x[changed - 1]))


@lru_cache(maxsize=256)
def _coeffs(window: int, deriv: int = 0, delta: float = 1.0) -> np.ndarray:
    """``savgol_coeffs`` of the cubic (read-only, computed once per window: O(window) each)."""
    c = savgol_coeffs(window, POLYORDER, deriv=deriv, delta=delta)
    c.flags.writeable = False
    return c


def centre_weight(window: int) -> float:
    """The weight of the centre sample in the smoothed value: the variance ratio of the filter."""
    return float(_coeffs(window)[window // 2])


def smooth(signal: np.ndarray, window: int, deriv: int = 0, delta: float = 1.0) -> np.ndarray:
    """``savgol_filter(signal, window, POLYORDER, deriv, delta)`` (mode 'interp'): the cubic
    Savitzky-Golay smoothing (``deriv`` 1: its derivative) of ``signal``. From ``FFT_WINDOW``
    samples on, the interior is convolved by overlap-add FFT (``scipy.signal.oaconvolve``,
    O(n log window) instead of O(n window)) and the ``window // 2`` samples at each end are the
    cubic fitted to the first and last ``window`` samples, as ``savgol_filter`` does: equal to
    it within rounding (about 1e-12 relative)."""
    if window < FFT_WINDOW:
        return savgol_filter(signal, window, POLYORDER, deriv=deriv, delta=delta)
    half = window // 2
    out = np.empty(signal.size)
    out[half:-half] = oaconvolve(signal, _coeffs(window, deriv, delta), mode="valid")
    k = np.arange(window, dtype=float)
    for ends, at in ((slice(None, window), slice(None, half)), (slice(-window, None), slice(-half, None))):
        cubic = Polynomial.fit(k, signal[ends], POLYORDER).deriv(deriv)
        out[at] = cubic(k[at]) / delta ** deriv
    return out


def steady_rows(v: np.ndarray, moving: np.ndarray, window: int) -> np.ndarray:
    """The ``moving`` rows whose whole centred window moves in one direction (no reversal and no
    row at rest within it); the half windows at the log's ends are left out."""
    direction = np.sign(v) * moving
    steady = (minimum_filter1d(direction, window) == maximum_filter1d(direction, window)) & moving
    steady[:window // 2] = steady[-(window // 2):] = False
    return steady


def gcv_score(signal: np.ndarray, window: int, rows: np.ndarray) -> float:
    """Generalized cross-validation of smoothing ``signal`` with ``window`` over ``rows``:
    mean (signal - smooth(signal))^2 / (1 - h0)^2, h0 the centre weight. It estimates the error
    of predicting a sample from its neighbours, noise and bias together."""
    residual = (signal - smooth(signal, window))[rows]
    return float(np.mean(residual ** 2)) / (1.0 - centre_weight(window)) ** 2


def derivative_noise(window: int, sample_time: float) -> float:
    """The standard deviation of the Savitzky-Golay derivative of unit white noise."""
    return float(np.linalg.norm(_coeffs(window, 1, sample_time)))


@lru_cache(maxsize=256)
def _differenced_norm(window: int, deriv: int, sample_time: float) -> float:
    """The standard deviation that unit white noise on a position leaves in the Savitzky-Golay
    smoothing (``deriv`` 1: derivative) of its central difference (``np.gradient``)."""
    difference = np.array([1.0, 0.0, -1.0]) / (2.0 * sample_time)
    return float(np.linalg.norm(np.convolve(_coeffs(window, deriv, sample_time), difference)))


@dataclass(frozen=True)
class VelocityNoise:
    """The noise on a log's velocity: white noise on v of standard deviation ``white``, and
    white noise of standard deviation ``position`` on the position v was differentiated from
    (an encoder count's rounding, q / sqrt(12)). The central difference makes the second blue:
    most of it lies at high frequencies, which the smoothing removes, so it weighs far less in
    a long window's v and dv/dt than white noise of its per-sample size would."""
    white: float
    position: float
    sample_time: float

    def per_sample(self) -> float:
        """The standard deviation of the noise on each sample of v."""
        return float(np.hypot(self.white, self.position / (np.sqrt(2.0) * self.sample_time)))

    def smoothed(self, window: int) -> float:
        """... left in v smoothed by ``window``."""
        return float(np.hypot(self.white * np.sqrt(centre_weight(window)),
                              self.position * _differenced_norm(window, 0, self.sample_time)))

    def derivative(self, window: int) -> float:
        """... left in dv/dt, the Savitzky-Golay derivative of ``window``."""
        return float(np.hypot(self.white * derivative_noise(window, self.sample_time),
                              self.position * _differenced_norm(window, 1, self.sample_time)))


def candidate_windows(n_rows: int) -> List[int]:
    """The odd windows ``choose_window`` scores for a log of ``n_rows``: from MIN_WINDOW up to
    MAX_WINDOW_FRACTION of the log, each about WINDOW_RATIO times the last."""
    largest = max(MIN_WINDOW, int(MAX_WINDOW_FRACTION * n_rows))
    windows, w = [], float(MIN_WINDOW)
    while int(w) | 1 <= largest:
        if not windows or int(w) | 1 != windows[-1]:
            windows.append(int(w) | 1)
        w *= WINDOW_RATIO
    return windows


def choose_window(force: np.ndarray, rows: np.ndarray, mass: float, noise: VelocityNoise,
                  progress: Optional[Callable[[str], None]] = None,
                  span: Optional[int] = None) -> int:
    """The odd window that minimizes the expected squared error of F = f - m a over ``rows``:
    the generalized cross-validation score of smoothing the force (its noise, and the bias where
    the Stribeck curve bends faster than the window) plus the variance m^2 var(a) that the
    velocity ``noise`` leaves in the derivative; from the smallest window up, until one scores
    STOP_FACTOR times the best. ``progress`` (a callable taking one line) hears
    how far the search is when it takes long (``fricgen._progress.Progress``). ``span``: the
    rows of a typical (the median) run of a log concatenated from runs (default: all rows),
    which bounds the windows (``candidate_windows``)."""
    windows = candidate_windows(rows.size if span is None else span)
    report = Progress(progress)
    scores = []
    for window in windows:
        scores.append(gcv_score(force, window, rows) + (mass * noise.derivative(window)) ** 2)
        report(f"smoothing window: scored {len(scores)} of {len(windows)} windows, up to {window} samples")
        if scores[-1] > STOP_FACTOR * min(scores):
            break
    return windows[int(np.argmin(scores))]
