"""The calibrated decision: does a fitted effect explain the residual on data it was not fitted to?

On the held-out rows, the residual without the effect ``e`` is regressed on the effect's
prediction ``p`` (both fitted on the first part of the log only): e = beta p + eps. When the
effect explains nothing, ``p`` is a fit to other data's noise, independent of ``e``, and
beta = 0. The one-sided test of beta > 0 uses the standard error of sum(eps p) with the
integrated autocorrelation time tau = 1 + 2 sum rho_k of eps p (Geyer's initial positive
sequence) and Student's t with n / tau - 1 degrees of freedom. So the false-alarm rate of one
test is the level whatever the sample rate, length, smoothing, noise colour or trajectory: they
change tau, not the calibration. Under an effect, eps is what stays unexplained, so the test's
power grows with the effect's size instead of being limited by how the effect varies.
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
    """One-sided p-value of "the effect explains the held-out residual" (beta > 0 above), and
    the effective sample size it used. ``before``/``after``: the residuals without and with
    the effect at the held-out rows."""
    e = np.asarray(before, float)
    p = e - np.asarray(after, float)
    pp = float(np.dot(p, p))
    if pp == 0.0:
        return 1.0, float(e.size)
    beta = float(np.dot(e, p)) / pp
    u = (e - beta * p) * p
    tau = autocorrelation_time(u)
    n_eff = e.size / tau
    var = float(np.dot(u, u)) * tau
    if var == 0.0:
        return (0.0 if beta > 0 else 1.0), n_eff
    stat = beta * pp / math.sqrt(var)
    return float(student_t.sf(stat, max(n_eff - 1.0, 1.0))), n_eff


def p_value_text(p: float) -> str:
    """A p-value as text: two digits, or '< 1e-300' where it underflows to 0."""
    return f"{p:.2g}" if p > 0 else "< 1e-300"


def p_text(p: float) -> str:
    """'p = 0.0012', or 'p < 1e-300' where the p-value underflows to 0."""
    return f"p {'= ' if p > 0 else ''}{p_value_text(p)}"
