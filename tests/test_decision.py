"""The calibrated decision of fricgen.diagnose.decision: the autocorrelation time against hand
values and the theory of AR(1), p-values uniform under the null (two-sided), and power."""
import numpy as np
import pytest
from scipy.signal import lfilter
from scipy.stats import kstest
from scipy.stats import t as student_t

from fricgen.diagnose.decision import autocorrelation_time, held_out_p_value


def test_autocorrelation_time_of_a_ramp_is_the_hand_computed_sum_of_pairs():
    """d = 1..8: x = d - 4.5, n var = 42; rho_1 = 26.25/42, rho_2 = 11.5/42, rho_3 = -1.25/42.
    Geyer's pairs (rho_0 + rho_1), (rho_2 + rho_3) are both positive:
    tau = -1 + 2 (1 + 26.25/42) + 2 (11.5 - 1.25)/42 = 2.25 + 20.5/42. For d = 1..4 (n var = 5,
    rho_1 = 1.25/5): tau = -1 + 2 (1 + 0.25) = 1.5."""
    assert autocorrelation_time(np.arange(1.0, 9.0)) == pytest.approx(2.25 + 20.5 / 42, rel=1e-12)
    assert autocorrelation_time(np.arange(1.0, 5.0)) == pytest.approx(1.5, rel=1e-12)
    # d = 1..6: n var = 17.5, rho_1 = 8.75/17.5 = 1/2, one pair: tau = -1 + 2 (1 + 1/2) = 2
    assert autocorrelation_time(np.arange(1.0, 7.0)) == pytest.approx(2.0, rel=1e-12)
    assert autocorrelation_time(np.ones(50)) == 1.0                   # no variance


@pytest.mark.parametrize("phi", [0.0, 0.5, 0.8])
def test_autocorrelation_time_of_ar1_is_one_plus_phi_over_one_minus_phi(phi):
    """x_t = phi x_(t-1) + e_t: tau = (1 + phi) / (1 - phi). The mean over 10 seeds of 4096
    samples; 0.08 relative is about 4 standard errors of that mean (sd 0.18 at tau = 3, 0.52
    at tau = 9 measured; at phi = 0 the estimate is biased up by about 0.05)."""
    taus = [autocorrelation_time(lfilter([1.0], [1.0, -phi], np.random.default_rng(s).standard_normal(4096)))
            for s in range(10)]
    assert np.mean(taus) == pytest.approx((1 + phi) / (1 - phi), rel=0.08)


def test_an_exact_residual_decides_without_noise():
    """No spread left (e = beta p exactly): p = 0 when the effect explains part of e (beta =
    1/2), p = 1 when it explains nothing (e = 0) or runs against it (beta = -1)."""
    p = np.sin(np.arange(100) / 7.0)
    assert held_out_p_value(0.5 * p, 0.5 * p - p)[0] == 0.0
    assert held_out_p_value(np.zeros(100), -p)[0] == 1.0
    assert held_out_p_value(-p, -2 * p)[0] == 1.0
    assert held_out_p_value(p, p)[0] == 1.0                         # no prediction at all


def test_p_values_of_tiny_samples_by_hand():
    """Below 4 samples tau = 1 and Student's t has n - 1 degrees of freedom, whose tails are
    closed forms. e = (1, 2, 3), p = (1, 0, 1): beta = 2, u = (-1, 0, 1), t = 2 * 2 / sqrt(2)
    = sqrt(8) with 2 dof: sf = (1 - t / sqrt(t^2 + 2)) / 2. e = (1, 2), p = (1, 1): beta = 3/2,
    u = (-1/2, 1/2), t = 3/2 * 2 / sqrt(1/2) = 3 sqrt(2) with 1 dof (Cauchy):
    sf = 1/2 - atan(t) / pi."""
    p, n_eff = held_out_p_value(np.array([1.0, 2.0, 3.0]), np.array([0.0, 2.0, 2.0]))
    assert (p, n_eff) == (pytest.approx(0.5 * (1 - np.sqrt(0.8)), rel=1e-12), 3.0)
    p, n_eff = held_out_p_value(np.array([1.0, 2.0]), np.array([0.0, 1.0]))
    assert (p, n_eff) == (pytest.approx(0.5 - np.arctan(3 * np.sqrt(2)) / np.pi, rel=1e-12), 2.0)


def test_autocorrelated_residuals_count_as_fewer_samples():
    """A short, smooth residual (tau > 1): the effective sample size is n / tau, below n, and
    the p-value is larger than the same statistic would give with n independent samples."""
    x = np.linspace(0.0, 1.0, 40)
    e = np.sin(3 * x) + 0.3 * x
    p = np.sin(3 * x)
    p_value, n_eff = held_out_p_value(e, e - p)
    beta = float(e @ p) / float(p @ p)
    tau = autocorrelation_time((e - beta * p) * p)
    assert tau > 1.5 and n_eff == pytest.approx(e.size / tau, rel=1e-12) and n_eff < e.size
    u = (e - beta * p) * p
    white = float(student_t.sf(beta * float(p @ p) / np.sqrt(float(u @ u)), e.size - 1))
    assert p_value > white


def _null_p_values(n_tests=400, seed=5):
    """p-values of predictions fitted to other noise, from white to strongly coloured."""
    rng = np.random.default_rng(seed)
    ps = []
    for k in range(n_tests):
        smooth = 1 + 10 * (k % 4)
        kernel = np.ones(smooth) / smooth
        e = np.convolve(rng.standard_normal(2000 + smooth), kernel, "valid")[:2000]
        pred = np.convolve(rng.standard_normal(2000 + smooth), kernel, "valid")[:2000] * 0.3
        ps.append(held_out_p_value(e, e - pred)[0])
    return np.array(ps)


def test_the_held_out_test_is_calibrated_on_noise_two_sided():
    """Uniform p-values, whatever the autocorrelation: neither too many false alarms nor too
    few (an over-conservative test fails too). KS at 1e-3, and each rate within 3 binomial sd
    of its level in both directions."""
    ps = _null_p_values()
    assert kstest(ps, "uniform").pvalue > 1e-3
    for alpha in (0.05, 0.1, 0.25, 0.5):
        assert abs(np.mean(ps < alpha) - alpha) <= 3 * np.sqrt(alpha * (1 - alpha) / ps.size)


def test_the_held_out_test_has_power_at_a_moderate_effect():
    """A sine of amplitude 0.15 sd in white noise (2000 samples): p < 0.01 in at least 18 of 20
    draws (20 of 20 measured; at 0.1 sd, 16 of 20)."""
    n = np.arange(2000)
    ps = []
    for s in range(20):
        e = np.random.default_rng(100 + s).standard_normal(n.size)
        ps.append(held_out_p_value(e + 0.15 * np.sin(n / 50.0 + s), e)[0])
    assert np.sum(np.array(ps) < 0.01) >= 18
