"""The encoder's aliases in a cogging calibration: a drive reading its position in counts
sees the count's sawtooth error at the count rate; at a steady speed the loop's response is a
ripple periodic in position, folded by the log's (and the loop's) sample rate to wavenumbers
that pass for cogging (``fit.cogging`` leaves them out of its screen)."""
from __future__ import annotations

from typing import Optional

import numpy as np

#: The multiples of the encoder's count rate whose aliases by the sample rate are no position
#: force (``aliased``: the count's sawtooth error is strongest at its first few), and the
#: relative precision of the mean speed that places them.
ENCODER_ALIASES = 4
SPEED_PRECISION = 1e-4
#: The multiples of a cogging harmonic whose sidebands of an encoder alias are aliases too.
SIDEBANDS = (1, 2)


def aliased(wavenumber, quantum: float, pace: Optional[float], ts: float, spacing: float,
             carriers=()) -> np.ndarray:
    """Which ``wavenumber``s (rad per unit of x) lie within ``spacing`` (and the speed's
    precision) of an alias of the encoder at the steady speed ``pace`` (None: no steady speed,
    none): a drive sampling its position every ts sees the count's sawtooth error at k pace /
    quantum per s, folded by the sample rate to |k f_c - n f_s|; at a constant speed its loop's
    response is a ripple periodic in position, of wavenumber 2 pi |k / quantum - n / (pace ts)|
    (a 12-bit linear motor without cogging, its loop at 8 kHz, had a map of harmonics 192 and 384
    of 32 mm at 32 mm/s: 2 and 4 counts a sample less 1 and 2 samples). The cogging's speed
    ripple modulates that ripple: its sidebands, the alias -+ 1 and 2 times each of the
    ``carriers`` (wavenumbers), are aliases too (a 12-bit calibration logged at 2 kHz at 3 rad/s
    had a map of harmonics 147 and 387 of a turn, 240 and 480 less the alias 93, 52 % off)."""
    w = np.asarray(wavenumber, dtype=float)
    if quantum <= 0 or pace is None:
        return np.zeros(w.shape, dtype=bool)
    count = 2 * np.pi * np.arange(1, ENCODER_ALIASES + 1) / quantum
    sample = 2 * np.pi / (pace * ts)
    n = np.round(count / sample)
    alias = np.abs(count - n * sample)
    tolerance = spacing + SPEED_PRECISION * n * sample         # the count's wavenumber is exact
    # an alias whose band reaches 0 is the error sampled at nearly one phase: no ripple, and the
    # cogging's first harmonics are there (1 um at 20 mm/s and 8 kHz had lost them all)
    line = alias > 2 * tolerance
    shift = np.concatenate([[0.0], np.outer(np.asarray(carriers, dtype=float), SIDEBANDS).ravel()])
    shift = np.concatenate([shift, -shift[1:]])
    alias = np.abs(alias[line][:, None] + shift).ravel()
    tolerance = np.repeat(tolerance[line], shift.size)
    return np.any(np.abs(w[..., None] - alias) <= tolerance, axis=-1)


def count_alias(period: float, quantum: float, pace: Optional[float], ts: float,
                highest: int) -> Optional[int]:
    """The harmonic of ``period`` at which a log every ``ts`` folds the encoder's count rate
    (pace / quantum counts per s) where that rate exceeds half the log's, if within ``highest``;
    else None. The drive's ripple at the count rate, folded there, is modulated by the cogging's
    speed ripple: its lines at the alias -+ the cogging's harmonics pass for cogging beyond
    those ``aliased`` takes out (a 12-bit axis at 3 rad/s logged at 2 kHz: the count rate 1956
    Hz folded to harmonic 93, maps up to 130 % off)."""
    if quantum <= 0 or pace is None or pace / quantum <= 0.5 / ts:
        return None
    rate = pace / quantum
    folded = abs(rate - round(rate * ts) / ts) * period / pace
    return int(round(folded)) if 1 <= round(folded) <= highest else None
