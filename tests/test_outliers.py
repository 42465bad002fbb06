"""The gross-outlier rule of fricgen.data.outliers at its threshold: OUTLIER_SIGMAS robust sd,
checked with residuals placed on either side of it, and through the default's confirmation
against [F1] fitted to every point."""
import numpy as np
import pytest

from fricgen.data.outliers import (gross_outliers, inner_points, robust_scale, running_median,
                                   unexplained)
from fricgen.fit import DefaultRegressor, StribeckRegressor
from fricgen.networks import StribeckCurve

X = np.linspace(0.0, 1.0, 201)
#: 1.4826: the robust sd of a residual whose median magnitude is 1.
MAD_SD = 1.4826


def test_robust_scale_is_1_4826_times_the_median_and_never_below_its_floor():
    r = np.array([0.0, 1.0, 2.0, 3.0, 100.0])
    assert robust_scale(r, np.full(5, 10.0)) == pytest.approx(1.4826 * 2.0, rel=1e-15)
    # a small positive median is the scale: the zeros count (not only the residuals beyond them)
    r = np.array([0.0, 0.1, 0.2, 0.3, 0.4])
    assert robust_scale(r, np.ones(5)) == pytest.approx(1.4826 * 0.2, rel=1e-15)
    assert robust_scale(np.zeros(5), np.full(5, 10.0)) == pytest.approx(1e-3 * 10.0)   # SCALE_FLOOR
    # mostly zero (a quantized force): the values' quantum, the median step between their
    # distinct values, whatever the few nonzero residuals are (a spike among them)
    values = np.array([1.0, 1.0, 1.05, 1.05, 1.1, 1.15, 51.1])
    for spike in (0.05, 50.0):
        r = np.array([0, 0, 0, 0, 0, 0.05, spike])
        assert robust_scale(r, values) == pytest.approx(1.4826 * 0.05, rel=1e-9)
    # and never below the floor: a quantum of 1e-9 next to values of 1
    assert robust_scale(np.zeros(4), np.array([1.0, 1.0 + 1e-9, 1.0, 1.0])) == pytest.approx(1e-3)


def test_running_median_and_inner_points_by_hand():
    x = np.array([3.0, 0.0, 1.0, 2.0, 4.0])
    t = np.array([30.0, 0.0, 100.0, 20.0, 40.0])          # in order of x: 0, 100, 20, 30, 40
    np.testing.assert_array_equal(running_median(x, t, 3), [30.0, 50.0, 20.0, 30.0, 35.0])
    np.testing.assert_array_equal(inner_points(x), [True, False, True, True, False])


def test_too_few_points_for_two_windows_have_no_outliers():
    """Below 2 windows of points (14) the running median is the ends' and nothing is flagged;
    from 14 on a spike is."""
    for n, flagged in ((2 * 7 - 1, []), (2 * 7, [6])):
        t = np.linspace(0.0, 1.0, n) + np.tile([0.0, 0.01, -0.01], 5)[:n]
        t[6] += 10.0
        assert np.flatnonzero(gross_outliers(np.arange(n), t)).tolist() == flagged


def _placed(kept_at=4.5, rejected_at=7.5, n=X.size):
    """Residuals 0, +1, -1, repeated (median magnitude 1: robust sd 1.4826; every running
    median of 7 over them is the middle 0), and two zeros replaced by ``kept_at`` and
    ``-rejected_at`` robust sd."""
    r = np.tile([0.0, 1.0, -1.0], n // 3 + 1)[:n]
    r[30], r[72] = kept_at * MAD_SD, -rejected_at * MAD_SD
    return r


def test_unexplained_confirms_a_suspect_only_beyond_outlier_sigmas():
    """6 robust sd (OUTLIER_SIGMAS): a suspect at 4.5 is explained and kept, one at 7.5 is not
    (a threshold of 3 would reject both, one of 9 neither); one at exactly 6 is not further
    than 6, and kept."""
    t = _placed()
    t[45] = 6 * MAD_SD
    suspects = np.zeros(t.size, dtype=bool)
    suspects[[30, 45, 72]] = True
    assert np.flatnonzero(unexplained(t, suspects, [np.zeros(t.size)])).tolist() == [72]
    # a suspect explained by any one of the models is kept
    assert not unexplained(t, suspects, [np.zeros(t.size), t]).any()


def test_gross_outliers_flag_only_beyond_outlier_sigmas_of_the_running_median():
    """The same residuals around a line: the running median follows the line, so the placed
    points' distances to it are 4.5 and 7.5 robust sd; only the second is flagged."""
    t = 100.0 + 0.01 * X + _placed()
    assert np.flatnonzero(gross_outliers(X, t)).tolist() == [72]
    assert np.flatnonzero(gross_outliers(X, t, 4.0)).tolist() == [30, 72]      # the rule's own knob


TRUTH = StribeckCurve("gauss", 0.4, np.array([0.3, 0.5]), np.array([0.05, 0.2]))
SD = 0.01


def _spiked(seed):
    """[F1] data with Gaussian noise of sd 0.01, and two points moved: by 4.5 sd (a rare
    but real measurement, kept) and by 12 sd (a spike)."""
    t = TRUTH(X) + SD * np.random.default_rng(seed).standard_normal(X.size)
    t[60] += 4.5 * SD
    t[140] += 12 * SD
    return t


def test_suspects_confirmed_against_eq1_are_the_spikes_on_every_seed():
    """The default's rule (running-median suspects confirmed against [F1] fitted to every
    point) on 3 noise draws: only the spike is rejected. The running median's robust sd is
    below the noise's (it follows each point a little), so 4.5 sd is often a suspect; [F1]
    explains it within 6 sd, never within 3."""
    for seed in range(3):
        t = _spiked(seed)
        fit = StribeckRegressor().fit(X, t)
        assert np.flatnonzero(unexplained(t, gross_outliers(X, t), [fit.predict(X)])).tolist() == [140]


@pytest.mark.slow
def test_the_default_regressor_rejects_the_spike_and_keeps_the_rare_point():
    for seed in range(3):
        est = DefaultRegressor().fit(X, _spiked(seed))
        assert np.flatnonzero(~est.inliers_).tolist() == [140]
