"""The calibrated decision: does a fitted effect reduce the residual on data it was not fitted to?

On the held-out rows, each row's loss difference d = e_before^2 - e_after^2 (force residual
without and with the effect, both fitted on the first part of the log only) has mean <= 0 when
the effect explains nothing (a fit to noise only adds error out of sample). The one-sided test
of mean(d) > 0 uses Student's t with the effective sample size n / tau, tau = 1 + 2 sum rho_k
the integrated autocorrelation time of d (Geyer's initial positive sequence). So the false-alarm
rate of one test is at most the level whatever the sample rate, length, smoothing or noise
colour: they change tau, not the calibration.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.stats import t as student_t


def autocorrelation_time(d: np.ndarray) -> float:
    """tau = 1 + 2 sum_k rho_k, summed over Geyer's initial positive sequence of pairs."""
    n = d.size
    x = d - d.mean()
    var = float(np.dot(x, x)) / n
    if n < 4 or var <= 0:
        return 1.0
    size = 1 << (2 * n - 1).bit_length()
    f = np.fft.rfft(x, size)
    acf = np.fft.irfft(f * np.conj(f), size)[: n // 2] / (n * var)
    tau = -1.0                        # 2 (rho_0 + rho_1) - 1 + ... with rho_0 = 1
    for k in range(0, acf.size - 1, 2):
        pair = acf[k] + acf[k + 1]
        if pair <= 0:
            break
        tau += 2.0 * pair
    return float(min(max(tau, 1.0), n / 2.0))


def held_out_p_value(before: np.ndarray, after: np.ndarray):
    """One-sided p-value of "the effect reduces the squared held-out residual", and the
    effective sample size it used. ``before``/``after``: the residuals at the held-out rows."""
    d = np.asarray(before, float) ** 2 - np.asarray(after, float) ** 2
    n_eff = d.size / autocorrelation_time(d)
    sd = float(np.std(d))
    mean = float(np.mean(d))
    if sd == 0.0:
        return (0.0 if mean > 0 else 1.0), n_eff
    stat = mean / (sd / math.sqrt(n_eff))
    return float(student_t.sf(stat, max(n_eff - 1.0, 1.0))), n_eff
